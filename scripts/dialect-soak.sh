#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Generated consoles on demand: N more seeds of the emulator's dialect generator (sim/README.md,
# "Dialects"), each console met all four ways (own model and 90100, dish up and booting) through
# the stock rotctld with the backend preloaded, as the `dialects` ctest label does for its fixed
# seeds. Prints every failing cell with its seed, the drawn console, the rotctld log and the
# whole console transcript; exit status 1 if any failed.
#
#   scripts/dialect-soak.sh N [START] [VARIANT]
#
# START: the first seed (default: a random one above 100000, printed); VARIANT: hal000, hal205,
# pro, carryout2003 or g2 (default: all five). BIRDCAGE_BUILD_DIR (default build) must hold a
# build with -DBIRDCAGE_BUILD_TESTS=ON; BIRDCAGE_SOAK_JOBS cells run at once (default nproc).
# Re-run one cell: BIRDCAGE_DIALECT_SEEDS=<seed> build/tests/e2e/test_dialects "<cell name>";
# read one console: build/sim/birdcage-sim --variant <v> --dialect describe --seed <seed>.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
[[ $# -ge 1 && $1 =~ ^[1-9][0-9]*$ ]] || { sed -n '8,14s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; exit 2; }
count=$1
start=${2:-$((100000 + (RANDOM << 10) + RANDOM % 1024))}
[[ $start =~ ^[0-9]+$ ]] || { echo "dialect-soak.sh: START must be a whole number" >&2; exit 2; }
variant=${3:-}
case "$variant" in "" | hal000 | hal205 | pro | carryout2003 | g2) ;; *) echo "dialect-soak.sh: unknown variant '$variant'" >&2; exit 2 ;; esac
jobs=${BIRDCAGE_SOAK_JOBS:-$(nproc)}

cmake --build "$build" --target test_dialects birdcage-sim -j "$(nproc)" >/dev/null
binary=$build/tests/e2e/test_dialects
last=$((start + count - 1))
echo "dialect soak: seeds $start..$last, ${variant:-all variants}, four ways each, $jobs at a time"

export BIRDCAGE_DIALECT_SEEDS="$start-$last" BIRDCAGE_DIALECT_ALL_WAYS=1 BIRDCAGE_DIALECT_TRANSCRIPT=full
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# Known-failing cells carry the tag too, so they run here as well.
# (Catch2 exits with the number of tests it listed.)
{ "$binary" "[dialects]${variant:+[$variant]}" --list-test-names-only || true; } | sed '/^$/d' >"$out/cells"
run_cell() {
    local name=$1 file
    file=$2/$(printf '%s' "$name" | tr -c 'A-Za-z0-9' '_').log
    if "$3" "$name" >"$file" 2>&1; then rm -f "$file"; echo "pass  $name"; else echo "FAIL  $name"; fi
}
export -f run_cell
tr '\n' '\0' <"$out/cells" | xargs -0 -P "$jobs" -I{} bash -c 'run_cell "$1" "$2" "$3"' _ {} "$out" "$binary" | tee "$out/summary"

failed=$(grep -c '^FAIL' "$out/summary" || true)
total=$(wc -l <"$out/cells")
echo "dialect soak: $((total - failed)) of $total cells passed"
if [[ $failed -gt 0 ]]; then
    for log in "$out"/*.log; do
        echo "================================================================================"
        cat "$log"
    done
    echo "failing cells (seed in the name):"
    grep '^FAIL' "$out/summary" | sed 's/^FAIL  /  /'
    exit 1
fi
