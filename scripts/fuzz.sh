#!/usr/bin/env bash
# Runs the mutational fuzz test (crates/fairpath-gcode/tests/fuzz.rs) in
# release for a given time and prints the count of inputs tried.
#
#   scripts/fuzz.sh [SECONDS] [SEED]
#
# SECONDS defaults to 600; SEED (decimal or 0x hex) to one from the clock,
# printed at the start so a run can be repeated. Failing inputs are written
# under target/release/../tmp/fuzz (the path is printed); replay one with
#   FAIRPATH_FUZZ_INPUT=FILE cargo test -p fairpath-gcode --test integration fuzz::mutated -- --nocapture
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
seed="${2:-$(date +%s)}"
FAIRPATH_FUZZ_SECONDS="$seconds" FAIRPATH_FUZZ_SEED="$seed" \
    exec cargo test --release -p fairpath-gcode --test integration -- --nocapture \
    fuzz::mutated_programs_and_json_never_panic
