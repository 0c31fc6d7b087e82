#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The tracking benchmark in one command (docs/benchmarks.md): builds tracking_bench, runs the pass
# matrix, the azimuth-mapping runs, the real-time subset and the time-scale sweep through the stock
# rotctld + backend + emulator, then draws the plots into docs/img/ and the tables into
# build-bench/bench/out/tables.md (pasted into docs/benchmarks.md).
# Every run passes `-C time_scale=k` to rotctld, so the backend's clock follows the emulator's.
#
#   ./scripts/benchmark.sh
# Environment:
#   BIRDCAGE_BENCH_SCALE        matrix time scale (default 5)
#   BIRDCAGE_BENCH_JOBS         matrix runs in parallel (default 8)
#   BIRDCAGE_BENCH_BUILD        build directory (default build-bench)
#   BIRDCAGE_BENCH_MODES        pointing modes of the matrix (default none,predictive,auto,oracle: auto is
#                               what a user gets with `pointing` unset; leapfrog can be added)
#   BIRDCAGE_BENCH_ARGS         extra tracking_bench arguments for the matrix, e.g.
#                               "--passes iss-85 --variants g2 --modes none,predictive --thresholds 0.5"
#   BIRDCAGE_BENCH_CLIENT_LIMITS the matrix's client rotator limits (tracking_bench --client-limits,
#                               default dish,wide: the dish's EL range, then EL 0-90)
#   BIRDCAGE_BENCH_MAPPING_ARGS the azimuth-mapping runs (empty: none; default below)
#   BIRDCAGE_BENCH_REALTIME_ARGS the real-time (k = 1) subset (empty: none; default below)
#   BIRDCAGE_BENCH_SWEEP_SCALES time scales of the sweep (default "1 5 10"; empty: no sweep)
#   BIRDCAGE_BENCH_SWEEP_MODES  pointing modes of the sweep (default none,predictive)
#   BIRDCAGE_BENCH_SWEEP_ARGS   extra tracking_bench arguments for every sweep run
#   BIRDCAGE_BENCH_IMG          where the PNGs go (default docs/img)
# Wall time on 2 cores: with dish limits only, the matrix (126 runs: 9 passes x 2 dishes x 3 modes x
# 2 thresholds, plus one oracle run per pass and dish) and the mapping runs (32) took 29 min, the
# real-time subset (30 runs at once) 10 min, the sweep (12 runs) ~8 min: about 45 minutes. Both
# limit settings double the matrix's non-oracle runs (234: 9 x 2 x 3 x 2 x 2 limit settings, plus
# the 18 oracle runs). Measured at 89ccdd3 with both: the matrix 47 min, the mapping runs 11, the
# real-time subset (42 runs) 12, the sweep 5: 69 minutes in all.
set -euo pipefail
cd "$(dirname "$0")/.."

BIRDCAGE_SETUP_EXTRA="python3-sgp4 python3-matplotlib python3-numpy ${BIRDCAGE_SETUP_EXTRA:-}" ./scripts/setup.sh

build=${BIRDCAGE_BENCH_BUILD:-build-bench}
scale=${BIRDCAGE_BENCH_SCALE:-5}
jobs=${BIRDCAGE_BENCH_JOBS:-8}
sweep_scales=${BIRDCAGE_BENCH_SWEEP_SCALES-1 5 10}
sweep_modes=${BIRDCAGE_BENCH_SWEEP_MODES:-none,predictive}
# The matrix runs under both rotator limits a Gpredict user may set (docs/benchmarks.md, "What runs");
# the other parts keep the dish's limits, as README sets Gpredict up.
client_limits=${BIRDCAGE_BENCH_CLIENT_LIMITS:-dish,wide}
matrix_modes=${BIRDCAGE_BENCH_MODES:-none,predictive,auto,oracle}
# The north-crossing passes (both directions) and the forced-unwind ones, under the two other ways a
# firmware may map an azimuth target onto its travel (the matrix runs the emulator's default).
mapping_args=${BIRDCAGE_BENCH_MAPPING_ARGS-"--passes iss-45,iss-60,iss-85,sso-70 --modes none,predictive --thresholds 0.5 --mappings literal,wrap_manager"}
# Real time (k = 1): does the k = 5 matrix hold? One pass of each kind that matters: a north
# crossing both dishes can hold (iss-45), one only the Trav'ler can (iss-60), one only the G2 can
# (sso-70). Real-time runs use little CPU (all 30 took 17 s of it), so they run at once.
realtime_args=${BIRDCAGE_BENCH_REALTIME_ARGS-"--passes iss-45,iss-60,sso-70 --modes none,predictive,auto,oracle --thresholds 0.5,5 --jobs 42"}
images=${BIRDCAGE_BENCH_IMG:-docs/img}
out=$build/bench/out

cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j2 --target tracking_bench
bench=$build/bench/tracking_bench
rm -rf "$out"

# The matrix: every pass x variant x pointing mode x client threshold x client limits, at one time
# scale.
# shellcheck disable=SC2086
"$bench" --scale "$scale" --jobs "$jobs" --out "$out/matrix" --client-limits "$client_limits" --modes "$matrix_modes" ${BIRDCAGE_BENCH_ARGS:-}

if [ -n "$mapping_args" ]; then
    # shellcheck disable=SC2086
    "$bench" --scale "$scale" --jobs "$jobs" --out "$out/mappings" $mapping_args
fi
if [ -n "$realtime_args" ]; then
    # shellcheck disable=SC2086
    "$bench" --scale 1 --out "$out/realtime" $realtime_args
fi

# Whether the time scale still distorts anything now that the backend is scaled too: one pass
# segment at several scales, down to real time, two rigs at a time so latency is measured on a
# quiet machine.
for k in $sweep_scales; do
    # shellcheck disable=SC2086
    "$bench" --passes iss-70 --variants g2,hal205 --modes "$sweep_modes" --thresholds 0.5 --window 120 \
        --scale "$k" --jobs 2 --out "$out/scale-$k" ${BIRDCAGE_BENCH_SWEEP_ARGS:-}
done

/usr/bin/python3 bench/plot.py "$out" "$images"
