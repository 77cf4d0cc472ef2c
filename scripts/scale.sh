#!/usr/bin/env bash
# Issue 19, item 6: how `fairpath smooth` scales. For each program and
# method: wall seconds, CPU seconds (user + system: on a shared machine
# the steadier figure), peak RSS (MB), the ratios of seconds to method
# `none` (read, verify, plan, write, re-read and check, geometry
# unchanged) in wall and in CPU seconds, and the targets (on wall
# seconds): bspline-corner within 3x of none, auto within 10x, peak RSS
# under 20x the input file's size (judged on inputs of 1 MB and more, and
# times where none takes at least 0.5 s: below that the process's fixed
# cost decides).
# Usage: scripts/scale.sh [TOLERANCE] [PROGRAM...]
#   (default 0.05 mm on surface-raster-large.ngc and a few other shared
#   programs; build first: cargo build --release -p fairpath-cli;
#   FAIRPATH_BIN=path times another build)
set -u
cd "$(dirname "$0")/.."
tol=${1:-0.05}; shift || true
P=../shared/paths
progs=("$@")
if [ ${#progs[@]} -eq 0 ]; then
  progs=($P/synthetic/surface-raster-large.ngc $P/synthetic/surface-raster.ngc
    $P/linuxcnc/performance/{contour,LHchips4,Cereal}.ngc $P/gcode-rs/makerblock_tinycnc.gcode)
fi
methods=(none bspline-corner auto arc-fit)
bin=${FAIRPATH_BIN:-target/release/fairpath}
[ -x "$bin" ] || { echo "build first: cargo build --release -p fairpath-cli" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
printf '%-28s %-15s %8s %8s %8s %7s %7s %7s %s\n' program method wall_s cpu_s rss_mb x_none x_cpu rss/in targets
for f in "${progs[@]}"; do
  [ -f "$f" ] || { echo "$(basename "$f"): not found" >&2; continue; }
  size=$(stat -c %s "$f")
  none_s=; none_cpu=
  for m in "${methods[@]}"; do
    if ! /usr/bin/time -f '%e %U %S %M' -o "$tmp/t" "$bin" smooth "$f" --tolerance "$tol" \
        --method "$m" -o "$tmp/out.ngc" >/dev/null 2>"$tmp/err"; then
      printf '%-28s %-15s failed: %s\n' "$(basename "$f" | cut -c1-28)" "$m" "$(tail -1 "$tmp/err")"
      continue
    fi
    read -r wall user sys kb < <(tail -1 "$tmp/t")
    [ "$m" = none ] && none_s=$wall && none_cpu=$(python3 -c "print($user + $sys)")
    python3 - "$f" "$m" "$wall" "$user" "$sys" "$kb" "$size" "${none_s:-}" "${none_cpu:-}" <<'PY'
import os, sys
f, m, wall, user, sys_, kb, size, none_s, none_cpu = sys.argv[1:]
wall, cpu, mb = float(wall), float(user) + float(sys_), int(kb) / 1024
ratio = wall / float(none_s) if none_s and float(none_s) > 0 else float("nan")
cpu_ratio = cpu / float(none_cpu) if none_cpu and float(none_cpu) > 0 else float("nan")
rss_in = int(kb) * 1024 / int(size)
limit = {"bspline-corner": 3.0, "auto": 10.0}.get(m)
ok = []
if limit is not None:
    if none_s and float(none_s) >= 0.5:
        ok.append(f"time {'ok' if ratio <= limit else 'MISSED'} (<= {limit:g}x)")
    else:
        ok.append("time n/a")
ok.append(f"rss {'ok' if rss_in < 20 else 'MISSED'}" if int(size) >= 1 << 20 else "rss n/a")
print(f"{os.path.basename(f)[:28]:28} {m:15} {wall:8.2f} {cpu:8.2f} {mb:8.1f} {ratio:7.2f} {cpu_ratio:7.2f} {rss_in:7.1f} {', '.join(ok)}")
PY
  done
done
