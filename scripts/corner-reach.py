#!/usr/bin/env python3
"""How far a written program passes from each vertex of the original.

The tolerance bounds one way: every point of the written feed path within
the tolerance of the original. This measures the other way at the
vertices: for each feed vertex of ORIGINAL (the end of a feed move that a
feed move follows), the distance to the written feed path of WRITTEN,
densified at 2 um (write it as G1 with a fine chord for a bound of 1 um:
`fairpath smooth P -t 0.05mm -f g1 --chord 0.001mm`). A corner
transition passes within sqrt(2) tolerances of its corner
(`fairpath::budget::CORNER_REACH_SHARE`).

  scripts/corner-reach.py ORIGINAL WRITTEN [TOLERANCE_MM]

Prints the vertex count, the largest distance, how many vertices lie
beyond 1.02 and 2 tolerances, and the farthest vertex. G20 programs are
read in inches and reported in mm; arcs count by their end points only.
Needs numpy and scipy (`pip install numpy scipy`).
"""

import math
import re
import sys

import numpy as np
from scipy.spatial import cKDTree


def moves(path):
    """(start, end, rapid) of every move, in mm."""
    x = y = z = 0.0
    out, mode, scale = [], None, 1.0
    for line in open(path, errors="replace"):
        code = re.sub(r"\(.*?\)|;.*", "", line).upper()
        if re.search(r"G20\b", code):
            scale = 25.4
        g = re.findall(r"G0*([0-3])(?![\d.])", code)
        if g:
            mode = g[-1]
        m = {k: float(v) for k, v in re.findall(r"([XYZ])\s*(-?[\d.]+)", code)}
        if m:
            nx, ny, nz = m.get("X", x), m.get("Y", y), m.get("Z", z)
            out.append(((x * scale, y * scale, z * scale), (nx * scale, ny * scale, nz * scale), mode == "0"))
            x, y, z = nx, ny, nz
    return out


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    original, written = moves(sys.argv[1]), moves(sys.argv[2])
    tol = float(sys.argv[3]) if len(sys.argv) > 3 else 0.05
    pts = []
    for a, b, rapid in written:
        if rapid:
            continue
        a, b = np.array(a), np.array(b)
        n = max(1, int(np.linalg.norm(b - a) / 0.002))
        pts.append(a + (b - a) * np.linspace(0.0, 1.0, n + 1)[:, None])
    tree = cKDTree(np.vstack(pts))
    vertices = [b for i, (a, b, rapid) in enumerate(original)
                if not rapid and i + 1 < len(original) and not original[i + 1][2]]
    v = np.array(vertices)
    d, _ = tree.query(v)
    worst = int(np.argmax(d))
    print("vertices %d, max %.4f mm, beyond %.3f: %d, beyond %.3f: %d; farthest at %s"
          % (len(v), d.max(), 1.02 * tol, (d > 1.02 * tol).sum(), 2 * tol, (d > 2 * tol).sum(),
             np.round(v[worst], 3).tolist()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
