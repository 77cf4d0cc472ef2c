#!/usr/bin/env bash
# Issue-5 survey: auto vs the original (junction-deviation planner) and vs
# bspline-corner, at the thesis machine with feeds overridden.
# Usage: scripts/survey.sh [TOLERANCE] [PROGRAM...]   (default: the dense set)
# Columns: planned times (s, rapids included), auto/original, auto/corner,
# auto/original on feed moves only, and auto's smoothing wall time.
set -u
cd "$(dirname "$0")/.."
tol=${1:-0.05}; shift || true
P=../shared/paths
progs=("$@")
if [ ${#progs[@]} -eq 0 ]; then
  progs=($P/synthetic/{surface-raster,helix,butterfly-80,noisy-line,hexagon-3d,square-wave}.ngc
    $P/linuxcnc/performance/{contour,spiral_lines,line-contouring-xz,zigzag_0.002_0.0005,zigzag_0.002_0.001}.ngc
    $P/linuxcnc/performance/{random_lines_0.001in,LHchips4,test_12mmflat,Cereal,blur_torus}.ngc
    $P/linuxcnc/wz-tests/130207L.ngc $P/linuxcnc/XYtests/51MeanderAve.ngc
    $P/gcode-rs/makerblock_tinycnc.gcode
    $P/linuxcnc/performance/{tort,arc_parabolic}.ngc $P/linuxcnc/arc-intersections/arc-arc-sawtooth.ngc)
fi
bin=target/release/fairpath
printf '%-28s %9s %9s %9s %6s %6s %6s %s\n' program original corner auto a/orig a/corn feed ok
for f in "${progs[@]}"; do
  out=$($bin compare "$f" --tolerance "${tol}mm" --override-feed --junction-deviation "$tol" \
        --methods bspline-corner,auto --format json 2>/dev/null) || { echo "$(basename $f): failed"; continue; }
  python3 - "$f" "$out" <<'PY'
import json, sys, os
rows = {r["method"]: r for r in json.loads(sys.argv[2])}
o, c, a = rows["original"]["time_s"], rows["bspline-corner"]["time_s"], rows["auto"]["time_s"]
ok = "ok" if a <= 0.7*o and a <= 0.7*c else "-"
# feed moves only (rapids are the same for every method)
f = rows["auto"]["feed_time_s"] / rows["original"]["feed_time_s"]
print(f'{os.path.basename(sys.argv[1])[:28]:28} {o:9.2f} {c:9.2f} {a:9.2f} {a/o:6.2f} {a/c:6.2f} {f:6.2f} {ok} {rows["auto"]["smoothing_s"]:.2f}s')
PY
done
