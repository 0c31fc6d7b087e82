#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# What the backend costs while it tracks (a benchmark, not a test; docs/benchmarks.md, "On a
# Raspberry Pi"): Debian's rotctld with the backend preloaded drives an emulated Carryout G2 in
# real time (time scale 1, 115200 baud) while a Gpredict-like client tracks bench/passes/iss-45
# (a `p` and a `P` every second, one connection) for SECONDS seconds. Measured on rotctld, the
# process that runs on the Pi:
#   CPU    utime+stime from /proc/<pid>/stat over the tracking seconds only (not the open), and
#          per minute of tracking (its last minute over its first: whether the cost grows);
#   memory VmHWM (peak resident) and VmRSS at the end, from /proc/<pid>/status;
#   instructions per second of tracking: the same run under valgrind's callgrind, its counters
#          zeroed when tracking starts (callgrind_control -z) and dumped every minute and at the
#          end (each dump holds what ran since the last), with the share of a Pi 3's core that
#          predicts (the slowest: 0.7 billion instructions/s, AArch64 30% above amd64's count).
#
#   scripts/backend-cost.sh [SECONDS]        (default 60; the callgrind run takes as long again)
# BIRDCAGE_BUILD_DIR: the build with the backend and birdcage-sim (default build/).
# BIRDCAGE_COST_VALGRIND=0 skips the callgrind run, BIRDCAGE_COST_NATIVE=0 the native one.
# BIRDCAGE_COST_PASS: the pass (default bench/passes/iss-45.csv); BIRDCAGE_COST_MIN_EL: tracked
# from where it rises above this (default 20; 0: from AOS, as Gpredict with Min El 0 does, which
# makes iss-45 a 10-minute pass: `BIRDCAGE_COST_MIN_EL=0 scripts/backend-cost.sh 600`).
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
pass=${BIRDCAGE_COST_PASS:-$root/bench/passes/iss-45.csv}
min_el=${BIRDCAGE_COST_MIN_EL:-20}
# Where the pass rises above min_el: the dish starts there (or on its elevation floor, which the
# emulator clamps to), so the open does not slew.
read -r az0 el0 < <(awk -F, -v m="$min_el" '/^[0-9]/ && $3 >= m { print $2, $3; exit }' "$pass")
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
# every_minute FILE COMMAND...: runs COMMAND every 60 s of tracking, each line of its output to FILE
# after the minute's number, until killed; sets $ticker_pid.
every_minute() {
    local file=$1
    shift
    (
        minute=0
        while sleep 60; do
            minute=$((minute + 1))
            echo "$minute $("$@")" >>"$file"
        done
    ) &
    ticker_pid=$!
}
# per_minute_ratio FILE UNIT: the ratio of the last whole minute to the first, from FILE's "MINUTE VALUE"
# lines (VALUE: that minute's amount of UNIT).
per_minute_ratio() {
    awk -v unit="$2" '{ v[$1] = $2; n = $1 } END {
        if (n < 2) { print "per minute: fewer than two whole minutes"; exit }
        printf "per minute: last (%d) over first: %.2fx (%s)\n", n, v[n] / v[1], unit }' "$1"
}

if [[ ${BIRDCAGE_COST_NATIVE:-1} != 0 ]]; then
say "native: rotctld + backend, emulated G2 in real time, tracking $(basename "$pass" .csv) from $min_el deg for $seconds s"
run native
before=$(cpu_ticks "$rotctld_pid")
start=$EPOCHREALTIME
ticks=$work/native.minutes
every_minute "$ticks" cpu_ticks "$rotctld_pid"
read -r sent _ < <(track_pass "$port" 1 1 "$seconds" "$pass" "$min_el") || exit 1
end=$EPOCHREALTIME
after=$(cpu_ticks "$rotctld_pid")
kill "$ticker_pid" 2>/dev/null || true
hwm=$(awk '/^VmHWM/ { print $2 }' "/proc/$rotctld_pid/status")
rss=$(awk '/^VmRSS/ { print $2 }' "/proc/$rotctld_pid/status")
threads=$(awk '/^Threads/ { print $2 }' "/proc/$rotctld_pid/status")
stop_servers
awk -v b="$before" -v a="$after" -v t="$tick" -v s="$start" -v e="$end" -v n="$sent" -v h="$hwm" -v r="$rss" -v th="$threads" 'BEGIN {
    cpu = (a - b) / t; wall = e - s
    printf "native: %d P over %.1f s: rotctld CPU %.3f s = %.2f ms per second of tracking (%.3f%% of one core); VmHWM %d KiB, VmRSS %d KiB, %d threads\n",
        n, wall, cpu, 1000 * cpu / wall, 100 * cpu / wall, h, r, th }'
# Each minute's CPU from the running totals.
awk -v b="$before" -v t="$tick" '{ printf "%d %.1f\n", $1, 1000 * ($2 - b) / t / 60; b = $2 }' "$ticks" >"$ticks.ms"
awk '{ printf "native: minute %d: %.1f ms CPU per second of tracking\n", $1, $2 }' "$ticks.ms"
per_minute_ratio "$ticks.ms" "rotctld CPU, /proc"
fi
if [[ ${BIRDCAGE_COST_VALGRIND:-1} != 0 ]]; then
    say "callgrind: the same, rotctld under valgrind --tool=callgrind"
    out=$work/callgrind.out
    run callgrind valgrind --tool=callgrind --callgrind-out-file="$out.%p" --dump-instr=no
    callgrind_control -z "$rotctld_pid" >/dev/null 2>&1
    start=$EPOCHREALTIME
    # A dump zeroes the counters: each holds one minute, the last one the rest of the run.
    every_minute /dev/null callgrind_control -d "$rotctld_pid" 2>/dev/null
    # Under valgrind rotctld's threads take turns: a fit that runs long delays the answer to `p`.
    # Counted up to there all the same.
    read -r sent _ < <(track_pass "$port" 1 1 "$seconds" "$pass" "$min_el") ||
        echo "backend-cost: the client gave up under callgrind (above); what ran until then is counted" >&2
    end=$EPOCHREALTIME
    kill "$ticker_pid" 2>/dev/null || true
    callgrind_control -d "$rotctld_pid" >/dev/null 2>&1
    # The dumps of the run, oldest first (numbered from 1 by callgrind).
    mapfile -t dumps < <(ls -v "$out.$rotctld_pid".* 2>/dev/null)
    ((${#dumps[@]})) || { echo "backend-cost: callgrind wrote no dump" >&2; exit 1; }
    irs=$work/callgrind.minutes
    minute=0
    for dump in "${dumps[@]}"; do
        minute=$((minute + 1))
        echo "$minute $(awk '/^(summary|totals):/ { ir = $2 } END { print ir + 0 }' "$dump")" >>"$irs"
    done
    awk -v s="$start" -v e="$end" -v n="$sent" '{ ir += $2 } END {
        wall = e - s
        printf "callgrind: %d P over %.1f s: %.0f instructions (amd64) = %.2f million per second of tracking\n",
            n, wall, ir, ir / wall / 1e6 }' "$irs"
    # The last dump is a part minute: only whole ones are compared and predicted.
    last_whole=$(awk -v s="$start" -v e="$end" 'BEGIN { print int((e - s) / 60) }')
    awk -v w="$last_whole" '$1 <= w { printf "callgrind: minute %d: %.2f million instructions per second of tracking: a Pi 3 core (0.7 billion/s, AArch64 +30%%) %.2f%% busy\n",
        $1, $2 / 60 / 1e6, 100 * $2 / 60 * 1.3 / 0.7e9 }' "$irs"
    awk -v w="$last_whole" '$1 <= w' "$irs" >"$irs.whole"
    per_minute_ratio "$irs.whole" "instructions, callgrind"
    echo "callgrind: where they went (inclusive, the top functions of the backend, last dump):"
    callgrind_annotate --inclusive=yes "${dumps[-1]}" 2>/dev/null | grep -E "birdcage::" | head -12 | cut -c1-160
fi
