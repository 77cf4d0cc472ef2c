#!/usr/bin/env bash
# Hashes of what `fairpath smooth` writes, for every method and format on a
# fixed set of programs: run it before and after a refactoring and diff the two
# lists (a refactoring must not change one byte).
#   scripts/same-output.sh > before.txt   # ... refactor ...
#   scripts/same-output.sh > after.txt && diff before.txt after.txt
# Uses target/release/fairpath (built first). Programs: the bundled examples
# and a spread of ../shared/paths (read in place).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release -p fairpath-cli
bin=${FAIRPATH_BIN:-target/release/fairpath}
shared=${SHARED:-../shared/paths}
files=(examples/*.ngc)
for f in synthetic/butterfly-80.ngc synthetic/noisy-line.ngc synthetic/helix.ngc \
         synthetic/hexagon-3d.ngc synthetic/square-wave.ngc synthetic/adversarial.ngc \
         linuxcnc/quick-tests/single_circle.ngc linuxcnc/quick-tests/square_spiral.ngc \
         linuxcnc/quick-tests/naive_cam_reversal.ngc linuxcnc/quick-tests/long-kink.ngc \
         linuxcnc/quick-tests/linearc-stellabee.ngc linuxcnc/quick-tests/rick_combine.ngc gcode-rs/_slot.ngc; do
  [ -f "$shared/$f" ] && files+=("$shared/$f")
done
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for f in "${files[@]}"; do
  for m in none bspline-corner ctm lotm bspline-fit arc-fit auto; do
    for fmt in arcs g1 g6.2 json; do
      out="$tmp/out.ngc"
      if "$bin" smooth -t 0.05mm -m "$m" -f "$fmt" "$f" -o "$out" >/dev/null 2>"$tmp/err"; then
        echo "$(sha256sum <"$out" | cut -c1-16) $m $fmt $(basename "$f")"
      else
        echo "error($(sed "s|$tmp|TMP|g" "$tmp/err" | head -c 80 | tr '\n' ' ')) $m $fmt $(basename "$f")"
      fi
      rm -f "$out"
    done
  done
done
