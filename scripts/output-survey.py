#!/usr/bin/env python3
"""Issue-16 survey: what `fairpath smooth` writes, planned as a controller
would run it.

For every reference program (or those given), `fairpath compare` smooths it
with `auto` at the tolerance, writes it in each format (as `smooth` does for
the controller) and plans the input, the exact curves and each written
program with `simulate`'s model at the default machine, feeds overridden to
the machine's maximum (the issue's targets). Writes a CSV (one row per
program and format) and a Markdown summary to stdout.

Usage: scripts/output-survey.py [--tolerance 0.05] [--controller generic]
       [--formats arcs,g1,g6.2] [--csv out.csv] [--markdown docs/output-survey.md]
       [PROGRAM ...]
Build first: cargo build --release. `--markdown` writes the report (with
the date, the commit and the command) to a file instead of stdout.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PATHS = os.path.normpath(os.path.join(ROOT, "..", "shared", "paths"))
BIN = os.path.join(ROOT, "target", "release", "fairpath")
EXTS = (".ngc", ".nc", ".gcode", ".tap", ".txt", ".cnc")

# The dense programs of the targets: helix, surface rasters, LinuxCNC's
# contour and finishing programs (the issue-5 dense set).
DENSE = {
    "synthetic/helix.ngc",
    "synthetic/surface-raster.ngc",
    "synthetic/surface-raster-large.ngc",
    "linuxcnc/performance/contour.ngc",
    "linuxcnc/performance/LHchips4.ngc",
    "linuxcnc/performance/test_12mmflat.ngc",
    "linuxcnc/performance/Cereal.ngc",
    "linuxcnc/performance/blur_torus.ngc",
    "linuxcnc/performance/line-contouring-xz.ngc",
    "linuxcnc/performance/3D_Chips.ngc",
    "linuxcnc/wz-tests/130207L.ngc",
    "linuxcnc/XYtests/51MeanderAve.ngc",
}


def programs(given):
    if given:
        return given
    out = []
    for d, _, files in os.walk(PATHS):
        for f in files:
            if f.lower().endswith(EXTS):
                out.append(os.path.join(d, f))
    return sorted(out)


def rel(p):
    return os.path.relpath(p, PATHS)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tolerance", default="0.05")
    ap.add_argument("--controller", default="generic")
    ap.add_argument("--formats", default="arcs,g1,g6.2")
    ap.add_argument("--csv")
    ap.add_argument("--markdown")
    ap.add_argument("--timeout", type=int, default=600)
    ap.add_argument("programs", nargs="*")
    a = ap.parse_args()
    formats = a.formats.split(",")
    rows = []
    refused = []
    for p in programs(a.programs):
        cmd = [BIN, "compare", p, "--tolerance", a.tolerance + "mm", "--override-feed",
               "--methods", "auto", "--controller", a.controller,
               "--formats", a.formats, "--format", "json"]
        t0 = time.time()
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=a.timeout)
        except subprocess.TimeoutExpired:
            refused.append((rel(p), "timeout"))
            continue
        if r.returncode not in (0, 3):
            refused.append((rel(p), r.stderr.strip().splitlines()[-1] if r.stderr else "?"))
            continue
        data = {row["method"]: row for row in json.loads(r.stdout)}
        orig, auto = data["original"], data["auto"]
        with open(p, "rb") as fh:
            lines_in = fh.read().decode("utf-8", "replace").count("\n")
        for w in auto["written"]:
            rows.append({
                "program": rel(p),
                "dense": rel(p) in DENSE,
                "format": w["format"],
                "lines_in": lines_in,
                "lines_out": w["lines"],
                "input_s": orig["time_s"],
                "curves_s": auto["time_s"],
                "written_s": w["time_s"],
                "written_over_input": w["time_s"] / orig["time_s"],
                "written_over_curves": w["time_s"] / auto["time_s"],
                "verified": w["verified"] and auto["verified"],
                "wall_s": round(time.time() - t0, 2),
            })
        print(f"{rel(p)}: " + ", ".join(
            f"{w['format']} {w['time_s']/orig['time_s']:.3f}/{w['time_s']/auto['time_s']:.3f}"
            for w in auto["written"]), file=sys.stderr)
    if a.csv:
        with open(a.csv, "w", newline="") as fh:
            wr = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
            wr.writeheader()
            wr.writerows(rows)
    out = open(a.markdown, "w") if a.markdown else sys.stdout
    if a.markdown:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"],
                                capture_output=True, text=True).stdout.strip()
        print("# Output survey (generated)\n", file=out)
        print(f"Written by `scripts/output-survey.py {' '.join(sys.argv[1:])}` on "
              f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}. "
              "Do not edit by hand.\n", file=out)
    report(rows, refused, formats, a, out)


def report(rows, refused, formats, a, out):
    def print(*args, **kw):
        kw.setdefault("file", out)
        __builtins__.print(*args, **kw)
    print(f"Survey at tolerance {a.tolerance} mm, controller {a.controller}, "
          f"`simulate --override-feed` model (default machine); "
          f"{len({r['program'] for r in rows})} programs written, {len(refused)} refused.\n")
    print("| format | programs | slower than input (>1.000) | median written/input | worst written/input | "
          "dense: worst written/input | median written/curves | worst written/curves | "
          "median lines out/in | not verified |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for f in formats:
        rs = [r for r in rows if r["format"] == f]
        if not rs:
            continue
        wi = sorted(r["written_over_input"] for r in rs)
        wc = sorted(r["written_over_curves"] for r in rs)
        li = sorted(r["lines_out"] / max(r["lines_in"], 1) for r in rs)
        dense = [r["written_over_input"] for r in rs if r["dense"]]
        slower = [r for r in rs if r["written_over_input"] > 1.0]
        worst_i = max(rs, key=lambda r: r["written_over_input"])
        worst_c = max(rs, key=lambda r: r["written_over_curves"])
        print(f"| {f} | {len(rs)} | {len(slower)} | {wi[len(wi)//2]:.3f} | "
              f"{worst_i['written_over_input']:.3f} ({os.path.basename(worst_i['program'])}) | "
              f"{max(dense) if dense else float('nan'):.3f} | {wc[len(wc)//2]:.3f} | "
              f"{worst_c['written_over_curves']:.3f} ({os.path.basename(worst_c['program'])}) | "
              f"{li[len(li)//2]:.2f} | {sum(not r['verified'] for r in rs)} |")
    print()
    print("Dense programs (written / input, written / curves, lines out / in):\n")
    print("| program | " + " | ".join(formats) + " |")
    print("|---|" + "---|" * len(formats))
    for prog in sorted({r["program"] for r in rows if r["dense"]}):
        cells = []
        for f in formats:
            r = next((r for r in rows if r["program"] == prog and r["format"] == f), None)
            cells.append("-" if r is None else
                         f"{r['written_over_input']:.3f} / {r['written_over_curves']:.3f} / "
                         f"{r['lines_out']}:{r['lines_in']}")
        print(f"| {prog} | " + " | ".join(cells) + " |")
    print()
    for f in formats:
        over = sorted((r for r in rows if r["format"] == f and r["written_over_curves"] > 1.25),
                      key=lambda r: -r["written_over_curves"])
        print(f"{f}: {len(over)} programs over 1.25 of the curves' time"
              + (": " + ", ".join(f"{os.path.basename(r['program'])} {r['written_over_curves']:.3f}"
                                   for r in over) if over else "") + ".\n")
    if refused:
        print(f"\nRefused ({len(refused)}): " + "; ".join(f"{p}: {e[:80]}" for p, e in refused[:200]))


if __name__ == "__main__":
    main()
