#!/usr/bin/python3
# Copied from the shared timing rig ../shared/tools/lcnc-master/analyze.py; the
# metrics are unchanged, added: --stream (the recording of play-stream.sh).
"""Analyse the halsampler recording of one rig run.

usage: analyze.py [--stream] RAW PERIOD_S CSV [POS_SCALE [JERK_LIMIT]]

RAW columns (halsampler -t): sample# inpos hold line mtype x y z cur_vel req_vel dtg
(x,y,z multiplied by 1/POS_SCALE in rig.hal; POS_SCALE=0.001 -> recorded in um).
With --stream (stream.hal of play-stream.sh):
  sample# stream_on fifo_empty fifo_depth underruns x y z
  stops are then counted from the sampled speed (there is no motion.current-vel),
  the CSV has the streamer columns and "line" (index of the stream line the
  streamer put out in that cycle, -1 in cycles without one), and two keys
  are added: played (cycles in which the streamer put out a line) and
  underruns (cycles with the stream switched on in which the FIFO was empty,
  before the last line played: the stream was not played as written).

Execution time = number of servo cycles from the first cycle in which the
commanded XYZ position changes to the last such cycle (inclusive).

Kinematics from finite differences of the commanded XYZ positions p_k (mm) at
the servo period T (the whole motion window plus the resting samples around it):
  v_k+1/2 = (p_k+1 - p_k)/T
  a_k     = (p_k+1 - 2 p_k + p_k-1)/T^2              (3D vector)
  j_k+1/2 = (a_k+1 - a_k)/T                          (3D vector)
  acc  = max |a_k|;  acc_t = max |a_k . u_k| with u_k = (p_k+1 - p_k-1)/|..|
  (tangential part), acc_n = max normal part sqrt(|a|^2 - a_t^2)
  jerk = max |j|;  jerk_p99 = 99th percentile of |j| over the moving samples
  acc_axis / jerk_axis / jerk5_axis: largest single-axis component (LinuxCNC
  limits are per axis; the 3D magnitude can be up to sqrt(3) times larger)
  acc5 / jerk5: same peaks after a centred 5-sample (5 ms) box average of the
  a and j vectors (jerk5 = |a_k+3 - a_k-2|/(5T)), i.e. a single-sample spike of
  height J shows as J/5.
  jerk_over_ms: number of 1 ms samples with |j| > 1.05*JERK_LIMIT (3D magnitude);
  jerk5_over_ms: same for the 5 ms box-averaged jerk.
Prints one line of key=value.
"""
import sys

import numpy as np


def box5(x):
    k = np.ones(5) / 5.0
    return np.stack([np.convolve(x[:, c], k, mode="same") for c in range(x.shape[1])], axis=1)


def main():
    args = sys.argv[1:]
    stream = bool(args) and args[0] == "--stream"
    if stream:
        args = args[1:]
    raw, period, csv = args[0], float(args[1]), args[2]
    pscale = float(args[3]) if len(args) > 3 else 1.0
    jlim = float(args[4]) if len(args) > 4 else float("inf")
    rows, overrun_lines = [], 0
    with open(raw) as f:
        for ln in f:
            p = ln.split()
            if not p:
                continue
            if p[0] == "overrun":
                overrun_lines += 1
                continue
            rows.append([float(v) for v in p])
    if not rows:
        print("cycles=NA seconds=NA status=no_samples")
        return 2
    a = np.array(rows)
    gaps = int(np.sum(np.diff(a[:, 0]) != 1))
    pos = a[:, 5:8] * pscale
    d = np.diff(pos, axis=0)
    moved = np.any(np.abs(d) > 1e-9, axis=1)          # moved between sample i and i+1
    if not moved.any():
        print("cycles=0 seconds=0 status=no_motion samples=%d" % len(a))
        return 1
    i0 = int(np.argmax(moved)) + 1                      # first sample that differs
    i1 = len(moved) - int(np.argmax(moved[::-1]))       # last sample that differs
    cycles = i1 - i0 + 1
    lo, hi = max(i0 - 1 - 4, 0), min(i1 + 4, len(a) - 1)   # include resting samples
    P = pos[lo:hi + 1]
    T = period
    v = np.diff(P, axis=0) / T                          # v[k] = v_{k+1/2}
    acc = np.zeros_like(P); acc[1:-1] = (P[2:] - 2 * P[1:-1] + P[:-2]) / T ** 2
    jrk = np.zeros_like(P); jrk[:-1] = np.diff(acc, axis=0) / T   # j[k] = j_{k+1/2}
    jrk[-2:] = 0; jrk[0] = 0
    u = np.zeros_like(P); c = P[2:] - P[:-2]
    n = np.linalg.norm(c, axis=1)
    ok = n > 1e-12
    u[1:-1][ok] = c[ok] / n[ok, None]
    am = np.linalg.norm(acc, axis=1)
    at = np.abs((acc * u).sum(1))
    an = np.sqrt(np.maximum(am ** 2 - at ** 2, 0))
    jm = np.linalg.norm(jrk, axis=1)
    a5 = np.linalg.norm(box5(acc), axis=1)
    j5 = np.linalg.norm(box5(jrk), axis=1)
    speed = np.linalg.norm(v, axis=1)
    mov = jm[speed.nonzero()[0]] if speed.any() else jm
    length = float(np.linalg.norm(np.diff(pos[i0 - 1:i1 + 1], axis=0), axis=1).sum())
    if stream:
        # streamer bookkeeping: a cycle with the stream on either put out a line
        # (underruns unchanged) or found the FIFO empty (underruns + 1)
        on = a[:, 1] > 0.5
        du = np.diff(a[:, 4], prepend=a[0, 4])
        played = on & (du == 0)
        line = np.where(played, np.cumsum(played) - 1, -1)
        n_played = int(played.sum())
        last = int(np.nonzero(played)[0][-1]) if n_played else -1
        n_under = int((on[:last + 1] & (du[:last + 1] > 0)).sum()) if n_played else -1
        cv = np.concatenate([[0.0], np.linalg.norm(d, axis=1) / period])[i0:i1 + 1]
    else:
        cv = a[i0:i1 + 1, 8]
    zero = cv[1:-1] <= 1e-6
    stops = int(np.sum(zero[1:] & ~zero[:-1]) + (1 if len(zero) and zero[0] else 0))
    print("cycles=%d seconds=%.3f max_vel=%.2f acc=%.0f acc_t=%.0f acc_n=%.0f jerk=%.0f "
          "jerk_p99=%.0f acc5=%.0f jerk5=%.0f acc_axis=%.0f jerk_axis=%.0f jerk5_axis=%.0f "
          "jerk_over_ms=%d jerk5_over_ms=%d path_len=%.3f stops=%d start=%s end=%s samples=%d gaps=%d overruns=%d"
          % (cycles, cycles * period, speed.max(), am.max(), at.max(), an.max(), jm.max(),
             np.percentile(mov, 99), a5.max(), j5.max(), np.abs(acc).max(), np.abs(jrk).max(),
             np.abs(box5(jrk)).max(), int((jm > 1.05 * jlim).sum()), int((j5 > 1.05 * jlim).sum()),
             length, stops,
             ",".join("%.4f" % x for x in pos[i0 - 1]), ",".join("%.4f" % x for x in pos[i1]),
             len(a), gaps, overrun_lines), end="")
    print(" underruns=%d played=%d" % (n_under, n_played) if stream else "")
    spd = np.concatenate([[0.0], speed])
    if stream:
        with open(csv, "w") as f:
            f.write("cycle,t,x,y,z,speed,acc,acc_t,jerk,acc5,jerk5,stream_on,fifo_empty,fifo_depth,underruns,line\n")
            for k in range(len(P)):
                r = a[lo + k]
                f.write("%d,%.6f,%.9f,%.9f,%.9f,%.4f,%.2f,%.2f,%.1f,%.2f,%.1f,%d,%d,%d,%d,%d\n" % (
                    k, (lo + k - (i0 - 1)) * T, P[k, 0], P[k, 1], P[k, 2], spd[k], am[k], at[k], jm[k],
                    a5[k], j5[k], r[1], r[2], r[3], r[4], line[lo + k]))
        return 0
    with open(csv, "w") as f:
        f.write("cycle,t,x,y,z,speed,acc,acc_t,jerk,acc5,jerk5,cur_vel,req_vel,dist_to_go,line,motion_type,in_pos,hold\n")
        for k in range(len(P)):
            r = a[lo + k]
            f.write("%d,%.6f,%.9f,%.9f,%.9f,%.4f,%.2f,%.2f,%.1f,%.2f,%.1f,%.6f,%.6f,%.6f,%d,%d,%d,%d\n" % (
                k, (lo + k - (i0 - 1)) * T, P[k, 0], P[k, 1], P[k, 2], spd[k], am[k], at[k], jm[k],
                a5[k], j5[k], r[8], r[9], r[10], r[3], r[4], r[1], r[2]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
