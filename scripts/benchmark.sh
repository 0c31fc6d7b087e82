#!/usr/bin/env bash
# The tracking benchmark in one command (issue 5): builds tracking_bench, runs the pass matrix and
# the time-scale sweep through the stock rotctld + backend + emulator, then draws the plots into
# docs/img/ and the tables into build-bench/bench/out/tables.md (pasted into docs/benchmarks.md).
# Every run passes `-C time_scale=k` to rotctld, so the backend's clock follows the emulator's.
#
#   ./scripts/benchmark.sh
# Environment:
#   BIRDCAGE_BENCH_SCALE        matrix time scale (default 5)
#   BIRDCAGE_BENCH_JOBS         matrix runs in parallel (default 8)
#   BIRDCAGE_BENCH_BUILD        build directory (default build-bench)
#   BIRDCAGE_BENCH_ARGS         extra tracking_bench arguments for the matrix, e.g.
#                               "--passes iss-85 --variants g2 --modes none,predictive --thresholds 0.5"
#   BIRDCAGE_BENCH_SWEEP_SCALES time scales of the sweep (default "1 5 10"; empty: no sweep)
#   BIRDCAGE_BENCH_SWEEP_MODES  pointing modes of the sweep (default none,predictive)
#   BIRDCAGE_BENCH_SWEEP_ARGS   extra tracking_bench arguments for every sweep run
#   BIRDCAGE_BENCH_IMG          where the PNGs go (default docs/img)
# About 30 minutes of wall time on 2 cores (112 matrix runs: 96 plus one oracle run per pass and dish; 12 sweep runs).
set -euo pipefail
cd "$(dirname "$0")/.."

BIRDCAGE_SETUP_EXTRA="python3-sgp4 python3-matplotlib python3-numpy ${BIRDCAGE_SETUP_EXTRA:-}" ./scripts/setup.sh

build=${BIRDCAGE_BENCH_BUILD:-build-bench}
scale=${BIRDCAGE_BENCH_SCALE:-5}
jobs=${BIRDCAGE_BENCH_JOBS:-8}
sweep_scales=${BIRDCAGE_BENCH_SWEEP_SCALES-1 5 10}
sweep_modes=${BIRDCAGE_BENCH_SWEEP_MODES:-none,predictive}
images=${BIRDCAGE_BENCH_IMG:-docs/img}
out=$build/bench/out

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j2 --target tracking_bench
bench=$build/bench/tracking_bench
rm -rf "$out"

# The matrix: every pass x variant x pointing mode x client threshold, at one time scale.
# shellcheck disable=SC2086
"$bench" --scale "$scale" --jobs "$jobs" --out "$out/matrix" ${BIRDCAGE_BENCH_ARGS:-}

# Whether the time scale still distorts anything now that the backend is scaled too: one pass
# segment at several scales, down to real time, two rigs at a time so latency is measured on a
# quiet machine.
for k in $sweep_scales; do
    # shellcheck disable=SC2086
    "$bench" --passes iss-70 --variants g2,hal205 --modes "$sweep_modes" --thresholds 0.5 --window 120 \
        --scale "$k" --jobs 2 --out "$out/scale-$k" ${BIRDCAGE_BENCH_SWEEP_ARGS:-}
done

/usr/bin/python3 bench/plot.py "$out" "$images"
