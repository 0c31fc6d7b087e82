#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# What the backend costs while it tracks (a benchmark, not a test; docs/benchmarks.md, "On a
# Raspberry Pi"): Debian's rotctld with the backend preloaded drives an emulated Carryout G2 in
# real time (time scale 1, 115200 baud) while a Gpredict-like client tracks bench/passes/iss-45
# (a `p` and a `P` every second, one connection) for SECONDS seconds. Measured on rotctld, the
# process that runs on the Pi:
#   CPU    utime+stime from /proc/<pid>/stat over the tracking seconds only (not the open);
#   memory VmHWM (peak resident) and VmRSS at the end, from /proc/<pid>/status;
#   instructions per second of tracking: the same run under valgrind's callgrind, its counters
#          zeroed when tracking starts (callgrind_control -z) and dumped when it ends.
#
#   scripts/backend-cost.sh [SECONDS]        (default 60; the callgrind run takes as long again)
# BIRDCAGE_BUILD_DIR: the build with the backend and birdcage-sim (default build/).
# BIRDCAGE_COST_VALGRIND=0 skips the callgrind run.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
seconds=${1:-60}
[[ $seconds =~ ^[1-9][0-9]*$ ]] || { echo "backend-cost: SECONDS must be a positive whole number" >&2; exit 2; }
backend=$build/src/hamlib/libhamlib-winegard.so
sim=$build/sim/birdcage-sim
for f in "$backend" "$sim"; do
    [[ -f $f ]] || { echo "backend-cost: $f is missing (scripts/build.sh --no-tests)" >&2; exit 2; }
done
if [[ ${BIRDCAGE_COST_VALGRIND:-1} != 0 ]]; then BIRDCAGE_SETUP_EXTRA="valgrind ${BIRDCAGE_SETUP_EXTRA:-}" "$root/scripts/setup.sh"; fi

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"
work=$(mktemp -d /tmp/birdcage-cost.XXXXXX)
trap 'stop_servers; rm -rf "$work"' EXIT
pass=$root/bench/passes/iss-45.csv
# Where the pass rises above 20 deg: the dish starts there, so the open does not slew.
read -r az0 el0 < <(awk -F, '/^[0-9]/ && $3 >= 20 { print $2, $3; exit }' "$pass")
tick=$(getconf CLK_TCK)

# run NAME WRAPPER...: the emulated G2 and `WRAPPER... rotctld` with the backend; sets $rotctld_pid and $port.
run() {
    local name=$1
    shift
    local dev=$work/$name.tty
    port=$(free_port 4750 4799)
    "$sim" --variant g2 --link "$dev" --time-scale 1 --az "$az0" --el "$el0" >"$work/$name.sim.log" 2>&1 &
    pids+=($!)
    wait_for 10 test -e "$dev" || { echo "backend-cost: the emulator did not start" >&2; exit 1; }
    LD_PRELOAD=$backend "$@" /usr/bin/rotctld -m 90105 -r "$dev" -s 115200 -T 127.0.0.1 -t "$port" \
        >"$work/$name.rotctld.log" 2>&1 &
    rotctld_pid=$!
    pids+=("$rotctld_pid")
    wait_for_listener 300 "$port" "$rotctld_pid" ||
        { echo "backend-cost: rotctld did not listen" >&2; tail -20 "$work/$name.rotctld.log" >&2; exit 1; }
}
cpu_ticks() { awk '{ print $14 + $15 }' "/proc/$1/stat"; }

say "native: rotctld + backend, emulated G2 in real time, tracking iss-45 for $seconds s"
run native
before=$(cpu_ticks "$rotctld_pid")
start=$EPOCHREALTIME
read -r sent _ < <(track_pass "$port" 1 1 "$seconds" "$pass") || exit 1
end=$EPOCHREALTIME
after=$(cpu_ticks "$rotctld_pid")
hwm=$(awk '/^VmHWM/ { print $2 }' "/proc/$rotctld_pid/status")
rss=$(awk '/^VmRSS/ { print $2 }' "/proc/$rotctld_pid/status")
threads=$(awk '/^Threads/ { print $2 }' "/proc/$rotctld_pid/status")
stop_servers
awk -v b="$before" -v a="$after" -v t="$tick" -v s="$start" -v e="$end" -v n="$sent" -v h="$hwm" -v r="$rss" -v th="$threads" 'BEGIN {
    cpu = (a - b) / t; wall = e - s
    printf "native: %d P over %.1f s: rotctld CPU %.3f s = %.2f ms per second of tracking (%.3f%% of one core); VmHWM %d KiB, VmRSS %d KiB, %d threads\n",
        n, wall, cpu, 1000 * cpu / wall, 100 * cpu / wall, h, r, th }'

if [[ ${BIRDCAGE_COST_VALGRIND:-1} != 0 ]]; then
    say "callgrind: the same, rotctld under valgrind --tool=callgrind"
    out=$work/callgrind.out
    run callgrind valgrind --tool=callgrind --callgrind-out-file="$out.%p" --dump-instr=no
    callgrind_control -z "$rotctld_pid" >/dev/null 2>&1
    start=$EPOCHREALTIME
    read -r sent _ < <(track_pass "$port" 1 1 "$seconds" "$pass") || exit 1
    end=$EPOCHREALTIME
    callgrind_control -d "$rotctld_pid" >/dev/null 2>&1
    # The last dump of the run holds only what ran since the zeroing.
    dump=$(ls -t "$out.$rotctld_pid".* 2>/dev/null | head -1)
    [[ -n $dump ]] || { echo "backend-cost: callgrind wrote no dump" >&2; exit 1; }
    awk -v s="$start" -v e="$end" -v n="$sent" '/^(summary|totals):/ { ir = $2 } END {
        wall = e - s
        printf "callgrind: %d P over %.1f s: %.0f instructions (amd64) = %.2f million per second of tracking\n",
            n, wall, ir, ir / wall / 1e6 }' "$dump"
    echo "callgrind: where they went (inclusive, the top functions of the backend):"
    callgrind_annotate --inclusive=yes "$dump" 2>/dev/null | grep -E "birdcage::" | head -12 | cut -c1-160
fi
