#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The main job on the emulator, no hardware needed: for each dish variant, start the dish emulator
# on a pseudo-terminal, start the distribution's stock rotctld with the Winegard backend preloaded,
# and drive it with the stock rotctl client, printing what the dish does; then print the commands
# that run the TUI, the MCP server and the probe against an emulated dish (docs/usage.md).
#
#   ./scripts/demo.sh [variant ...]        variants: hal000 hal205 pro carryout2003 g2 (default: all)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
# What the demo runs (the backend and the emulator) and the programs its next steps name (the TUI,
# the probe, and the sky scan the TUI launches), not the test suite; the first time this compiles
# the core from scratch, a few minutes on 2 cores, so the compiler's progress is shown.
"$root/scripts/setup.sh"
[[ -f "$build/CMakeCache.txt" ]] || cmake -S "$root" -B "$build" -DBIRDCAGE_WERROR=ON >/dev/null
echo "== Building the backend, the emulator, the TUI and the probe (the first time takes a few minutes)"
if ! cmake --build "$build" -j "$(nproc)" --target hamlib-winegard birdcage-sim birdcage-tui birdcage-probe \
    birdcage-skyscan 2>&1 | tee "$build/demo-build.log" |
    { grep --line-buffered -E '^\[ *[0-9]+%\] (Building|Linking)' || true; }; then
    echo "demo: the build failed; the end of its log ($build/demo-build.log):" >&2
    tail -n 30 "$build/demo-build.log" >&2
    exit 1
fi

lib="$build/src/hamlib/libhamlib-winegard.so"
sim="$build/sim/birdcage-sim"
time_scale=${BIRDCAGE_DEMO_TIME_SCALE:-4}
variants=("$@")
((${#variants[@]})) || variants=(hal000 hal205 pro carryout2003 g2)

declare -A model=([hal000]=90101 [hal205]=90102 [pro]=90103 [carryout2003]=90104 [g2]=90105)
work=$(mktemp -d /tmp/birdcage-demo.XXXXXX)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"

echo "== Models the backend adds to the stock rotctl ($(rotctl --version | head -1)):"
LD_PRELOAD="$lib" rotctl -l | awk 'NR==1 || /Winegard/'

for v in "${variants[@]}"; do
    m=${model[$v]:?unknown variant $v}
    dev="$work/$v.tty"
    port=$(free_port 4540 4599)
    echo
    echo "== $v: emulated dish on $dev (time x$time_scale), rotctld -m $m -C time_scale=$time_scale on 127.0.0.1:$port"
    "$sim" --variant "$v" --link "$dev" --time-scale "$time_scale" --az 100 --el 30 >"$work/$v.sim.log" 2>&1 &
    pids+=($!)
    wait_for 10 test -e "$dev"
    # The backend's clock and polling must run at the emulated dish's pace (conf time_scale).
    LD_PRELOAD="$lib" rotctld -m "$m" -r "$dev" -C "time_scale=$time_scale" -T 127.0.0.1 -t "$port" >"$work/$v.rotctld.log" 2>&1 &
    pids+=($!)
    if ! wait_for_listener 60 "$port" "${pids[-1]}"; then
        echo "rotctld did not start; its log:"; cat "$work/$v.rotctld.log"; exit 1
    fi
    rc() { rotctl -m 2 -r "127.0.0.1:$port" "$@"; }
    # All of `_`: through Hamlib's NET rotator (rotctl -m 2) only its first 63 characters arrive.
    info() {
        local line
        exec 3<>"/dev/tcp/127.0.0.1/$port"
        printf '_\n' >&3
        IFS= read -r -t 10 line <&3 || line="(no answer)"
        exec 3>&-
        printf '%s\n' "$line"
    }
    # The 2003 Carryout cannot report its position at rest: p is an error until a move has run.
    pos() {
        local out
        out=$(rc p 2>/dev/null | tr '\n' ' ') || true
        [[ "$out" =~ ^-?[0-9.]+\ -?[0-9.]+\ $ ]] && echo "${out% }" || true
    }
    info | fold -s -w 90 | sed 's/ *$//; 1s/^/info:     /; 2,$s/^/          /'
    p0=$(pos)
    echo "position: ${p0:-unknown (this dish reports its position only while it moves)}"
    echo "command:  P 180 45   (one target: the dish goes there and stops, whatever the pointing mode)"
    rc P 180 45
    last=""
    for _ in $(seq 1 60); do
        now=$(pos)
        [[ -n "$now" && "$now" == "$last" ]] && break   # two equal readings: the dish has arrived
        [[ -n "$now" ]] && printf '  dish at  az %s el %s\n' $now
        last=$now
        sleep 0.25
    done
    before=$(pos)
    echo "command:  P 230 25, then S at once"
    rc P 230 25
    rc S
    sleep 2
    if [[ $v == carryout2003 ]]; then
        # Its one `g` moves both axes, and on this firmware S cannot abort it (docs/firmware.md 8.5).
        echo "stopped:  $(pos)  (from $before: the g in flight, both axes, finishes)"
    else
        echo "stopped:  $(pos)  (from $before: the leg in flight finishes, the rest is dropped)"
    fi
done
echo
echo "demo finished"
echo
# The next steps are docs/usage.md's own commands (tests/docs/from_source.sh runs them as written),
# with this build tree for build/.
commands() {
    doc_block "$root/docs/usage.md" "$1" | sed -e "s#\(^\|[ =]\)build/#\1${build#"$root"/}/#g" -e 's/^/      /'
}
echo "== Next: the TUI, the MCP server and the probe against an emulated G2"
echo "   (docs/usage.md, \"From source, on the emulator\"), from $root, in three terminals:"
echo "   1. the dish:"
commands dish
echo "   2. rotctld with this backend:"
commands rotctld
echo "   3. the position, then the TUI (q quits):"
commands position
commands tui
echo "   The MCP server: docs/mcp.md. The probe needs the pty to itself: stop rotctld (Ctrl-C), then"
commands probe
