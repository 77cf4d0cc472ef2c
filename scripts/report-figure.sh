#!/usr/bin/env bash
# The README's figure of `fairpath report`: the report of
# examples/pocket-corners.ngc with auto and arc-fit at 0.05 mm, rendered by
# headless Chromium (Debian's `chromium`) into docs/report.png (its top:
# the summary and the path). Usage: scripts/report-figure.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build -q --release -p fairpath-cli
command -v chromium >/dev/null || { echo "needs chromium (apt-get install chromium)" >&2; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
target/release/fairpath report examples/pocket-corners.ngc --tolerance 0.05mm \
  --methods auto,arc-fit -o "$tmp/report.html"
chromium --headless --no-sandbox --disable-gpu --hide-scrollbars \
  --window-size=1050,1500 --virtual-time-budget=2000 \
  --screenshot="$PWD/docs/report.png" "file://$tmp/report.html" 2>/dev/null
echo "docs/report.png"
