#!/bin/bash
# bench.sh - fairpath against LinuxCNC's own planners, measured in LinuxCNC.
#
# usage: bench.sh [-o TABLE.md] [-t TOL] [-L TREE|system] [PROGRAM...]
#   PROGRAM  default: ../shared/paths/{synthetic/butterfly-80, synthetic/helix,
#            synthetic/surface-raster, linuxcnc/performance/contour}.ngc
#   -o  markdown table (default target/lcnc-bench/table.md); the raw lines of
#       every run go to the same name with .log
#   -t  fairpath tolerance, mm (default 0.05)
#   -L  LinuxCNC: run-in-place tree (default $HOME/lcnc-master, or $LCNC) or "system"
#       (2.9: no S-curve planner; the P1 rows are then trapezoid too)
# Machine: V 400 mm/s, A 4000 mm/s^2, J 20000 mm/s^3, 1 ms servo period.
# For each program:
#   a. trapezoid-raw   the program, PLANNER_TYPE 0, G64 P0.05 Q0, feeds overridden
#                      (F = 60*V*1.001: the machine limits, not F, govern)
#   b. scurve-raw      the same with PLANNER_TYPE 1 (S-curve)
#   c. fairpath-gcode  fairpath smooth --method auto --controller linuxcnc
#                      (the curvature-continuous output), PLANNER_TYPE 1,
#                      run with -g keep, deviation against the ORIGINAL program
#   e. fairpath-arcfit the same with --method arc-fit, the default for
#                      --controller linuxcnc (the fewest blocks within
#                      the tolerance: LinuxCNC's S-curve planner caps the speed
#                      at every block end)
#   d. fairpath-stream fairpath stream (its own jerk-limited plan, one position
#                      per servo period) played with play-stream.sh,
#                      deviation against the original; its planned time is
#                      parsed from "planned time: X s" (NA if absent)
# $CASES: which of them, by name (default all five).
# Progress on stderr. $FAIRPATH_BIN: the fairpath binary (default
# target/release/fairpath of this checkout). Takes long (the S-curve planner
# runs these programs slowly, and LinuxCNC runs in real time): not for CI.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(git -C "$HERE" rev-parse --show-toplevel) || exit 2
PATHS=$ROOT/../shared/paths
TABLE=$ROOT/target/lcnc-bench/table.md; TOL=0.05; LARGS=()
V=400; A=4000; J=20000; PERIOD_NS=1000000
usage() { sed -n '2,27p' "$0"; exit 2; }
while getopts "o:t:L:h" o; do
  case $o in
    o) TABLE=$OPTARG;; t) TOL=$OPTARG;; L) LARGS=(-L "$OPTARG");;
    *) usage;;
  esac
done
shift $((OPTIND-1))
if [ $# -eq 0 ]; then
  set -- "$PATHS/synthetic/butterfly-80.ngc" "$PATHS/synthetic/helix.ngc" \
         "$PATHS/synthetic/surface-raster.ngc" "$PATHS/linuxcnc/performance/contour.ngc"
fi
FAIRPATH=${FAIRPATH_BIN:-$ROOT/target/release/fairpath}
[ -x "$FAIRPATH" ] || { echo "no fairpath binary at $FAIRPATH (cargo build --release, or set FAIRPATH_BIN)" >&2; exit 2; }
TABLE=$(realpath -m "$TABLE")
LOG=${TABLE%.md}.log
WORK=$(dirname "$TABLE")/work
mkdir -p "$WORK"
: > "$LOG"
LIMITS=(-v "$V" -a "$A" -j "$J" -p "$PERIOD_NS")
CASES=${CASES:-trapezoid-raw scurve-raw fairpath-gcode fairpath-arcfit fairpath-stream}
want() { [[ " $CASES " == *" $1 "* ]]; }
n_total=$(( $# * $(wc -w <<<"$CASES") )); n=0

# log PROGRAM CASE LINE: one raw line "program case key=value ..."
log() { echo "$1 $2 $3" >> "$LOG"; }
progress() {   # label, result line
  local short
  short=$(grep -oE '(cycles|seconds|jerk5|max_dev|underruns|status|errors)=("[^"]*"|[^ ]*)' <<<"$2" | tr '\n' ' ')
  echo "[$n/$n_total] $1: $short" >&2
}
run_case() {   # program-name case command...
  local name=$1 case=$2 out; shift 2
  n=$((n+1))
  echo "[$n/$n_total] $name $case ..." >&2
  out=$("$@" 2>>"$WORK/stderr.txt" | tail -1)
  [ -n "$out" ] || out='cycles=NA seconds=NA status=failed errors="no output (see '"$WORK"'/stderr.txt)"'
  log "$name" "$case" "$out"
  progress "$name $case" "$out"
}

for prog in "$@"; do
  prog=$(realpath "$prog") || exit 2
  name=$(basename "$prog" .ngc)
  want trapezoid-raw && run_case "$name" trapezoid-raw "$HERE/run-program.sh" "${LARGS[@]}" "${LIMITS[@]}" -P 0 -g "P0.05 Q0" "$prog"
  want scurve-raw && run_case "$name" scurve-raw    "$HERE/run-program.sh" "${LARGS[@]}" "${LIMITS[@]}" -P 1 -g "P0.05 Q0" "$prog"

  # c. fairpath's G-code for LinuxCNC. --controller linuxcnc writes
  #    "G64 P<blend> Q0" before every smoothed run (blend = a share of the
  #    tolerance, e.g. P0.0005 at 0.05 mm; Q0 so that LinuxCNC neither merges
  #    blocks nor replaces short arcs) and the program's own G64/G61 after it:
  #    so the output is run as written (-g keep). Imposing "G64 P0.005 Q0" as
  #    the shared rig did would blend 10x more than fairpath budgeted for, and
  #    over the program's own path control outside the smoothed runs.
  for c in fairpath-gcode fairpath-arcfit; do
    want "$c" || continue
    if [ "$c" = fairpath-arcfit ]; then margs=(--method arc-fit); else margs=(--method auto); fi
    smooth=$WORK/$name-$c.ngc
    if "$FAIRPATH" smooth "$prog" "${margs[@]}" --controller linuxcnc --tolerance "${TOL}mm" -o "$smooth" >"$WORK/$name-$c.txt" 2>&1; then
      # Runs fairpath keeps as written carry no G64 of fairpath's; the raw
      # runs above are blended with "G64 P<TOL> Q0": so are they, by that
      # line after the units line (fairpath's own G64 around the runs it
      # rewrote comes later and governs those).
      awk -v tol="$TOL" 'BEGIN{done=0}
        { print }
        !done && toupper($0) ~ /G *2[01]([^0-9.]|$)/ {
          p = (toupper($0) ~ /G *20([^0-9.]|$)/) ? tol / 25.4 : tol
          printf "G64 P%.6g Q0 (bench: the raw runs'"'"' blending)\n", p; done=1 }' \
        "$smooth" > "$smooth.tmp" && mv "$smooth.tmp" "$smooth"
      run_case "$name" "$c" "$HERE/run-program.sh" "${LARGS[@]}" "${LIMITS[@]}" -P 1 -g keep -r "$prog" "$smooth"
    else
      n=$((n+1))
      out="cycles=NA seconds=NA status=failed errors=\"fairpath smooth failed (see $WORK/$name-$c.txt)\""
      log "$name" "$c" "$out"; progress "$name $c" "$out"
    fi
  done

  # d. fairpath's stream, played through halstreamer
  stream=$WORK/$name-stream.txt
  if ! want fairpath-stream; then :
  elif "$FAIRPATH" stream "$prog" --tolerance "${TOL}mm" --override-feed --max-feed $((V*60)) \
       --acc "$A" --jerk "$J" --period "$(awk -v p="$PERIOD_NS" 'BEGIN{printf "%.9g", p/1e9}')" \
       -o "$stream" >"$WORK/$name-stream.out" 2>&1; then
    planned=$(sed -n 's/.*planned time: *\([0-9.eE+-]*\) *s.*/\1/p' "$WORK/$name-stream.out" | head -1)
    run_case "$name" fairpath-stream "$HERE/play-stream.sh" "${LARGS[@]}" "${LIMITS[@]}" -r "$prog" "$stream"
    sed -i '$ s/$/ planned='"${planned:-NA}"'/' "$LOG"
  else
    n=$((n+1))
    out="cycles=NA seconds=NA status=failed errors=\"fairpath stream failed (see $WORK/$name-stream.out)\" planned=NA"
    log "$name" fairpath-stream "$out"; progress "$name fairpath-stream" "$out"
  fi
done
/usr/bin/python3 "$HERE/bench_table.py" "$LOG" > "$TABLE"
echo "table: $TABLE  raw lines: $LOG" >&2
cat "$TABLE"
