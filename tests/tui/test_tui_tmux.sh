#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# birdcage-tui driven as a person would, in an 80x24 tmux pane, against the stock rotctld with the
# backend preloaded and the emulated G2 (ctest label `tui`):
#   1. the dashboard shows the dish's position;
#   2. `g`, `200 35`, Enter moves the dish there (rotctl confirms) and the screen shows it;
#   3. another client (rotctl) sends P 120 30; one right-arrow then jogs from there (P 121.00 30.00),
#      not from this screen's old target; `g 999 40` is refused with the range named, nothing sent;
#   3b. the sky screen, in a second birdcage-tui on a rehearsal clock (the bench's iss-45 pass, 20
#      s before it enters the G2's window, at time scale 20): the pass's AOS/LOS as birdcage-track
#      asked directly gives them; `t` tracks it to LOS (`g` refused meanwhile), the screen's dish
#      agrees with rotctl; a second `t` waits for the next pass and `x` ends it: interrupted, the
#      dish stays where it rests;
#   4. at 60x16 the screen says the terminal is too small (need 80x24); at 80x24 the screens return;
#   5. rotctld killed: the screen says it is reconnecting, `g` and `s` answer "not connected", the
#      signal screen shows no RSSI or LNB; rotctld started again on the same port: the screen is
#      connected again and shows the position;
#   6. `q` quits with status 0.
# Every wait polls the pane against a deadline; the emulator runs 20 times faster than a dish.
#
#   test_tui_tmux.sh --tui PROGRAM --sim PROGRAM --backend LIBRARY --track BIRDCAGE_TRACK [--keep]
# BIRDCAGE_PRELOAD_FIRST (a sanitizer runtime) goes before the backend in rotctld's LD_PRELOAD.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"

tui='' sim='' backend='' track='' keep=0
while (($#)); do
    case $1 in
    --tui) tui=$2; shift 2 ;;
    --sim) sim=$2; shift 2 ;;
    --backend) backend=$2; shift 2 ;;
    --track) track=$2; shift 2 ;;
    --keep) keep=1; shift ;;
    *) echo "test_tui_tmux.sh: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
[[ -x $tui && -x $sim && -f $backend && -x $track ]] ||
    { echo "test_tui_tmux.sh: needs --tui, --sim, --backend and --track" >&2; exit 2; }
command -v tmux >/dev/null || { echo "SKIP: tmux is not installed (scripts/test.sh installs it)"; exit 77; }

time_scale=20
work=$(mktemp -d /tmp/birdcage-tui-test.XXXXXX)
socket=$work/tmux.sock
pids=() rotctld_pid=''
cleanup() {
    tmux -S "$socket" kill-server 2>/dev/null || true
    [[ -n $rotctld_pid ]] && kill "$rotctld_pid" 2>/dev/null
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    if ((keep)); then echo "kept: $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

screen() { tmux -S "$socket" capture-pane -p -t tui; }
fail() {
    echo "FAIL: $*"
    echo "--- the screen:"; screen || true
    echo "--- rotctld log (tail):"; tail -20 "$work/rotctld.log" 2>/dev/null || true
    exit 1
}
# wait_screen SECONDS REGEX: until the pane shows a line matching REGEX (extended).
wait_screen() { wait_for "$1" bash -c 'tmux -S "$0" capture-pane -p -t tui | grep -qE -- "$1"' "$socket" "$2"; }
# The numbers the dashboard shows.
shown_position() {
    screen | grep -oE '(Azimuth|Elevation) +-?[0-9.]+ deg' |
        awk '$1 == "Azimuth" { az = $2 } $1 == "Elevation" { el = $2 } END { if (az != "" && el != "") print az, el }'
}
# shows_near AZ EL TOL: the screen's position is within TOL degrees of (AZ, EL) on both axes.
shows_near() {
    local az el
    read -r az el < <(shown_position) || return 1
    awk -v a="$az" -v e="$el" -v ta="$1" -v te="$2" -v t="$3" 'BEGIN { exit !((a - ta) ^ 2 <= t * t && (e - te) ^ 2 <= t * t) }'
}
start_rotctld() {
    LD_PRELOAD="${BIRDCAGE_PRELOAD_FIRST:+$BIRDCAGE_PRELOAD_FIRST:}$backend" ASAN_OPTIONS=detect_leaks=0 \
        /usr/bin/rotctld -m 90105 -r "$work/dish.tty" -T 127.0.0.1 -t "$port" -C time_scale=$time_scale \
        >>"$work/rotctld.log" 2>&1 &
    rotctld_pid=$!
    wait_for 60 bash -c "exec 3<>/dev/tcp/127.0.0.1/$port" || fail "rotctld does not listen on $port"
}

"$sim" --variant g2 --link "$work/dish.tty" --time-scale $time_scale --az 100 --el 30 >"$work/sim.log" 2>&1 &
pids+=($!)
wait_for 10 test -e "$work/dish.tty" || fail "the emulator made no pty"
port=$(free_port 46100 46400)
start_rotctld

# The pane runs a shell line that reports the program's exit status and keeps the pane open, so a
# crash shows on the screen instead of closing it.
tmux -S "$socket" new-session -d -x 80 -y 24 -s tui \
    "TERM=xterm $(printf '%q' "$tui") --host 127.0.0.1 --port $port; echo \"birdcage-tui exited \$?\"; sleep 600"

echo "== 1. the dashboard shows the position (the emulated dish starts at 100 30)"
wait_screen 30 'link: connected' || fail "never connected"
wait_for 30 shows_near 100 30 0.5 || fail "the dashboard does not show ~100 30"
echo "   shown: $(shown_position)"
screen | grep -qE 'Status +' || fail "no status line"
screen | grep -q 'Info (_):' || fail "no _ info"

echo "== 2. g, 200 35, Enter"
tmux -S "$socket" send-keys -t tui g
wait_screen 5 'Go to AZ EL:' || fail "g opened no prompt"
tmux -S "$socket" send-keys -t tui '200 35' Enter
wait_screen 10 'Target +200\.00 +35\.00' || fail "the target 200 35 is not shown"
wait_for 90 shows_near 200 35 0.2 || fail "the screen does not show ~200 35"
echo "   shown: $(shown_position)"
read -r az el <<<"$(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')"
echo "   rotctl p: $az $el"
awk -v a="$az" -v e="$el" 'BEGIN { exit !((a - 200) ^ 2 <= 0.04 && (e - 35) ^ 2 <= 0.04) }' ||
    fail "rotctl says the dish is at $az $el, not 200 35"

echo "== 3. another client moves the dish; a jog starts from where it is; g 999 40 is refused"
rotctl -m 2 -r "127.0.0.1:$port" P 120 30 >/dev/null || fail "rotctl P 120 30 failed"
wait_for 90 shows_near 120 30 0.2 || fail "the screen does not show ~120 30 after the other client's P"
tmux -S "$socket" send-keys -t tui Right
wait_screen 10 'P 12[01]\.[0-9]{2} (29|30)\.[0-9]{2}: ok' || fail "the jog was not sent from the dish's position (120 30)"
wait_for 60 shows_near 121 30 0.2 || fail "the dish did not jog to ~121 30"
tmux -S "$socket" send-keys -t tui g
wait_screen 5 'Go to AZ EL:' || fail "g opened no prompt"
tmux -S "$socket" send-keys -t tui '999 40' Enter
wait_screen 5 'refused: az 999\.00 is outside -?[0-9.]+\.\.[0-9.]+' || fail "g 999 40 was not refused with the range"
read -r az el <<<"$(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')"
awk -v a="$az" -v e="$el" 'BEGIN { exit !((a - 121) ^ 2 <= 0.09 && (e - 30) ^ 2 <= 0.09) }' ||
    fail "after the refused g 999 40 the dish is at $az $el, not 121 30"

echo "== 3b. the sky screen: passes, a track to LOS, a track stopped with x"
# bench/passes/iss-45 at the benchmark's site: in the G2's window (18..65) from 153.5 s to 418 s
# after the TLE's epoch (2024-06-01T00:00:00Z; the CSV's t starts 68 s before it), leaving at
# azimuth 89.1.
sky_args=(--lat 45 --lon -93 --alt 250 --tle "$root/bench/passes/iss-45.tle")
tmux -S "$socket" new-session -d -x 80 -y 24 -s sky \
    "TERM=xterm $(printf '%q ' "$tui" --host 127.0.0.1 --port "$port" --track-program "$track" "${sky_args[@]}" \
        --at 2024-06-01T00:02:13Z --time-scale $time_scale); echo \"birdcage-tui exited \$?\"; sleep 600"
sky_screen() { tmux -S "$socket" capture-pane -p -t sky; }
wait_sky() { wait_for "$1" bash -c 'tmux -S "$0" capture-pane -p -t sky | grep -qE -- "$1"' "$socket" "$2"; }
sky_fail() { echo "--- the sky screen:"; sky_screen || true; fail "$@"; }
wait_sky 30 'link: connected' || sky_fail "the sky TUI never connected"
tmux -S "$socket" send-keys -t sky 5
wait_sky 30 'Up now \(00:0[0-9]:[0-9]{2} UTC\)' || sky_fail "the sky screen shows no answer of birdcage-track --visible"
# The truth: birdcage-track asked directly, on a clock that stands still at the same instant.
truth=$("$track" --host 127.0.0.1 --port "$port" "${sky_args[@]}" --at 2024-06-01T00:02:13Z --time-scale 1e-9 \
    --passes --hours 2 --count 1 --json 'BIRDCAGE ISS-45')
read -r aos los max_el < <(python3 -c 'import json, sys; p = json.loads(sys.argv[1])["passes"][0]
print(p["aos"][11:19], p["los"][11:19], "%.1f" % p["max_el"])' "$truth")
echo "   birdcage-track --passes: AOS $aos LOS $los max el $max_el"
[[ $aos == 00:02:3[34] && $los == 00:06:5[78] ]] || sky_fail "birdcage-track's pass $aos..$los is not the bench's (00:02:33.5..00:06:58)"
tmux -S "$socket" send-keys -t sky p
wait_sky 5 'Passes of:' || sky_fail "p opened no prompt"
tmux -S "$socket" send-keys -t sky C-u 'BIRDCAGE ISS-45' Enter
# The highest elevation comes from a search sampled from the moment asked (44.8..45.0 here):
# the times must agree, the peak to 0.2 deg.
wait_sky 30 "^ +$aos  $los +4[45]\.[0-9] " || sky_fail "the screen's pass is not birdcage-track's ($aos $los)"
shown_max=$(sky_screen | sed -nE "s/^ +$aos  $los +([0-9.]+) .*/\1/p")
awk -v a="$shown_max" -v b="$max_el" 'BEGIN { exit !((a - b) ^ 2 <= 0.04) }' ||
    sky_fail "the screen's highest elevation $shown_max is not birdcage-track's $max_el"
tmux -S "$socket" send-keys -t sky t
wait_sky 5 'Track:' || sky_fail "t opened no prompt"
tmux -S "$socket" send-keys -t sky C-u 'BIRDCAGE ISS-45' Enter
wait_sky 30 'BIRDCAGE ISS-45: tracking, LOS in [0-9]' || sky_fail "the track did not start"
tmux -S "$socket" send-keys -t sky g
wait_sky 5 'Go to AZ EL:' || sky_fail "g opened no prompt"
tmux -S "$socket" send-keys -t sky '200 35' Enter
wait_sky 5 'g refused: tracking BIRDCAGE ISS-45' || sky_fail "g was not refused while tracking"
wait_sky 60 'ended: los, rms [0-9.]+ max [0-9.]+ deg' || sky_fail "the track did not end at LOS"
sky_screen | grep -E 'ended: |BIRDCAGE ISS-45: '
read -r az el <<<"$(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')"
echo "   rotctl p after LOS: $az $el"
awk -v a="$az" -v e="$el" 'BEGIN { exit !((a - 89.1) ^ 2 <= 2.25 && (e - 18) ^ 2 <= 2.25) }' ||
    sky_fail "after LOS the dish is at $az $el, not where the pass left the window (89.1 18)"
read -r shown_az shown_el < <(sky_screen | sed -nE 's/^ dish +az +([-0-9.]+) el +([-0-9.]+).*/\1 \2/p')
# The last sample shown comes up to a second before LOS: 20 s of sky, under 5 deg of this pass's end.
awk -v a="$az" -v e="$el" -v sa="$shown_az" -v se="$shown_el" 'BEGIN { exit !((a - sa) ^ 2 <= 25 && (e - se) ^ 2 <= 25) }' ||
    sky_fail "the screen's last dish position $shown_az $shown_el is not rotctl's $az $el"
tmux -S "$socket" send-keys -t sky t Enter
wait_sky 30 'BIRDCAGE ISS-45: waiting, AOS in' || sky_fail "a second track does not wait for the next pass"
tmux -S "$socket" send-keys -t sky x
wait_sky 30 'ended: interrupted' || sky_fail "x did not end the track as interrupted"
# At rest: two readings a second apart (20 s of sky: a track still sending would move the dish)
# agree (Hamlib 4.5.4's NET rotator, rotctl -m 2, has no status to ask).
still() {
    local first
    first=$(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')
    sleep 1
    [[ $(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ') == "$first" ]]
}
wait_for 30 still || sky_fail "the dish does not come to rest after x"
still || sky_fail "the dish moved after x"
read -r rest_az rest_el <<<"$(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')"
echo "   the dish rests at $rest_az $rest_el after x"
tmux -S "$socket" send-keys -t sky q
wait_sky 10 'birdcage-tui exited 0' || sky_fail "the sky TUI did not quit with status 0"

echo "== 4. a terminal below 80x24"
tmux -S "$socket" resize-window -t tui -x 60 -y 16
wait_screen 5 'terminal too small \(need 80x24, have 60x16\)' || fail "no 'terminal too small' at 60x16"
tmux -S "$socket" resize-window -t tui -x 80 -y 24
wait_screen 5 'link: connected' || fail "the screens did not come back at 80x24"

echo "== 5. rotctld restarts"
kill "$rotctld_pid"
wait "$rotctld_pid" 2>/dev/null || true
rotctld_pid=''
wait_screen 15 'link: RECONNECTING' || fail "the screen does not say it lost rotctld"
wait_screen 15 'retrying in' || fail "the screen does not say it retries"
[[ -z $(shown_position) ]] || fail "a position is shown while rotctld is away"
screen | sed -n '1,3p'
for key in g s; do
    tmux -S "$socket" send-keys -t tui $key
    wait_screen 5 '^not connected: rotctld at ' || fail "'$key' does not answer 'not connected' while rotctld is away"
    tmux -S "$socket" send-keys -t tui 1   # clears the message
done
tmux -S "$socket" send-keys -t tui 3
wait_screen 5 'not connected: no RSSI or LNB reading' || fail "the signal screen does not say it is not connected"
! screen | grep -qE 'RSSI +[0-9]|LNB +1[38] V' || fail "the signal screen shows a dead link's RSSI or LNB"
tmux -S "$socket" send-keys -t tui 1
start_rotctld
wait_screen 60 'link: connected' || fail "not connected again after rotctld came back"
wait_screen 10 'reconnected 1x' || fail "the dashboard does not say it reconnected"
wait_for 30 shows_near "$rest_az" "$rest_el" 0.2 || fail "the position is not shown after the reconnect"
echo "   shown after the restart: $(shown_position)"

echo "== 6. q quits"
tmux -S "$socket" send-keys -t tui q
wait_screen 10 'birdcage-tui exited' || fail "q did not quit"
screen | grep -q 'birdcage-tui exited 0' || fail "birdcage-tui did not exit with status 0"
echo "ok"
