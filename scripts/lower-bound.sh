#!/usr/bin/env bash
# Usage: scripts/lower-bound.sh [TOLERANCE] [PROGRAM...]
# compare over the dense reference programs (default: the synthetic
# programs but the surface rasters, about 10 minutes on 2 cores; name
# more programs to survey them) and writes docs/lower-bound.md:
# the lower bound, the input's and auto's time, auto/bound, the best
# single method over the bound, and the best curvature-continuous single
# method (bspline-corner, ctm, lotm, bspline-fit, fair: not arc-fit) with
# whether auto is no slower than it, and the bound of paths that follow
# the original in order with auto's time over it where auto's written
# program passes that bound's gates in order (issue 21; "tie" where it is slower by
# at most a millionth: the same geometry with its coordinates rounded
# differently, e.g. square-wave.ngc, where auto writes bspline-corner's
# program and ctm the same transitions). Build first: cargo build
# --release. OUT=FILE writes the table there instead.
set -euo pipefail
cd "$(dirname "$0")/.."
TOL="${1:-0.05mm}"; shift || true
BIN="${FAIRPATH_BIN:-target/release/fairpath}"
SHARED=/work/shared/paths
if [ $# -eq 0 ]; then
  set -- $(ls "$SHARED"/synthetic/*.ngc | grep -v surface-raster)
fi
# A name relative to $SHARED (as the table's header gives them) is taken
# from there.
progs=()
for p in "$@"; do
  if [ ! -e "$p" ] && [ -e "$SHARED/$p" ]; then p="$SHARED/$p"; fi
  progs+=("$p")
done
set -- "${progs[@]}"
ARGS="$TOL"
for p in "$@"; do ARGS="$ARGS ${p#$SHARED/}"; done
OUT=${OUT:-docs/lower-bound.md}
{
  echo "# auto against the lower bound"
  echo
  echo "Generated on $(date -u '+%Y-%m-%d') at commit $(git rev-parse --short HEAD) by \`scripts/lower-bound.sh $ARGS\` (programs under $SHARED; \`fairpath compare --tolerance $TOL --formats arcs --format json\`, default machine). Times in s, of the program each method writes (arcs, the default format), planned as \`simulate\` plans it; the bound is \`feed::lower_bound\` (its module docs give the argument): \"bound\" holds for every path within the tolerance (one-sided, as \`smooth\` verifies; on a closed contour such a path may stay at the start, so there it falls to almost 0), \"in-order bound\" for paths that follow the original in order (\`BandPaths::InOrder\`); \"auto/in-order\" is given where auto's written program passes that bound's gates in order (\`verify::follows_in_order\`), \"no\" where it does not. \"tie\": slower by at most a millionth of the time (the same geometry, its coordinates rounded differently)."
  echo
  echo "| program | bound | in-order bound | input | auto written | auto/bound | auto/in-order bound | best single method written/bound | best C2 method written/bound | auto <= best C2 |"
  echo "|---|---|---|---|---|---|---|---|---|---|"
  for p in "$@"; do
    json=$(timeout 600 "$BIN" compare "$p" --tolerance "$TOL" --formats arcs --format json 2>/dev/null) || { echo "| ${p#$SHARED/} | failed | | | | | | | | |"; continue; }
    echo "$json" | python3 -c '
import json,sys
rows=json.load(sys.stdin); name=sys.argv[1]
b=rows[0]["lower_bound_s"]; bo=rows[0]["lower_bound_in_order_s"]; by={r["method"]:r for r in rows}
def written(r):
    w=[x for x in r.get("written",[]) if x["format"]=="arcs" and x["verified"]]
    return w[0] if w else None
def xb(x):
    # x_bound is null where the bound is 0 (a program of rapids, or of
    # moves too short to bound).
    return "n/a" if x is None else "%.2f" % x
singles=[r for r in rows if r["method"] not in ("original","auto") and written(r)]
best=min(singles,key=lambda r:written(r)["time_s"]) if singles else None
a=written(by["auto"]); o=by["original"]
bs="%s (%s)" % (xb(written(best)["x_bound"]), best["method"]) if best else ""
c2=[r for r in singles if r["method"] in ("bspline-corner","ctm","lotm","bspline-fit","fair")]
bc=min(c2,key=lambda r:written(r)["time_s"]) if c2 else None
cs="%s (%s, %.3f s)" % (xb(written(bc)["x_bound"]), bc["method"], written(bc)["time_s"]) if bc else ""
d=a["time_s"]-written(bc)["time_s"] if bc else 0.0
tb=written(bc)["time_s"] if bc else 0.0
ok=("yes" if d<=0 else "tie (%+.2g s)" % d if d<=1e-6*tb else "no (%+.2g s, %+.2g%%)" % (d, 100*d/tb)) if bc else ""
xo="no" if a.get("follows_in_order") is False else xb(a.get("x_bound_in_order"))
print("| %s | %.3f | %.3f | %.3f | %.3f | %s | %s | %s | %s | %s |" % (name, b, bo, o["time_s"], a["time_s"], xb(a["x_bound"]), xo, bs, cs, ok))
' "${p#$SHARED/}"
  done
} > "$OUT.tmp"
# A table whose every program failed (paths not found, no build) is not
# written over the last good one.
if ! grep -q '^| [^|]* | [0-9]' "$OUT.tmp"; then
  rm -f "$OUT.tmp"
  echo "every program failed (give paths, e.g. $SHARED/synthetic/helix.ngc); $OUT left as it was" >&2
  exit 1
fi
mv "$OUT.tmp" "$OUT"
echo "wrote $OUT"
