#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# docs/usage.md, "From source, on the emulator", run as a newcomer would (ctest label `docs`): the
# command blocks marked <!--run:NAME--> are taken from the doc as written and run with this build
# tree for `build/`, a pty path of the test's own and a free port for 4533:
#   dish      the emulated G2 starts and makes its pty;
#   rotctld   the stock rotctld with the backend preloaded listens;
#   position  rotctl p answers two numbers, the emulated dish's 180 45;
#   tui       the TUI, in an 80x24 tmux pane, connects and shows the dish at 180.00 / 45.00, and q
#             quits it with status 0 (this step is skipped without tmux, which scripts/test.sh installs);
#   probe     refused (exit 3, naming rotctld) while rotctld holds the pty, as the doc says; after a
#             Ctrl-C (SIGINT) to rotctld it names the variant (Carryout G2) and reports a pty;
# and the dish, stopped with Ctrl-C too, counted 0 hazardous commands.
#
#   from_source.sh --build BUILD_DIR [--keep]
set -euo pipefail
set -m  # each block in its own process group, as in a terminal, so that SIGINT reaches it like Ctrl-C
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"

build='' keep=0
while (($#)); do
    case $1 in
    --build) build=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "from_source.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
[[ -d $build ]] || { echo "from_source.sh: needs --build BUILD_DIR" >&2; exit 2; }
build=$(cd "$build" && pwd)
doc=$root/docs/usage.md

work=$(mktemp -d /tmp/birdcage-from-source.XXXXXX)
socket=$work/tmux.sock
pids=()
cleanup() {
    tmux -S "$socket" kill-server 2>/dev/null || true
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    if ((keep)); then echo "kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
fail() {
    echo "FAIL: $*"
    for log in "$work"/*.log; do [[ -f $log ]] && { echo "--- $(basename "$log") (tail):"; tail -15 "$log"; }; done
    exit 1
}

port=$(free_port 4800 4899)
# block NAME WORD...: the doc's block NAME with this test's paths and port; each WORD must be in it
# as written, so that a doc that changes a path or the port fails here instead of running elsewhere.
block() {
    local name=$1 text word
    shift
    text=$(doc_block "$doc" "$name")
    [[ -n $text ]] || fail "docs/usage.md has no command block marked <!--run:$name-->"
    for word in "$@"; do
        [[ $text == *"$word"* ]] || fail "docs/usage.md's block $name does not name $word: $text"
    done
    sed -e "s#\(^\|[ =]\)build/#\1$build/#g" -e "s#/tmp/birdcage-g2#$work/g2.tty#g" -e "s#\b4533\b#$port#g" <<<"$text"
}
cd "$work"

dish=$(block dish build/sim/birdcage-sim /tmp/birdcage-g2)
echo "== dish: $dish"
bash -c "$dish" >"$work/dish.log" 2>&1 &
dish_pid=$!
pids+=("$dish_pid")
wait_for 10 test -e "$work/g2.tty" || fail "the emulator made no pty"

rotctld=$(block rotctld build/src/hamlib/libhamlib-winegard.so rotctld /tmp/birdcage-g2 4533)
echo "== rotctld: $rotctld"
bash -c "$rotctld" >"$work/rotctld.log" 2>&1 &
rotctld_pid=$!
pids+=("$rotctld_pid")
wait_for_listener 60 "$port" "$rotctld_pid" || fail "rotctld does not listen on $port"

position=$(block position rotctl 4533)
echo "== position: $position"
answer=$(bash -c "$position" | tr '\n' ' ') || fail "'$position' failed"
[[ $answer == "180.00 45.00 " ]] || fail "rotctl p answered '$answer', not the emulated dish's 180.00 45.00"
echo "   answered: $answer"

tui=$(block tui build/tui/birdcage-tui 4533)
echo "== tui: $tui"
if command -v tmux >/dev/null; then
    screen() { tmux -S "$socket" capture-pane -p -t tui; }
    shows() { screen | grep -qE -- "$1"; }
    tmux -S "$socket" new-session -d -x 80 -y 24 -s tui "TERM=xterm $tui; echo \"birdcage-tui exited \$?\"; sleep 600"
    wait_for 30 shows 'link: connected' || { screen; fail "the TUI never connected"; }
    wait_for 30 shows 'Azimuth +180\.00 deg' || { screen; fail "the TUI does not show the dish's azimuth 180.00"; }
    shows 'Elevation +45\.00 deg' || { screen; fail "the TUI does not show the dish's elevation 45.00"; }
    screen | head -6
    tmux -S "$socket" send-keys -t tui q
    wait_for 10 shows 'birdcage-tui exited 0' || { screen; fail "q did not quit the TUI with status 0"; }
    echo "   connected, showed 180.00 45.00, q quit with status 0"
else
    echo "   SKIPPED: tmux is not installed (scripts/test.sh installs it)"
fi

probe=$(block probe build/tools/birdcage-probe /tmp/birdcage-g2)
echo "== probe while rotctld holds the pty: $probe"
status=0
bash -c "$probe" 2>"$work/probe-refused.log" || status=$?
((status == 3)) || fail "the probe beside a running rotctld exited $status, not 3 (busy)"
grep -q 'is busy: PID [0-9]* (rotctld)' "$work/probe-refused.log" || fail "the refusal does not name rotctld"
echo "   refused: $(head -c 100 "$work/probe-refused.log")..."
kill -INT "$rotctld_pid"  # Ctrl-C in its terminal
wait "$rotctld_pid" 2>/dev/null || true
echo "== probe after Ctrl-C to rotctld: $probe"
bash -c "$probe" 2>"$work/probe.log" || fail "the probe exited $?"
grep -q 'variant: Carryout G2 (identified)' "$work/probe.log" || fail "the probe did not name the Carryout G2"
report=$work/g2-probe.json
grep -q '"variant": {"name": "g2"' "$report" || fail "the report names no g2: $(head -c 400 "$report")"
grep -q '"line": "pty"' "$report" || fail "the report does not say the line is a pty"
echo "   $(grep 'variant:' "$work/probe.log")"

kill -INT "$dish_pid"  # Ctrl-C in its terminal
wait "$dish_pid" 2>/dev/null || true
grep -q 'hazards received: 0$' "$work/dish.log" || fail "the dish counted hazards: $(grep hazards "$work/dish.log")"
echo "ok: docs/usage.md's commands ran as written: rotctld answered p, the TUI showed the dish, the probe named it; 0 hazards"
