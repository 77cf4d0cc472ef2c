#!/usr/bin/python3
# Copied from the shared timing rig ../shared/tools/lcnc-master/rig_display.py
# (unchanged apart from this note): the DISPLAY program of run-program.sh.
"""Headless "DISPLAY" program for the LinuxCNC timing rig.

Started by the linuxcnc script as:  rig_display.py -ini <rig.ini>
It resets estop, turns the machine on, homes all joints (HOME_SEARCH_VEL=0 ->
immediate homing), switches to AUTO, opens [RIG]PROGRAM, starts halsampler
(per-servo-cycle recorder) and runs the program.  With [RIG]PREFILL=1 the
motion feed-inhibit pin is held TRUE until task has queued the whole program
(or the motion queue is full / queueing stalls), so the planner sees the same
look-ahead on every run (deterministic cycle counts).  When the program is
finished it stops the recorder and exits; the linuxcnc script then shuts
everything down (its own Cleanup).  A JSON status file is written.
"""
import json
import os
import subprocess
import sys
import time

import linuxcnc

t_start = time.time()
status = {"ok": False, "errors": [], "messages": [], "phase": "start"}


def halcmd(*args):
    return subprocess.run(["halcmd"] + list(args), check=True,
                          capture_output=True, text=True).stdout.strip()


def main():
    ini_path = sys.argv[sys.argv.index("-ini") + 1]
    ini = linuxcnc.ini(ini_path)
    prog = ini.find("RIG", "PROGRAM")
    raw_path = ini.find("RIG", "RAW")
    status_path = ini.find("RIG", "STATUS")
    prefill = int(ini.find("RIG", "PREFILL") or "1")
    timeout = float(ini.find("RIG", "TIMEOUT") or "300")
    with open(os.path.join(os.path.dirname(status_path), "display.pid"), "w") as f:
        f.write(str(os.getpid()))

    def save():
        status["wall_s"] = round(time.time() - t_start, 3)
        with open(status_path, "w") as f:
            json.dump(status, f, indent=1)

    s = linuxcnc.stat()
    c = linuxcnc.command()
    e = linuxcnc.error_channel()

    def drain_errors():
        while True:
            m = e.poll()
            if not m:
                break
            kind, text = m
            if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
                status["errors"].append(text)
            else:
                status["messages"].append(text)

    def wait(cond, tmo, what):
        t0 = time.time()
        while True:
            s.poll()
            drain_errors()
            if cond():
                return
            if time.time() - t0 > tmo:
                raise RuntimeError("timeout waiting for " + what)
            time.sleep(0.005)

    sampler = None
    try:
        # task may need a moment before NML status is available
        for _ in range(300):
            try:
                s.poll()
                break
            except linuxcnc.error:
                time.sleep(0.1)
        status["phase"] = "machine-on"
        c.state(linuxcnc.STATE_ESTOP_RESET); c.wait_complete(5)
        c.state(linuxcnc.STATE_ON); c.wait_complete(5)
        wait(lambda: s.task_state == linuxcnc.STATE_ON, 10, "machine on")

        status["phase"] = "homing"
        c.mode(linuxcnc.MODE_MANUAL); c.wait_complete(5)
        c.teleop_enable(0); c.wait_complete(5)
        c.home(-1); c.wait_complete(5)
        wait(lambda: all(s.homed[j] for j in range(s.joints)), 20, "homing")

        status["phase"] = "open"
        c.mode(linuxcnc.MODE_AUTO); c.wait_complete(5)
        wait(lambda: s.task_mode == linuxcnc.MODE_AUTO, 10, "auto mode")
        c.program_open(prog); c.wait_complete(5)
        drain_errors()

        # start the per-cycle recorder (halsampler copies the sampler FIFO to a file)
        status["phase"] = "record"
        rawf = open(raw_path, "w")
        sampler = subprocess.Popen(["halsampler", "-t"], stdout=rawf,
                                   stderr=subprocess.DEVNULL)
        time.sleep(0.2)
        if prefill:
            halcmd("sets", "rig-hold", "1")
        halcmd("sets", "rig-rec", "1")
        time.sleep(0.02)

        status["phase"] = "run"
        t_run = time.time()
        c.auto(linuxcnc.AUTO_RUN, 0)
        if prefill:
            # wait until task has pushed everything it can into the motion queue
            last_q, t_last = -1, time.time()
            while True:
                s.poll(); drain_errors()
                if status["errors"]:
                    break
                if s.queue != last_q:
                    last_q, t_last = s.queue, time.time()
                stable = time.time() - t_last
                if s.queue_full:
                    status["prefill_end"] = "queue_full"; break
                if s.interp_state in (linuxcnc.INTERP_WAITING, linuxcnc.INTERP_IDLE) and stable > 0.3:
                    status["prefill_end"] = "program_queued"; break
                if stable > 2.0:
                    status["prefill_end"] = "stalled(sync command?)"; break
                time.sleep(0.01)
            status["prefill_queue"] = s.queue
            halcmd("sets", "rig-hold", "0")

        # wait for the end of the program
        time.sleep(0.05)
        while True:
            s.poll(); drain_errors()
            if status["errors"]:
                c.abort(); raise RuntimeError("LinuxCNC error: " + " | ".join(status["errors"]))
            if (s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0
                    and s.inpos and s.exec_state == linuxcnc.EXEC_DONE):
                break
            if time.time() - t_run > timeout:
                c.abort(); raise RuntimeError("program timeout (%gs)" % timeout)
            time.sleep(0.01)
        status["run_wall_s"] = round(time.time() - t_run, 3)

        status["phase"] = "stop-record"
        time.sleep(0.1)                     # record some idle cycles after the end
        halcmd("sets", "rig-rec", "0")
        for _ in range(500):               # let halsampler drain the FIFO
            if int(halcmd("getp", "sampler.0.curr-depth")) == 0:
                break
            time.sleep(0.01)
        time.sleep(0.2)
        status["sampler_overruns"] = int(halcmd("getp", "sampler.0.overruns"))
        status["phase"] = "done"
        status["ok"] = True
    except Exception as ex:  # noqa
        status["errors"].append("%s: %s" % (type(ex).__name__, ex))
    finally:
        if sampler is not None:
            sampler.terminate()            # our own child, by PID
            try:
                sampler.wait(5)
            except subprocess.TimeoutExpired:
                sampler.kill(); sampler.wait()
        try:
            c.state(linuxcnc.STATE_ESTOP); c.wait_complete(2)
        except Exception:
            pass
        save()


if __name__ == "__main__":
    main()
