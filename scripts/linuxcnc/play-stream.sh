#!/bin/bash
# play-stream.sh - play a position stream (fairpath stream) through LinuxCNC's
#                  halstreamer, headless, and measure what the drives got.
#
# usage: play-stream.sh [options] STREAM
#   STREAM: one line per servo period, whitespace-separated positions in mm,
#       X Y Z first (further columns are streamed onto streamer.0.pin.3.. and
#       not used), no comments, no blank lines; the first line is the start
#       position (the machine is homed there).
#   -L  LinuxCNC: a run-in-place tree (default $HOME/lcnc-master, or $LCNC) or "system"
#   -v  max velocity, mm/s   } the machine's limits (INI TRAJ/AXIS/JOINT, as
#   -a  max acceleration     } run-program.sh; motion does not move here);
#   -j  max jerk, mm/s^3     } -j is also the limit for jerk_over_ms (defaults 400, 4000, 20000)
#   -p  servo period in ns (default 1000000 = 1 ms; must be the stream's period)
#   -r  reference program (.ngc, absolute G0/G1/G2/G3): max_dev/rms_dev against its
#       polyline (start point after the leading rapids + every move end point up
#       to the last feed move, prep.py --ref-only); without -r: max_dev=NA
#   -c  write the per-servo-cycle samples of the motion window to CSV
#       (x,y,z mm of the drive command, kinematics, streamer state, stream line)
#   -d  streamer FIFO depth, lines (default 65536)
#   -t  timeout for playing, s (default: the stream's duration + 120)
# Output (stdout, one line): the keys of run-program.sh (cycles seconds max_vel
#   acc acc_t acc_n jerk jerk_p99 acc5 jerk5 acc_axis jerk_axis jerk5_axis
#   jerk_over_ms jerk5_over_ms path_len stops start end samples gaps overruns)
#   + underruns played max_dev rms_dev lines moving status.
#   played: cycles in which the streamer put out a line (must be = lines);
#   underruns: cycles before the last line in which the FIFO was empty;
#   moving: lines from the first to the last one that differs from its
#   predecessor in X, Y or Z (= cycles when played as written).
# Exit status 0 when the stream was played as written (every line, no
# underrun, no sampler overrun), 1 when not (status=failed), 2/3 on errors.
# Per-run files in $FAIRPATH_LCNC_RUN (default /tmp/fairpath-lcnc-stream).
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
VEL=400; ACC=4000; JERK=20000; PERIOD=1000000; REF=""; CSV=""; DEPTH=65536; TIMEOUT=""
LCNC=${LCNC:-$HOME/lcnc-master}
PLANNER=0        # motion never moves here; written so that the INI is complete
usage() { sed -n '2,33p' "$0"; exit 2; }
while getopts "L:v:a:j:p:r:c:d:t:h" o; do
  case $o in
    L) LCNC=$OPTARG;; v) VEL=$OPTARG;; a) ACC=$OPTARG;; j) JERK=$OPTARG;;
    p) PERIOD=$OPTARG;; r) REF=$(realpath "$OPTARG") || exit 2;;
    c) CSV=$(realpath -m "$OPTARG");; d) DEPTH=$OPTARG;; t) TIMEOUT=$OPTARG;;
    *) usage;;
  esac
done
shift $((OPTIND-1))
[ $# -eq 1 ] || usage
STREAM=$(realpath "$1") || exit 2
[ -r "$STREAM" ] || { echo "cannot read $STREAM" >&2; exit 2; }
[ "$LCNC" = system ] || LCNC=$(realpath -m "$LCNC")
# shellcheck source-path=SCRIPTDIR source=lib.sh
. "$HERE/lib.sh"

# check the stream (halstreamer skips bad lines with a message, and a last line
# without newline): lines, columns, start position, moving lines
INFO=$($PY - "$STREAM" <<'EOF'
import sys
path = sys.argv[1]
data = open(path, "rb").read()
if not data:
    sys.exit("empty stream")
if not data.endswith(b"\n"):
    sys.exit("the last line has no newline (halstreamer would skip it)")
rows, ncol, first, prev = 0, None, None, None
start = stop = -1
for i, ln in enumerate(data.decode("ascii").split("\n")[:-1]):
    f = ln.split()
    if not f or ln.lstrip().startswith("#"):
        sys.exit("line %d: blank or comment line" % (i + 1))
    try:
        v = [float(x) for x in f]
    except ValueError:
        sys.exit("line %d: not numbers: %r" % (i + 1, ln[:80]))
    if ncol is None:
        ncol, first = len(f), f
        if ncol < 3:
            sys.exit("line 1: %d columns, need X Y Z" % ncol)
    elif len(f) != ncol:
        sys.exit("line %d: %d columns, line 1 has %d" % (i + 1, len(f), ncol))
    if prev is not None and any(abs(a - b) > 1e-9 for a, b in zip(v[:3], prev[:3])):
        stop = i
        if start < 0:
            start = i
    prev = v
    rows += 1
print("lines=%d cols=%d start=%s,%s,%s moving=%d"
      % (rows, ncol, first[0], first[1], first[2], stop - start + 1 if start >= 0 else 0))
EOF
) || { echo "play-stream.sh: bad stream $STREAM" >&2; exit 2; }
LINES=$(sed -n 's/.*lines=\([0-9]*\).*/\1/p' <<<"$INFO")
COLS=$(sed -n 's/.*cols=\([0-9]*\).*/\1/p' <<<"$INFO")
MOVING=$(sed -n 's/.*moving=\([0-9]*\).*/\1/p' <<<"$INFO")
START=$(sed -n 's/.*start=\([^ ]*\).*/\1/p' <<<"$INFO")
IFS=, read -r SX SY SZ <<<"$START"
export SX SY SZ
CFG=$(head -c "$COLS" </dev/zero | tr '\0' f)
PERIOD_S=$(awk -v p="$PERIOD" 'BEGIN{printf "%.9g", p/1e9}')
[ -n "$TIMEOUT" ] || TIMEOUT=$(awk -v n="$LINES" -v p="$PERIOD_S" 'BEGIN{printf "%d", n*p+120}')

lcnc_lock
RUN=${FAIRPATH_LCNC_RUN:-/tmp/fairpath-lcnc-stream}
lcnc_prepare_run
if [ -n "$REF" ]; then
  $PY "$HERE/prep.py" --ref-only "$REF" "$RUN/ref.csv" >/dev/null || exit 2
fi
lcnc_ini "$RUN/stream.ini" "$HERE/play_display.py" "$HERE/stream.hal" "# $INFO
[STREAM]
FILE = $STREAM
LINES = $LINES
DEPTH = $DEPTH
CFG = $CFG
RAW = $RUN/samples.raw
STATUS = $RUN/status.json
TIMEOUT = $TIMEOUT
SAMPLER_DEPTH = 65536"
lcnc_run "$RUN/stream.ini" "$TIMEOUT" || exit 2
lcnc_status_ok || exit 1

OUT=$($PY "$HERE/analyze.py" --stream "$RUN/samples.raw" "$PERIOD_S" "$RUN/window.csv" 0.001 "$JERK") || {
  echo "$OUT underruns=NA max_dev=NA rms_dev=NA lines=$LINES moving=$MOVING status=failed"; exit 1; }
if [ -n "$REF" ]; then
  DEV=$($PY "$HERE/pathdev.py" "$RUN/ref.csv" "$RUN/window.csv")
else
  DEV="max_dev=NA rms_dev=NA"
fi
[ -n "$CSV" ] && cp "$RUN/window.csv" "$CSV"
key() { sed -n "s/.* $1=\([^ ]*\).*/\1/p" <<<" $OUT"; }
ST=ok
[ "$(key played)" = "$LINES" ] && [ "$(key underruns)" = 0 ] && [ "$(key overruns)" = 0 ] \
  && [ "$(key gaps)" = 0 ] || ST=failed
echo "$OUT $DEV lines=$LINES moving=$MOVING status=$ST"
[ $ST = ok ]
