#!/usr/bin/env python3
"""How many of a written program's feed blocks are shorter than one
interpolation period of travel at the speed fairpath plans there, and
what a controller that spends at least one period on every block (as
LinuxCNC's does) would add to the planned time.

Plain G-code only: each block's length is the distance between its end
points (an arc's chord, a little less than its length), in the program's
order; the planned speed is read from `fairpath simulate --profile` of the
same program (pass the same machine flags as to `smooth`). Blocks of a
G0 (or of modal G0) are left out.

fairpath's planner does this itself with a block time (`simulate
--block-time 0.001`, or `smooth` and `compare` with it): this script
counts the blocks and estimates their cost from the plan without one.

Usage: scripts/block-periods.py PROGRAM [SIMULATE FLAGS...]
(FAIRPATH_BIN for another binary than target/release/fairpath.)
"""
import bisect
import csv
import math
import os
import re
import subprocess
import sys
import tempfile

BIN = os.environ.get("FAIRPATH_BIN", "target/release/fairpath")
prog, flags = sys.argv[1], sys.argv[2:]

with tempfile.TemporaryDirectory() as tmp:
    profile = os.path.join(tmp, "profile.csv")
    subprocess.run([BIN, "simulate", prog, "--profile", profile, *flags],
                   check=True, stdout=subprocess.DEVNULL)
    ss, vs, period = [], [], None
    with open(profile) as fh:
        rows = csv.reader(fh)
        next(rows)
        for r in rows:
            t, s, v = float(r[0]), float(r[1]), float(r[2])
            if period is None and t > 0:
                period = t
            ss.append(s)
            vs.append(v)

pos, s, rapid = [0.0, 0.0, 0.0], 0.0, True
blocks = []
with open(prog) as fh:
    for line in fh:
        code = re.sub(r"\([^)]*\)|;.*", "", line).upper()
        for g in re.findall(r"G\s*0*([0-3])(?![0-9.])", code):
            rapid = g == "0"
        words = {m.group(1): float(m.group(2))
                 for m in re.finditer(r"([XYZ])\s*([-+]?[0-9]*\.?[0-9]+)", code)}
        if not words:
            continue
        new = [words.get(a, pos[i]) for i, a in enumerate("XYZ")]
        d = math.dist(pos, new)
        if d > 0 and not rapid:
            blocks.append((s, d))
        s += d
        pos = new

short, added = 0, 0.0
for s0, d in blocks:
    i = min(bisect.bisect_left(ss, s0 + 0.5 * d), len(vs) - 1)
    v = vs[i]
    if v > 0 and d < v * period:
        short += 1
        added += period - d / v
print(f"{prog}: {len(blocks)} feed blocks, {short} shorter than one period "
      f"of travel at the planned speed; one period per block would add "
      f"{added:.3f} s")
