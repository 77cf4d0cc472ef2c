#!/usr/bin/env bash
# Times every method and format on the small programs of issue 19, item 6,
# whose work once grew with 1/tolerance (inch arcs, a long 3D line after an
# arc, LinuxCNC's 111-byte spiral `sam-circle_lines.ngc`), and the peak
# memory on a comment-heavy program.
#
#   scripts/bounded-work.sh [BINARY] [TIMEOUT_S]
#
# BINARY defaults to target/release/fairpath (build it first with
# `cargo build --release -p fairpath-cli`). A case still running after
# TIMEOUT_S (default 30) seconds is killed and shown as ">TIMEOUT_S".
# COMMENT_MB (default 200) sets the size of the comment-heavy programs;
# COMMENT_MB=0 skips them, TABLES=0 skips the timing tables.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/target/release/fairpath}
limit=${2:-30}
comment_mb=${COMMENT_MB:-200}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT

cat >"$dir/five.ngc" <<'NGC'
G90 G20
G0 X0 Y0
G2 X3 R2 F100
G1 X6.9282 Y-4 Z-3.9167
M2
NGC
cat >"$dir/variant.ngc" <<'NGC'
G90 G20
G0 X0 Y0
G2 X3 R2 F100
G1 Y2
G1 X6.9282 Y-4 Z-3.9167
M2
NGC

# LinuxCNC's quick-tests/sam-circle_lines.ngc: 370 polar moves, a spiral.
cat >"$dir/spiral.ngc" <<'NGC'
g20 g64 g90

g0 z.1
g0 x1 y0
g1 z-.1 f999

o100 repeat [370]
g91 g1 @-.0025 ^4.5
o100 endrepeat

g90 g0 z.1
m2
NGC

tolerances="0.05 0.01 0.005 0.001"
# Seconds of one run, ">limit" when killed, "fail" on another error.
run() {
    local start end rc
    start=$(date +%s.%N)
    timeout "$limit" "$bin" smooth "$@" -o "$dir/out" >/dev/null 2>"$dir/err"
    rc=$?
    end=$(date +%s.%N)
    if [ $rc -eq 124 ]; then
        printf '>%s' "$limit"
    elif [ $rc -ne 0 ]; then
        printf 'fail'
    else
        awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }'
    fi
}

table() {
    local prog=$1 what=$2
    shift 2
    printf '\n%s (%s)\n' "$prog" "$what"
    printf '%-16s' "case"
    for t in $tolerances; do printf '%10s' "$t"; done
    printf '\n'
    for item in "$@"; do
        printf '%-16s' "$item"
        for t in $tolerances; do
            if [ "$what" = methods ]; then
                printf '%10s' "$(run "$dir/$prog" --tolerance "${t}mm" --method "$item")"
            else
                printf '%10s' "$(run "$dir/$prog" --tolerance "${t}mm" --format "$item")"
            fi
        done
        printf '\n'
    done
}

echo "seconds per run of: $bin smooth PROGRAM --tolerance T (--method M | --format F) -o OUT"
methods="auto arc-fit bspline-corner bspline-fit ctm lotm fair"
formats="arcs g1 g5.2 g6.2 json"
[ "${TABLES:-1}" = 0 ] || for prog in five.ngc variant.ngc; do
    # shellcheck disable=SC2086
    table "$prog" methods $methods
    # shellcheck disable=SC2086
    table "$prog" formats $formats
done
# shellcheck disable=SC2086
[ "${TABLES:-1}" = 0 ] || table spiral.ngc methods $methods

if [ "$comment_mb" -gt 0 ]; then
    # Two shapes of comment-heavy program: 100-byte comment lines, and
    # comments of 50 MB each, on a few G1 moves.
    for shape in lines long; do
        big="$dir/comments-$shape.ngc"
        python3 - "$big" "$comment_mb" "$shape" <<'PY'
import sys
path, mb, shape = sys.argv[1], int(sys.argv[2]), sys.argv[3]
size = 100 if shape == "lines" else 50 << 20
line = "(comment " + "x" * (size - 11) + ")\n"
n = mb * (1 << 20) // len(line)
with open(path, "w") as f:
    f.write("G90 G21\nG0 X0 Y0\nG1 X1 F600\n")
    per = max(1, (1 << 20) // len(line))
    for k in range(0, n, per):
        f.write(line * min(per, n - k))
    f.write("G1 X1 Y1\nG1 X2 Y1\nM2\n")
PY
        size_kb=$(($(stat -c %s "$big") / 1024))
        for m in auto arc-fit; do
            if /usr/bin/time -f "%e %M" -o "$dir/time" timeout "$limit" "$bin" smooth "$big" \
                --tolerance 0.05mm --method "$m" -o "$dir/out" >/dev/null 2>&1; then
                read -r secs kb <"$dir/time"
                ratio=$(awk -v k="$kb" -v s="$size_kb" 'BEGIN { printf "%.2f", k / s }')
            else
                secs=">$limit or failed" kb=? ratio=?
            fi
            echo
            echo "comment-heavy program ($shape), $size_kb KB, --method $m:" \
                "$secs s, peak RSS $kb KB ($ratio x the file)"
        done
    done
fi
