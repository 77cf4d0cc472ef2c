#!/usr/bin/env python3
"""Issue 19, memory on one-run programs: are the methods local enough for a
long run to be smoothed in overlapping windows and stitched, with the same
pieces as the whole run?

A run of one long raster is cut at a seam line S. Window A is the program
up to line S + OVERLAP (its run ends there); window B starts with a rapid to
where the program stands before line S - OVERLAP and goes on from there
(its run starts there); "whole" is the program up to the end of B. Each is
smoothed with `fairpath smooth -f json` and the pieces compared exactly
(the JSON numbers as written, `source_lines` left out: B's lines are
numbered from its own start). A agrees with the whole for its first a
pieces, B for its last b: where a + b >= the whole's count, the agreeing
stretches overlap, and the whole run's pieces are A's up to a piece both
hold and B's after it, to the bit.

Usage: scripts/window-locality.py [--md FILE] [--program P] [--lines N]
       [--seam S] [--overlap K ...] [--method M ...]
(build first: cargo build --release -p fairpath-cli; FAIRPATH_BIN=path
times another build.)
"""

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(__file__), ".."))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "paths"))


def position_before(lines, n):
    """X, Y, Z as the program stands before line n (1-based), G90 only."""
    pos = {"X": 0.0, "Y": 0.0, "Z": 0.0}
    for line in lines[: n - 1]:
        code = re.sub(r"\(.*?\)", "", line.split(";")[0])
        for axis, value in re.findall(r"([XYZ])\s*(-?[\d.]+)", code.upper()):
            pos[axis] = value
    return pos


def smooth(binary, path, method, tolerance):
    out = path[:-4] + "." + method + ".json"
    started = time.time()
    r = subprocess.run(
        [binary, "smooth", path, "-t", tolerance, "-m", method, "-f", "json", "-o", out],
        capture_output=True,
        text=True,
    )
    if r.returncode != 0:
        sys.exit(f"fairpath smooth {path} -m {method} failed:\n{r.stderr}")
    with open(out) as f:
        pieces = json.load(f)["pieces"]
    keys = []
    for p in pieces:
        q = dict(p)
        q.pop("source_lines", None)
        keys.append(json.dumps(q, sort_keys=True))
    return keys, time.time() - started


def agree_prefix(a, w):
    i = 0
    while i < len(a) and i < len(w) and a[i] == w[i]:
        i += 1
    return i


def agree_suffix(b, w):
    j = 0
    while j < len(b) and j < len(w) and b[-1 - j] == w[-1 - j]:
        j += 1
    return j


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--program", default=os.path.join(SHARED, "synthetic", "surface-raster-large.ngc"))
    ap.add_argument("--lines", type=int, default=40000)
    ap.add_argument("--seam", type=int, default=20000)
    ap.add_argument("--overlap", type=int, nargs="+", default=[10, 1000])
    ap.add_argument("--method", nargs="+", default=["bspline-corner", "ctm", "lotm", "bspline-fit", "auto"])
    ap.add_argument("--tolerance", default="0.05mm")
    ap.add_argument("--md")
    args = ap.parse_args()
    binary = os.environ.get("FAIRPATH_BIN", os.path.join(ROOT, "target", "release", "fairpath"))
    if not os.access(binary, os.X_OK):
        sys.exit("build first: cargo build --release -p fairpath-cli")
    with open(args.program) as f:
        lines = f.read().split("\n")
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        whole = os.path.join(tmp, "whole.ngc")
        with open(whole, "w") as f:
            f.write("\n".join(lines[: args.lines]) + "\nM2\n")
        for k in args.overlap:
            a_path = os.path.join(tmp, f"a{k}.ngc")
            with open(a_path, "w") as f:
                f.write("\n".join(lines[: args.seam + k]) + "\nM2\n")
            start = args.seam - k
            pos = position_before(lines, start)
            feed = re.findall(r"F\s*([\d.]+)", "\n".join(lines[:start]).upper())
            b_path = os.path.join(tmp, f"b{k}.ngc")
            with open(b_path, "w") as f:
                f.write("G21 G90 G17\n")
                f.write(f"G0 X{pos['X']} Y{pos['Y']} Z{pos['Z']}\n")
                f.write(f"G1 F{feed[-1] if feed else 1000}\n")
                f.write("\n".join(lines[start - 1 : args.lines]) + "\nM2\n")
            for m in args.method:
                w, tw = smooth(binary, whole, m, args.tolerance)
                a, ta = smooth(binary, a_path, m, args.tolerance)
                b, tb = smooth(binary, b_path, m, args.tolerance)
                i, j = agree_prefix(a, w), agree_suffix(b, w)
                rows.append((m, k, len(w), len(a), len(b), len(a) - i, len(b) - j, i + j >= len(w), tw, ta + tb))
    head = (
        "| method | overlap (lines each side) | whole: pieces | A: pieces | B: pieces "
        "| A's last pieces unlike the whole's | B's first pieces unlike the whole's "
        "| stitched = whole | whole s | A + B s |"
    )
    out = [head, "|" + "---|" * 10]
    for r in rows:
        out.append(
            f"| `{r[0]}` | {r[1]} | {r[2]} | {r[3]} | {r[4]} | {r[5]} | {r[6]} | "
            f"{'yes' if r[7] else 'no'} | {r[8]:.2f} | {r[9]:.2f} |"
        )
    table = "\n".join(out)
    print(table)
    if args.md:
        rel = os.path.relpath(args.program, SHARED)
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
        with open(args.md, "w") as f:
            f.write("# Are the methods local? Windows of one long run against the whole\n\n")
            f.write(
                f"Generated by `scripts/window-locality.py --md {args.md}` on "
                f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}: "
                f"the first {args.lines} lines of `{rel}` (one run), cut at line {args.seam}, "
                f"tolerance {args.tolerance}. Window A is the program up to the seam plus the "
                "overlap (its run ends there); window B starts with a rapid to where the program "
                "stands before the seam less the overlap. Pieces are compared exactly (JSON "
                "output, `source_lines` left out). \"stitched = whole\": A's agreeing pieces and "
                "B's overlap, so A's pieces up to one both hold and B's after it are the whole "
                "run's pieces, to the bit.\n\n"
            )
            f.write(table + "\n\n")
            f.write(
                "What it is for: a program of one long run (a raster) is held whole today, so "
                "its memory is many times the file's (issue 19; `docs/scale.md`). Smoothing it "
                "in overlapping windows and stitching where the windows agree keeps the output "
                "the same wherever the table says yes; the check that they agree is what makes "
                "the stitch safe where a method is not local (a larger overlap, or the whole run, "
                "where no piece agrees). The planner is stitched so already, for the times the "
                "writer's check and `auto` compare (`fairpath::feed::windowed`); the rest of the "
                "pipeline (smoothing, rendering, writing, reading back) still holds a run whole: "
                "`docs/performance.md`, \"Windows of one run\".\n"
            )


if __name__ == "__main__":
    main()
