#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Bounded libFuzzer run of every fuzz target (clang from Debian): the parsers (framer, replies,
# transcripts) and the console synchroniser with auto-detection. Prints libFuzzer's final stats
# (stat::number_of_executed_units per target); a crash or sanitizer finding in any target fails
# the run, after every target has had its turn.
#   ./scripts/fuzz.sh [seconds-per-target]        (default 30)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_FUZZ_BUILD_DIR:-$root/build-fuzz}
targets=(fuzz_framer fuzz_replies fuzz_transcript fuzz_synchroniser)
BIRDCAGE_SETUP_EXTRA="clang libclang-rt-14-dev" "$root/scripts/setup.sh"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DBIRDCAGE_FUZZ=ON -DBIRDCAGE_WERROR=ON \
    -DBIRDCAGE_FUZZ_SECONDS="${1:-30}" >/dev/null
cmake --build "$build" -j "$(nproc)" >/dev/null
failed=()
for target in "${targets[@]}"; do
    echo "== $target"
    if ! output=$(cmake --build "$build" --target "run_$target" 2>&1); then
        failed+=("$target")
    fi
    grep -E "^(Done|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY)|deadly signal|Test unit written" <<<"$output" || true
done
if ((${#failed[@]} > 0)); then
    echo "fuzz: findings in ${failed[*]} (reproducers: crash-* under $build/tests/fuzz)" >&2
    exit 1
fi
