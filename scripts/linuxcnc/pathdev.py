#!/usr/bin/python3
# Copied unchanged from the shared timing rig ../shared/tools/lcnc-master/pathdev.py
# (so that the project's LinuxCNC scripts stand on their own).
"""Deviation of a recorded run from a reference polyline.

usage: pathdev.py REF.csv RUN.csv
REF.csv: x,y,z[,line] vertices in mm (prep.py writes it: start point + feed-move
end points). RUN.csv: window CSV from analyze.py (x,y,z in mm).
Prints max / rms distance (mm) of every sampled position from the polyline
(exact point-to-segment distance; the nearest segment is searched in a window
around the previous sample's segment and globally whenever that is > 1 um).
"""
import sys

import numpy as np


def seg_dist(q, A, AB, L2):
    t = np.clip(((q - A) * AB).sum(-1) / L2, 0, 1)
    return np.linalg.norm(q - (A + t[..., None] * AB), axis=-1)


def main():
    R = np.genfromtxt(sys.argv[1], delimiter=",", names=True)
    P = np.stack([R["x"], R["y"], R["z"]], axis=1).reshape(-1, 3)
    d = np.genfromtxt(sys.argv[2], delimiter=",", names=True)
    Q = np.stack([d["x"], d["y"], d["z"]], axis=1)
    if len(P) == 1:
        P = np.vstack([P, P])
    A, B = P[:-1], P[1:]
    AB = B - A
    L2 = np.maximum((AB ** 2).sum(1), 1e-30)
    n = len(A)
    best = np.empty(len(Q))
    ptr, W = 0, 64
    for i, q in enumerate(Q):
        lo, hi = max(ptr - W, 0), min(ptr + W, n)
        dd = seg_dist(q, A[lo:hi], AB[lo:hi], L2[lo:hi])
        k = int(np.argmin(dd))
        if dd[k] > 1e-3:                  # maybe lost: search all segments
            da = seg_dist(q, A, AB, L2)
            kk = int(np.argmin(da))
            if da[kk] < dd[k]:
                best[i], ptr = da[kk], kk
                continue
        best[i], ptr = dd[k], lo + k
    print("max_dev=%.5f rms_dev=%.5f" % (best.max(), np.sqrt((best ** 2).mean())))


if __name__ == "__main__":
    main()
