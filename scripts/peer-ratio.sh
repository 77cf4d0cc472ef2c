#!/usr/bin/env bash
# Issue 21's first target: `auto` against the junction-deviation peer.
# For each program, the time of the program `auto` writes (arcs, the
# default format) over the time of the raw program run by fairpath's
# junction-deviation planner held to the same jerk limit, both planned by
# the same model: the default machine (400 mm/s, 4000 mm/s^2,
# 20000 mm/s^3, 1 ms), every feed move at the maximum feed, corners of
# the raw program blended within the tolerance (`--junction-deviation`
# = tolerance). Targets: at most 0.6 on the dense reference programs and
# on rasters with step-overs, at most 0.25 on contour-like programs
# whose segments are shorter than the tolerance (mean feed move: the
# raw program's feed length over its joints plus one). Also the exact curves' time and
# the same curves written as G6.2, over the raw time. scripts/survey.sh
# (issue 5) takes the same ratio on the exact curves only; the lower
# bound is scripts/lower-bound.sh's.
# Usage: scripts/peer-ratio.sh [TOLERANCE_MM] [PROGRAM...]
#   (PROGRAMs: files to time instead of the reference set, class
#   "given"; PEER_SOURCE: a sentence for the table's header saying where
#   they come from, e.g. the scripts/random-programs.py command)
#   (build first: cargo build --release -p fairpath-cli; FAIRPATH_BIN
#   times another build; PEER_MD=docs/peer-ratio.md also writes the
#   table there, with the date and commit; PEER_EXTRA: more arguments
#   for every `compare`, e.g. PEER_EXTRA="--block-time 0.001")
set -euo pipefail
cd "$(dirname "$0")/.."
tol=${1:-0.05}
bin=${FAIRPATH_BIN:-target/release/fairpath}
[ -x "$bin" ] || { echo "build first: cargo build --release -p fairpath-cli" >&2; exit 1; }
shift || true
python3 - "$bin" "$tol" "${PEER_MD:-}" "$(git rev-parse --short HEAD)" "$(nproc)" "${PEER_EXTRA:-}" "${PEER_SOURCE:-}" "$@" <<'PY'
import json, os, subprocess, sys, time
bin_, tol, md, commit, cores, extra, source = sys.argv[1:8]
given = sys.argv[8:]
tol_f = float(tol)
P = "../shared/paths/"
# (program, class): "dense" = the dense reference programs of issue 5's
# survey (scripts/methods-figures.sh), "raster" = rasters with
# step-overs; contour-like is measured (mean segment below the tolerance).
PROGRAMS = [
    ("synthetic/surface-raster.ngc", "raster"),
    ("synthetic/surface-raster-large.ngc", "raster"),
    ("synthetic/helix.ngc", "dense"),
    ("linuxcnc/performance/contour.ngc", "dense"),
    ("linuxcnc/performance/spiral_lines.ngc", "dense"),
    ("linuxcnc/performance/line-contouring-xz.ngc", "dense"),
    ("linuxcnc/performance/zigzag_0.002_0.0005.ngc", "dense"),
    ("linuxcnc/performance/zigzag_0.002_0.001.ngc", "dense"),
    ("linuxcnc/performance/random_lines_0.001in.ngc", "dense"),
    ("linuxcnc/performance/LHchips4.ngc", "dense"),
    ("linuxcnc/performance/test_12mmflat.ngc", "dense"),
    ("linuxcnc/performance/Cereal.ngc", "dense"),
    ("linuxcnc/performance/blur_torus.ngc", "dense"),
    ("linuxcnc/wz-tests/130207L.ngc", "dense"),
    ("linuxcnc/XYtests/51MeanderAve.ngc", "dense"),
    ("gcode-rs/makerblock_tinycnc.gcode", "dense"),
]
if given:
    PROGRAMS = [(g, "given") for g in given]
rows = []
for rel, cls in PROGRAMS:
    t0 = time.monotonic()
    path = rel if given else P + rel
    if given:
        rel = os.path.basename(rel)
    o = subprocess.run([bin_, "compare", path, "--tolerance", tol + "mm", "--override-feed",
                        "--junction-deviation", tol, "--methods", "auto", "--formats", "arcs,g6.2",
                        "--format", "json", *extra.split()], capture_output=True, text=True)
    wall = time.monotonic() - t0
    if o.returncode != 0:
        print(f"{rel}: compare failed: {o.stderr.strip().splitlines()[-1:]}", file=sys.stderr)
        continue
    r = {x["method"]: x for x in json.loads(o.stdout)}
    orig, auto = r["original"], r["auto"]
    joints = orig["c0"] + orig["c1"] + orig["c2"] + orig["gaps"]
    mean_seg = orig["length_mm"] / max(joints + 1, 1)
    arcs, g6_2 = auto["written"][0], auto["written"][1]
    g6 = g6_2["time_s"] / orig["time_s"]
    ratio = arcs["time_s"] / orig["time_s"]
    contour = mean_seg < tol_f
    limit = 0.25 if contour else 0.6
    curves = auto["time_s"] / orig["time_s"]
    floor = orig["lower_bound_in_order_s"] / orig["time_s"]
    rows.append((rel, cls + (", contour-like" if contour else ""), mean_seg, orig["time_s"],
                 arcs["time_s"], ratio, limit, "met" if ratio <= limit else "NOT met", wall, curves, g6,
                 floor))
    print(f"{rel:48} {rows[-1][1]:22} seg {mean_seg:8.4f} mm  raw {orig['time_s']:9.3f} s  "
          f"auto {arcs['time_s']:9.3f} s  ratio {ratio:.3f} (<= {limit}) {rows[-1][7]}  "
          f"curves {curves:.3f}  g6.2 {g6:.3f}  in-order bound {floor:.3f}  ({wall:.0f} s)", flush=True)
met = sum(1 for x in rows if x[7] == "met")
print(f"peer target met on {met} of {len(rows)}")
if md:
    with open(md, "w") as f:
        w = lambda s="": f.write(s + "\n")
        w("# `auto` against the junction-deviation peer")
        w()
        env = f"PEER_EXTRA=\"{extra}\" " if extra else ""
        args = "".join(" " + g for g in given)
        w(f"Generated by `{env}PEER_MD={md} scripts/peer-ratio.sh {tol}{args}` on "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, commit {commit}, {cores} cores. "
          "Issue 21's first target. `fairpath compare P --tolerance "
          f"{tol}mm --override-feed --junction-deviation {tol} --methods auto --formats arcs "
          f"--format json{' ' + extra if extra else ''}`: the default machine (400 mm/s, 4000 mm/s^2, 20000 mm/s^3, 1 ms), "
          "every feed move at the maximum feed. \"raw\" is the program as it is, run by "
          "fairpath's planner with its corners blended within the tolerance (junction "
          "deviation) and held to the same jerk limit; \"auto\" the program `auto` writes "
          "(arcs, the default format), planned by the same model. Targets: ratio at most 0.6 "
          "on the dense reference programs (issue 5's set) and on rasters with step-overs, at "
          "most 0.25 on contour-like programs (mean feed move shorter than the tolerance: the "
          "raw program's feed length over its joints plus one). \"curves / raw\": the exact curves `auto` "
          "chose (what a G6.2 output carries, which the arcs approximate within the output's "
          "share of the tolerance), over the raw program: where it meets the target and the "
          "written arcs do not, the loss is the rendering's. \"G6.2 / raw\": those curves written as G6.2 NURBS "
          "blocks (`--format g6.2`, for controllers that read them), read back and planned. "
          "The last column is the wall time "
          "of the `compare` run (smoothing, writing and planning every form). How far `auto` is "
          "from the least time any path within the tolerance can take: "
          "[lower-bound.md](lower-bound.md). Here \"in-order bound / raw\" is that bound "
          "(`feed::lower_bound`, `BandPaths::InOrder`: the least time of any path within the "
          "tolerance that follows the original in order, under the same limits and feeds) over "
          "the raw time, the least ratio such a path could reach: a target below it cannot be "
          "met by a path that follows the original, one above it is not shown to be reachable "
          "(the bound is loose at turns and on "
          "gentle curves)." + (f" The programs: {source}" if source else ""))
        w()
        w("| program | class | mean move mm | raw s | auto written s | auto / raw | target | "
          "met | curves / raw | G6.2 / raw | in-order bound / raw | compare wall s |")
        w("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for x in rows:
            w(f"| {x[0]} | {x[1]} | {x[2]:.4f} | {x[3]:.3f} | {x[4]:.3f} | {x[5]:.3f} | "
              f"<= {x[6]} | {x[7]} | {x[9]:.3f} | {x[10]:.3f} | {x[11]:.3f} | {x[8]:.1f} |")
        w()
        w(f"Met on {met} of {len(rows)}.")
PY
