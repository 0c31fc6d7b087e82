#!/usr/bin/env bash
# The tracking benchmark in one command (issue 5): builds tracking_bench, runs the pass matrix and
# the time-scale sweep through the stock rotctld + backend + emulator, then draws the plots into
# docs/img/ and the tables into build-bench/bench/out/tables.md (pasted into docs/benchmarks.md).
#
#   ./scripts/benchmark.sh
# Environment: BIRDCAGE_BENCH_SCALE (matrix time scale, default 5), BIRDCAGE_BENCH_JOBS (runs in
# parallel, default 8), BIRDCAGE_BENCH_BUILD (build dir, default build-bench),
# BIRDCAGE_BENCH_ARGS (extra tracking_bench arguments for the matrix, e.g. "--passes iss-85").
# About 10 minutes of wall time on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."

BIRDCAGE_SETUP_EXTRA="python3-sgp4 python3-matplotlib python3-numpy ${BIRDCAGE_SETUP_EXTRA:-}" ./scripts/setup.sh

build=${BIRDCAGE_BENCH_BUILD:-build-bench}
scale=${BIRDCAGE_BENCH_SCALE:-5}
jobs=${BIRDCAGE_BENCH_JOBS:-8}
out=$build/bench/out

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j2 --target tracking_bench
bench=$build/bench/tracking_bench
rm -rf "$out"

# The matrix: every pass x variant x mode x client threshold, at one time scale.
# shellcheck disable=SC2086
"$bench" --scale "$scale" --jobs "$jobs" --out "$out/matrix" ${BIRDCAGE_BENCH_ARGS:-}

# What the time scale distorts (the backend's worker runs on real time): one pass segment at
# several scales, down to real time, two rigs at a time so latency is measured on a quiet machine.
for k in 1 5 10; do
    "$bench" --passes iss-70 --variants g2,hal205 --modes none --thresholds 0.5 --window 120 \
        --scale "$k" --jobs 2 --out "$out/scale-$k"
done

/usr/bin/python3 bench/plot.py "$out" docs/img
