#!/bin/bash
# smoke.sh - CI smoke test of play-stream.sh (about 10 s).
#
# Plays a short stream (a 300 ms jerk-limited 5 mm move in X, from a start
# position away from 0, then 20 resting lines; 3 columns, made here by python)
# through LinuxCNC: the Debian package (-L system) when /usr/bin/linuxcnc
# exists, else the run-in-place tree ${LCNC:-$HOME/lcnc-master} if present,
# else prints "skipped" and exits 0. Checks:
#   - play-stream.sh reports status=ok, underruns=0 and every line played;
#   - cycles = the stream's moving lines (within 1);
#   - the recorded drive commands equal the stream lines (max |diff| < 1e-6 mm).
# Then, when a fairpath binary is there ($FAIRPATH_BIN, else target/release
# or target/debug of this checkout), plays fairpath's own stream of
# examples/zigzag.ngc at 0.05 mm and checks the targets of the stream: time
# = fairpath's planned time (within 2 periods), peak jerk averaged over 5 ms
# within 5% of J, peak acceleration within 2% of A, deviation from the
# program within the tolerance.
# LinuxCNC that cannot start here at all (no status from its display
# program) is reported and skipped; anything played wrong fails.
# Exit status 0 = pass (or skipped), 1 = fail.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
if [ -x /usr/bin/linuxcnc ]; then
  L=system
elif [ -r "${LCNC:-$HOME/lcnc-master}/scripts/rip-environment" ]; then
  L=${LCNC:-$HOME/lcnc-master}
else
  echo "skipped (no LinuxCNC: neither /usr/bin/linuxcnc nor ${LCNC:-$HOME/lcnc-master})"
  exit 0
fi
TMP=$(mktemp -d /tmp/fairpath-lcnc-smoke.XXXXXX) || exit 1
trap 'rm -rf "$TMP"' EXIT
STREAM=$TMP/move.txt
/usr/bin/python3 - "$STREAM" <<'EOF'
import sys
# minimum-jerk move x0 -> x0+D in T (peak jerk 60 D/T^3 = 11111 mm/s^3)
x0, y0, z0, D, T, dt = 12.5, -3.25, 7.0, 5.0, 0.3, 0.001
n = round(T / dt)
with open(sys.argv[1], "w") as f:
    for k in range(n + 1 + 20):
        u = min(k, n) / n
        x = x0 + D * (10 * u**3 - 15 * u**4 + 6 * u**5)
        f.write("%.9f %.9f %.9f\n" % (x, y0, z0))
EOF
RUNDIR=${FAIRPATH_LCNC_RUN:-/tmp/fairpath-lcnc-smoke}
OUT=$(FAIRPATH_LCNC_RUN=$RUNDIR "$HERE/play-stream.sh" -L "$L" -c "$TMP/run.csv" -t 60 "$STREAM" | tail -1)
echo "play-stream.sh -L $L: $OUT"
if [ ! -s "$RUNDIR/status.json" ]; then
  echo "skipped: LinuxCNC did not start here (no $RUNDIR/status.json; see $RUNDIR/linuxcnc.log)"
  tail -5 "$RUNDIR/linuxcnc.log" 2>/dev/null
  exit 0
fi
/usr/bin/python3 - "$STREAM" "$TMP/run.csv" "$OUT" <<'EOF'
import re
import sys

import numpy as np

S = np.loadtxt(sys.argv[1])
d = dict(re.findall(r"(\w+)=(\S+)", sys.argv[3]))
fails = []
if d.get("status") != "ok":
    fails.append("status=%s" % d.get("status"))
if d.get("underruns") != "0":
    fails.append("underruns=%s" % d.get("underruns"))
if d.get("played") != str(len(S)):
    fails.append("played=%s of %d lines" % (d.get("played"), len(S)))
moved = np.nonzero(np.any(np.abs(np.diff(S[:, :3], axis=0)) > 1e-9, axis=1))[0]
moving = int(moved[-1] - moved[0] + 1)
try:
    cycles = int(d.get("cycles", "NA"))
    if abs(cycles - moving) > 1:
        fails.append("cycles=%d, stream moves in %d lines" % (cycles, moving))
except ValueError:
    fails.append("cycles=%s" % d.get("cycles"))
try:
    R = np.genfromtxt(sys.argv[2], delimiter=",", names=True)
    m = R["line"] >= 0
    L = R["line"][m].astype(int)
    Q = np.stack([R["x"][m], R["y"][m], R["z"][m]], axis=1)
    diff = float(np.abs(Q - S[L, :3]).max())
    if len(L) < moving or diff >= 1e-6:
        fails.append("positions: %d lines compared, max |diff| %.3g mm" % (len(L), diff))
    else:
        print("positions: %d lines compared, max |diff| %.3g mm" % (len(L), diff))
except (OSError, ValueError, IndexError) as ex:
    fails.append("no samples CSV (%s)" % ex)
if fails:
    print("FAIL: " + "; ".join(fails))
    sys.exit(1)
print("ok: cycles=%s moving=%d" % (d["cycles"], moving))
EOF
# shellcheck disable=SC2181
[ $? -eq 0 ] || exit 1

# fairpath's own stream of a bundled example, against the targets.
ROOT=$(cd "$HERE/../.." && pwd)
FP=${FAIRPATH_BIN:-}
[ -n "$FP" ] || for c in "$ROOT/target/release/fairpath" "$ROOT/target/debug/fairpath"; do
  [ -x "$c" ] && { FP=$c; break; }
done
if [ -z "$FP" ]; then
  echo "fairpath stream: skipped (no fairpath binary; cargo build first)"
  exit 0
fi
PROG=$ROOT/examples/zigzag.ngc
"$FP" stream "$PROG" --tolerance 0.05mm --override-feed -o "$TMP/zigzag.txt" > "$TMP/zigzag.out" || {
  cat "$TMP/zigzag.out"; echo "FAIL: fairpath stream"; exit 1; }
PLANNED=$(sed -n 's/.*planned time: *\([0-9.eE+-]*\) *s.*/\1/p' "$TMP/zigzag.out" | head -1)
# One playback through LinuxCNC and its check; status 1 when it misses.
play_zigzag() {
OUT=$(FAIRPATH_LCNC_RUN=$RUNDIR "$HERE/play-stream.sh" -L "$L" -r "$PROG" -t 60 "$TMP/zigzag.txt" | tail -1)
echo "fairpath stream of zigzag.ngc (planned $PLANNED s), play-stream.sh -L $L: $OUT"
/usr/bin/python3 - "$OUT" "$PLANNED" <<'EOF'
import re
import sys

d = dict(re.findall(r"(\w+)=(\S+)", sys.argv[1]))
planned = float(sys.argv[2])
A, J, TOL, T = 4000.0, 20000.0, 0.05, 0.001
fails = []
try:
    if d.get("status") != "ok":
        fails.append("status=%s" % d.get("status"))
    if abs(int(d["cycles"]) * T - planned) > 2 * T:
        fails.append("executed %s s, planned %s s" % (d["seconds"], planned))
    if float(d["jerk5"]) > 1.05 * J:
        fails.append("jerk5=%s > 1.05 J" % d["jerk5"])
    if float(d["acc"]) > 1.02 * A:
        fails.append("acc=%s > 1.02 A" % d["acc"])
    if float(d["max_dev"]) > TOL:
        fails.append("max_dev=%s > %s" % (d["max_dev"], TOL))
except (KeyError, ValueError) as ex:
    fails.append("missing %s" % ex)
if fails:
    print("FAIL: " + "; ".join(fails))
    sys.exit(1)
print("ok: the stream as executed meets its targets")
EOF
}
# The same text is played a second time where the first playback misses:
# on this VM LinuxCNC's playback once jumped 5 mm for one period (a 5,000
# mm/s spike, the path 10 mm longer) with a stream that played right before
# and after (docs/ci-times.md, b394e51). A miss that does not repeat is
# printed as the player's glitch; one that repeats fails.
play_zigzag && exit 0
echo "the playback missed; played again (a miss that repeats fails)"
play_zigzag && { echo "ok on the second playback: the first was LinuxCNC's glitch"; exit 0; }
exit 1
