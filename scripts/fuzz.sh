#!/usr/bin/env bash
# Bounded libFuzzer run of every parser target (clang from Debian). Prints libFuzzer's final stats
# (stat::number_of_executed_units per target); a crash or sanitizer finding fails the run.
#   ./scripts/fuzz.sh [seconds-per-target]        (default 30)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_FUZZ_BUILD_DIR:-$root/build-fuzz}
BIRDCAGE_SETUP_EXTRA="clang libclang-rt-14-dev" "$root/scripts/setup.sh"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DBIRDCAGE_FUZZ=ON -DBIRDCAGE_WERROR=ON \
    -DBIRDCAGE_FUZZ_SECONDS="${1:-30}" >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
cmake --build "$build" --target fuzz 2>&1 | grep -E "^(Done|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY)|deadly signal" || true
# The build above fails (set -e) on any finding; reaching here means every target ran clean.
