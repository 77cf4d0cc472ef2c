#!/bin/bash
# run-program.sh - time a G-code program through LinuxCNC's own trajectory planner
#                  (uspace simulation, headless).
# Adapted from the shared timing rig ../shared/tools/lcnc-master/run.sh (same
# options, INI, HAL, display program and analysis; the rig's files are copied
# here: prep.py, analyze.py, pathdev.py, program.hal (rig.hal),
# program_display.py (rig_display.py)). Output is the rig's line.
#
# usage: run-program.sh [options] FILE.ngc
#   -P  [TRAJ]PLANNER_TYPE: 0 = trapezoid (as 2.9), 1 = S-curve/ruckig  (default 1)
#   -v  max velocity, mm/s: TRAJ MAX_LINEAR_VELOCITY + per-axis MAX_VELOCITY  (default 400)
#   -a  max acceleration, mm/s^2: TRAJ + per-axis (default 4000)
#   -j  max jerk, mm/s^3: TRAJ MAX_LINEAR_JERK + per-axis/joint MAX_JERK (default 20000)
#   -g  path control inserted after the G20/G21 line, tolerances in mm
#       (default "P0.05 Q0" -> "G64 P0.05 Q0"; "G61"/"G61.1" also accepted;
#       "keep": the program's own G61/G64 as programmed); otherwise existing
#       G61/G64 words in the program are removed
#   -F  feed (mm/min) written over every F word (default 60*VEL*1.001);
#       "-F keep" keeps the program's feeds
#   -r  reference program for the deviation (default: FILE.ngc itself)
#   -p  servo period in ns (default 1000000 = 1 ms)
#   -c  write per-servo-cycle samples (t,x,y,z mm, vel, acc, jerk ...) of the motion window to CSV
#   -n  no prefill (do not hold feed-inhibit while task fills the motion queue)
#   -t  timeout for the program run, s (default 900)
#   -L  LinuxCNC: a run-in-place tree (default $HOME/lcnc-master, or $LCNC) or "system"
#       (the Debian linuxcnc-uspace package; PLANNER_TYPE/JERK keys are then ignored)
# Output (stdout, one line): cycles=N seconds=.. max_vel=.. acc=.. acc_t=.. jerk=..
#   acc5=.. jerk5=.. max_dev=.. rms_dev=.. start=.. end=.. path_len=.. (see README.md)
# Per-run files in $FAIRPATH_LCNC_RUN (default /tmp/fairpath-lcnc-program).
# Exit status 0 on success.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
PLANNER=1; VEL=400; ACC=4000; JERK=20000; G64="P0.05 Q0"; FEED=""; REF=""
PERIOD=1000000; CSV=""; PREFILL=1; TIMEOUT=900; LCNC=${LCNC:-$HOME/lcnc-master}
usage() { sed -n '2,30p' "$0"; exit 2; }
while getopts "P:v:a:j:g:F:r:p:c:nt:L:h" o; do
  case $o in
    P) PLANNER=$OPTARG;; v) VEL=$OPTARG;; a) ACC=$OPTARG;; j) JERK=$OPTARG;;
    g) G64=$OPTARG;; F) FEED=$OPTARG;; r) REF=$(realpath "$OPTARG");;
    p) PERIOD=$OPTARG;; c) CSV=$(realpath -m "$OPTARG");;
    n) PREFILL=0;; t) TIMEOUT=$OPTARG;; L) LCNC=$OPTARG;;
    *) usage;;
  esac
done
shift $((OPTIND-1))
[ $# -eq 1 ] || usage
SRC=$(realpath "$1") || exit 2
[ -r "$SRC" ] || { echo "cannot read $SRC" >&2; exit 2; }
[ -n "$REF" ] || REF=$SRC
[ -n "$FEED" ] || FEED=$(awk -v v="$VEL" 'BEGIN{printf "%.4f", v*60*1.001}')
[ "$LCNC" = system ] || LCNC=$(realpath -m "$LCNC")
# shellcheck source-path=SCRIPTDIR source=lib.sh
. "$HERE/lib.sh"

lcnc_lock
RUN=${FAIRPATH_LCNC_RUN:-/tmp/fairpath-lcnc-program}
lcnc_prepare_run
NGC=$RUN/prog.ngc
if [ "$FEED" = keep ]; then FA=(); else FA=(--feed "$FEED"); fi
PREP=$($PY "$HERE/prep.py" "$SRC" "$NGC" "$RUN/prog_ref.csv" --g64 "$G64" "${FA[@]}") || exit 2
START=$(sed -n 's/^start=\([^ ]*\).*/\1/p' <<<"$PREP")
IFS=, read -r SX SY SZ <<<"$START"
export SX SY SZ
$PY "$HERE/prep.py" --ref-only "$REF" "$RUN/ref.csv" >/dev/null || exit 2
PERIOD_S=$(awk -v p="$PERIOD" 'BEGIN{printf "%.9g", p/1e9}')

lcnc_ini "$RUN/rig.ini" "$HERE/program_display.py" "$HERE/program.hal" "# $PREP
[RIG]
PROGRAM = $NGC
RAW = $RUN/samples.raw
STATUS = $RUN/status.json
PREFILL = $PREFILL
TIMEOUT = $TIMEOUT
SAMPLER_DEPTH = 65536"
lcnc_run "$RUN/rig.ini" "$TIMEOUT" || exit 2
lcnc_status_ok || exit 1

OUT=$($PY "$HERE/analyze.py" "$RUN/samples.raw" "$PERIOD_S" "$RUN/window.csv" 0.001 "$JERK"); RC=$?
DEV=$($PY "$HERE/pathdev.py" "$RUN/ref.csv" "$RUN/window.csv")
[ -n "$CSV" ] && cp "$RUN/window.csv" "$CSV"
Q=$($PY -c "import json; d=json.load(open('$RUN/status.json')); print('queued=%s prefill_end=%s msgs=%d' % (d.get('prefill_queue','NA'), d.get('prefill_end','off'), len(d.get('messages',[]))))")
echo "$OUT $DEV $Q"
exit $RC
