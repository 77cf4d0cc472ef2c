#!/usr/bin/python3
# Adapted from the shared timing rig ../shared/tools/lcnc-master/rig_display.py
# (here: program_display.py): the machine handling is the same, the program run
# is replaced by playing a stream through halstreamer.
"""Headless "DISPLAY" program of play-stream.sh.

Started by the linuxcnc script as:  play_display.py -ini <stream.ini>
  1. estop reset, machine on, home (HOME_SEARCH_VEL=0 -> immediate homing at
     JOINT HOME = the stream's first line), then MDI G53 G0 out by 1 mm and
     back, so that motion is exactly at the first line (homing ends only near it);
  2. prefill: halstreamer copies the stream file into the streamer FIFO while
     the streamer is disabled, until the FIFO holds the whole file or is full
     (DEPTH-1 lines; halstreamer then blocks and keeps feeding while the
     stream plays);
  3. start halsampler and the recording, then switch stream-on (muxes to the
     stream + streamer enable, in the same servo cycle: see stream.hal);
  4. wait until halstreamer has read the whole file and the FIFO is empty,
     plus a few cycles; stop the recording, switch back to motion, exit.
A JSON status file is written ([STREAM]STATUS); the linuxcnc script then shuts
everything down (its own Cleanup).
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


def getp(name):
    return int(halcmd("getp", name))


def main():
    ini_path = sys.argv[sys.argv.index("-ini") + 1]
    ini = linuxcnc.ini(ini_path)
    stream_path = ini.find("STREAM", "FILE")
    lines = int(ini.find("STREAM", "LINES"))
    depth = int(ini.find("STREAM", "DEPTH"))
    raw_path = ini.find("STREAM", "RAW")
    status_path = ini.find("STREAM", "STATUS")
    timeout = float(ini.find("STREAM", "TIMEOUT") or "300")
    run_dir = os.path.dirname(status_path)
    with open(os.path.join(run_dir, "display.pid"), "w") as f:
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

    sampler = streamer = None
    streamer_err = os.path.join(run_dir, "halstreamer.err")
    try:
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
        time.sleep(0.05)
        drain_errors()
        if status["errors"]:
            raise RuntimeError("LinuxCNC error: " + " | ".join(status["errors"]))

        # Homing (HOME_SEARCH_VEL 0) declares the position 0 as HOME_OFFSET (0) and
        # then moves to HOME with the free planner, which stops within
        # ~1e-3*A*T^2 of it (2.6e-7 mm seen): not exactly at the stream's first
        # line. Go there with the coordinated planner, which ends a move on its
        # end point: out by 1 mm and back (a move shorter than its fuzz would be
        # dropped).
        status["phase"] = "go-to-start"
        home = [ini.find("JOINT_%d" % j, "HOME") for j in range(3)]
        away = ["%.9f" % (float(h) + 1.0) for h in home]
        c.mode(linuxcnc.MODE_MDI); c.wait_complete(5)
        wait(lambda: s.task_mode == linuxcnc.MODE_MDI, 10, "MDI mode")
        for target in (away, home):
            c.mdi("G21 G90 G53 G0 X%s Y%s Z%s" % tuple(target)); c.wait_complete(5)
            time.sleep(0.05)
            wait(lambda: s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0
                 and s.inpos and s.exec_state == linuxcnc.EXEC_DONE, 20, "move to the start")
        time.sleep(0.05)
        err = max(abs(float(halcmd("getp", "joint.%d.motor-pos-cmd" % j)) - float(home[j]))
                  for j in range(3))
        status["start_error_mm"] = err
        if err > 1e-6:
            raise RuntimeError("motion is %.3g mm from the stream's first line" % err)
        c.mode(linuxcnc.MODE_MANUAL); c.wait_complete(5)

        # prefill: streamer disabled (stream-on FALSE), halstreamer fills the FIFO
        status["phase"] = "prefill"
        target = min(lines, depth - 1)       # the ring buffer holds DEPTH-1 lines
        with open(stream_path) as fin, open(streamer_err, "w") as ferr:
            streamer = subprocess.Popen(["halstreamer"], stdin=fin, stderr=ferr)
        t0, last, t_last = time.time(), -1, time.time()
        while True:
            d = getp("streamer.0.curr-depth")
            if d != last:
                last, t_last = d, time.time()
            if d >= target:
                break
            if streamer.poll() is not None and time.time() - t_last > 0.2:
                raise RuntimeError("halstreamer ended (status %s) with %d of %d lines in the FIFO: %s"
                                   % (streamer.returncode, d, lines, open(streamer_err).read().strip()[:300]))
            if time.time() - t0 > 120:
                raise RuntimeError("prefill timeout: %d of %d lines in the FIFO" % (d, target))
            time.sleep(0.005)
        status["prefill_depth"] = last
        status["prefill_s"] = round(time.time() - t0, 3)

        # recorder on, then the stream on
        status["phase"] = "record"
        rawf = open(raw_path, "w")
        sampler = subprocess.Popen(["halsampler", "-t"], stdout=rawf,
                                   stderr=subprocess.DEVNULL)
        time.sleep(0.2)
        halcmd("sets", "stream-rec", "1")
        time.sleep(0.02)

        status["phase"] = "play"
        t_run = time.time()
        halcmd("sets", "stream-on", "1")
        # wait until halstreamer has read the whole file and the FIFO is empty
        while True:
            drain_errors()
            if status["errors"]:
                raise RuntimeError("LinuxCNC error: " + " | ".join(status["errors"]))
            if streamer.poll() is not None and getp("streamer.0.curr-depth") == 0:
                break
            if time.time() - t_run > timeout:
                raise RuntimeError("stream timeout (%gs)" % timeout)
            time.sleep(0.01)
        status["play_wall_s"] = round(time.time() - t_run, 3)
        status["halstreamer_rc"] = streamer.returncode
        err = open(streamer_err).read().strip()
        if streamer.returncode != 0 or err:
            status["errors"].append("halstreamer (status %d): %s" % (streamer.returncode, err[:300]))

        status["phase"] = "stop-record"
        time.sleep(0.05)                    # record some resting cycles after the end
        halcmd("sets", "stream-rec", "0")
        # back to motion (the stream's last position is not motion's: no drive
        # is connected here; on a machine motion would first go there)
        halcmd("sets", "stream-on", "0")
        # underruns counts every enabled cycle with an empty FIFO, so it also
        # counts the cycles after the last line; analyze.py --stream counts
        # those before the last line from the recording
        status["underruns_total"] = getp("streamer.0.underruns")
        for _ in range(500):                # let halsampler drain the FIFO
            if getp("sampler.0.curr-depth") == 0:
                break
            time.sleep(0.01)
        time.sleep(0.2)
        status["sampler_overruns"] = getp("sampler.0.overruns")
        drain_errors()
        if status["errors"]:
            raise RuntimeError("errors reported")
        status["phase"] = "done"
        status["ok"] = True
    except Exception as ex:  # noqa
        status["errors"].append("%s: %s" % (type(ex).__name__, ex))
    finally:
        for p in (streamer, sampler):       # our own children, by PID
            if p is None or p.poll() is not None:
                continue
            p.terminate()
            try:
                p.wait(5)
            except subprocess.TimeoutExpired:
                p.kill(); p.wait()
        try:
            c.state(linuxcnc.STATE_ESTOP); c.wait_complete(2)
        except Exception:
            pass
        save()


if __name__ == "__main__":
    main()
