#!/usr/bin/env bash
# Usage: scripts/output-diff.sh OLD_BIN NEW_BIN [MAX_KB]
# What a change does to the programs `fairpath smooth` writes: both
# binaries smooth every program of ../shared/paths under MAX_KB (default
# 30) with each of METHODS (default "fair auto bspline-fit") at each of
# TOLS (default "0.05 0.01"), two cases at a time. Prints, as Markdown,
# every case whose written program differs (hash of the bytes) with its
# written time (the summary's "planned time ... written") and wall seconds
# before and after, then the totals: cases, differing, written faster,
# slower, and the wall seconds of each binary (a busy host inflates both
# alike; CPU is not measured). EXTRA: more arguments for both (e.g.
# EXTRA=--override-feed).
set -euo pipefail
old=${1:?old binary}
new=${2:?new binary}
max_kb=${3:-30}
methods=${METHODS:-fair auto bspline-fit}
tols=${TOLS:-0.05 0.01}
extra=${EXTRA:-}
shared=$(cd "$(dirname "$0")/../../shared/paths" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export old new methods tols extra dir

one() {
    f=$1
    for m in $methods; do
        for t in $tols; do
            line="$(basename "$f") $m $t"
            for b in old new; do
                bin=$old
                [ $b = new ] && bin=$new
                out=$dir/out-$$-$b.ngc
                s=$(date +%s.%N)
                if timeout 600 "$bin" smooth -t "${t}mm" -m "$m" $extra "$f" -o "$out" >"$dir/sum-$$" 2>&1; then
                    h=$(sha256sum <"$out" | cut -c1-12)
                else
                    h=error
                fi
                e=$(date +%s.%N)
                w=$(grep -o "written [0-9.]* s" "$dir/sum-$$" | head -1 | awk '{print $2}')
                line="$line $h ${w:-na} $(awk -v a="$s" -v b="$e" 'BEGIN { printf "%.2f", b - a }')"
                rm -f "$out"
            done
            echo "$line"
        done
    done
}
export -f one

echo "# Output differences"
echo
echo "\`${EXTRA:+EXTRA=$EXTRA }scripts/output-diff.sh $old $new $max_kb\` on $(date -u '+%Y-%m-%d %H:%M') UTC, methods: $methods; tolerances (mm): $tols; programs of ../shared/paths under $max_kb kB."
echo
find "$shared" -type f \( -name "*.ngc" -o -name "*.gcode" -o -name "*.nc" -o -name "*.tap" \) \
    -size -"${max_kb}"k | sort | xargs -P 2 -I{} bash -c 'one "$@"' _ {} >"$dir/rows"
sort "$dir/rows" >"$dir/sorted"
echo "| program | method | tolerance | written before (s) | after (s) | wall before (s) | after (s) |"
echo "|---|---|---|---|---|---|---|"
awk '$4 != $7 { printf "| %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $5, $8, $6, $9 }' "$dir/sorted"
echo
awk '
{ n++; wo += $6; wn += $9 }
$4 != $7 { d++; if ($8 + 0 < $5 + 0) f++; else if ($8 + 0 > $5 + 0) s++ }
END {
    printf "%d cases, %d written differently: %d faster when written, %d slower; wall seconds %.1f before, %.1f after.\n", n, d, f, s, wo, wn
}' "$dir/sorted"
