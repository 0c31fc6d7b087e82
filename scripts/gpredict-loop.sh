#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Real Gpredict in the loop: Debian's Gpredict, under Xvfb, tracks a satellite pass with the
# emulated Carryout G2 through the distribution's rotctld and this backend, once per threshold and
# rotator limits setting (in parallel), and reports what it sent, what the dish did, and the pointing
# error.
#
#   scripts/gpredict-loop.sh [--build DIR] [--out DIR] [--thresholds "5 0.5"] [--limits "dish wide"] [--preload LIBS] [--conf KEY=VALUE]... [--check]
#
# --limits: the rotator limits in Gpredict's .rot file, which it clamps every target to: `dish` (the
# default) = the G2's elevation range 18-65, README's advice before the orbit model; `wide` = 0-90 (its advice now), so the
# backend clamps instead (docs/gpredict.md). One lane per threshold and setting.
# --conf KEY=VALUE: passed to every lane's rotctld as -C KEY=VALUE (docs/usage.md), e.g. start_cost=0.
#
# Per lane: birdcage-sim (g2) -> rotctld -m 90105 (backend preloaded) -> logging proxy
# (scripts/gpredict_loop.py) -> Gpredict with a fresh $HOME (ground station, the TLE of
# bench/passes/iss-45.tle, rotator localhost:<proxy>, the lane's threshold and limits), its clock
# set by libfaketime to the pass. xdotool opens Antenna Control and presses Track and Engage, as a
# user would. The pass runs in real time (Gpredict's clock cannot follow the emulator's time
# scale): about 5½ minutes. Writes to --out (default <build>/gpredict-loop): per lane (threshold-<thr> for the
# dish's limits, threshold-<thr>-wide for wide ones) the proxy log, the dish positions, the error
# series, the emulator's truth file (motor starts: its `moving` column going 0 -> 1), a screenshot, and summary.json; prints a summary table.
# --check fails (exit 1) unless Gpredict engaged and the dish tracked (bounds below).
# Exits 77 (ctest's SKIP_RETURN_CODE) when a needed Debian package is missing.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"
build=${BIRDCAGE_BUILD_DIR:-$root/build}
out=""
thresholds="5 0.5"
limit_settings="dish"
preload=""
conf=()
check=0
usage() { grep -m1 '^#   scripts/gpredict-loop.sh' "${BASH_SOURCE[0]}" | sed 's/^# *//'; }
while (($#)); do
    case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --thresholds) thresholds=$2; shift 2 ;;
    --limits) limit_settings=$2; shift 2 ;;
    --preload) preload=$2; shift 2 ;;
    --conf) conf+=(-C "$2"); shift 2 ;;
    --check) check=1; shift ;;
    -h | --help) echo "usage: $(usage)"; exit 0 ;;
    *) echo "gpredict-loop.sh: unknown argument '$1'; usage: $(usage)" >&2; exit 2 ;;
    esac
done
out=${out:-$build/gpredict-loop}
for setting in $limit_settings; do
    case "$setting" in
    dish | wide) ;;
    *) echo "gpredict-loop.sh: unknown --limits setting '$setting' (dish or wide)" >&2; exit 2 ;;
    esac
done
# Gpredict's MinEl/MaxEl per setting: the G2's elevation range, or the whole sky.
declare -A min_el=([dish]=18 [wide]=0) max_el=([dish]=65 [wide]=90)
sim="$build/sim/birdcage-sim"
backend="$build/src/hamlib/libhamlib-winegard.so"
preload=${preload:-$backend}
python=/usr/bin/python3   # Debian's interpreter: python3-sgp4 and python3-numpy live there
helper="$root/scripts/gpredict_loop.py"
tle="$root/bench/passes/iss-45.tle"

# --- what is needed (Debian packages: gpredict xvfb xdotool imagemagick faketime python3-sgp4
#     python3-numpy libhamlib-utils; scripts/test.sh installs them)
faketime_lib=$(ls /usr/lib/*/faketime/libfaketime.so.1 2>/dev/null | head -1 || true)
missing=()
for c in gpredict Xvfb xdotool import rotctld; do command -v "$c" >/dev/null || missing+=("$c"); done
[[ -n "$faketime_lib" ]] || missing+=(libfaketime)
"$python" -c 'import sgp4, numpy' 2>/dev/null || missing+=(python3-sgp4/python3-numpy)
if ((${#missing[@]})); then
    echo "gpredict-loop: skipped, missing: ${missing[*]} (Debian: gpredict xvfb xdotool imagemagick faketime python3-sgp4 python3-numpy)"
    exit 77
fi
if [[ ! -x "$sim" || ! -f "$backend" ]]; then
    cmake --build "$build" --target birdcage-sim hamlib-winegard >/dev/null
fi

# --- the pass: bench/passes/iss-45 (peak 45 deg, crosses north), in seconds after the TLE epoch.
epoch=1717200000          # 2024-06-01T00:00:00Z, the TLE's epoch (scripts/gpredict_loop.py)
# Gpredict's clock at launch: satellite at el 5, rising in the north-west, far below the dish's
# 18 deg floor, as a user engages before a pass. The backend learns the pass's direction from
# Gpredict's second distinct target (at 5 deg about a minute later, at el ~11) and then puts the
# dish on the wrap branch that holds the whole pass (README, "Cable wrap"): a 360 deg turn that
# must end before the measurement starts. Engaged later, at 5 deg that turn lands mid-pass
# (docs/gpredict.md).
start_s=40
measure_from_s=180        # el 22.7 (the dish's floor is 18)
measure_to_s=360          # el 29.6 on the way down, after north (~265) and the peak (44.9 at ~285)
screenshot_s=300          # just after the peak, azimuth sweeping east
stop_s=362
offset=$((epoch + start_s - $(date +%s)))   # Gpredict's clock minus the wall clock, whole seconds
wall_of() { echo $((epoch + $1 - offset)); }

mkdir -p "$out"
work=$(mktemp -d /tmp/birdcage-gpredict.XXXXXX)
pids=()
cleanup() {
    local p
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT

wait_until_wall() { while (($(date +%s) < $1)); do sleep 0.5; done; }
# Below the ephemeral range, as scripts/lib.sh's free_port() says why.
next_port=4700
take_port() { # sets $port; never hands out the same port twice (a lane's servers start later)
    port=$(free_port "$next_port" 4899) || return 1
    next_port=$((port + 1))
}

# Gpredict's configuration, as a user would set it up (docs/gpredict.md lists the same settings).
write_gpredict_config() { # DIR PROXY_PORT THRESHOLD MIN_EL MAX_EL
    local c="$1/home/.config/Gpredict"
    mkdir -p "$c/modules" "$c/satdata" "$c/hwconf"
    cat >"$c/birdcage.qth" <<EOF
[QTH]
LOCATION=birdcage test site (bench/generate_passes.py)
DESCRIPTION=45 N 93 W, 250 m
LAT=45.0
LON=-93.0
ALT=250
WX=
QTH_TYPE=0
EOF
    cat >"$c/modules/BIRDCAGE.mod" <<EOF
[GLOBAL]
SATELLITES=99045
QTHFILE=birdcage.qth
EOF
    {
        echo "[Satellite]"
        echo "VERSION=1.1"
        echo "NAME=$(sed -n 1p "$tle")"
        echo "NICKNAME=$(sed -n 1p "$tle")"
        echo "TLE1=$(sed -n 2p "$tle")"
        echo "TLE2=$(sed -n 3p "$tle")"
        echo "STATUS=0"
    } >"$c/satdata/99045.sat"
    cat >"$c/hwconf/winegard-g2.rot" <<EOF
[Rotator]
Host=localhost
Port=$2
AzType=0
MinAz=0
MaxAz=360
MinEl=$4
MaxEl=$5
AzStopPos=0
Cycle=1000
Threshold=$3
EOF
    # No TLE update reminder: the elements are synthetic and there is no network.
    cat >"$c/gpredict.cfg" <<EOF
[GLOBAL]
OPEN_MODULES=BIRDCAGE
DEFAULT_QTH=birdcage.qth
[TLE]
AUTO_UPDATE_FREQ=0
LAST_UPDATE=$((epoch + start_s))
EOF
}

# The clicks a user makes: module menu (top right of the module) -> Antenna Control, then Track and
# Engage. The menu is walked with the keyboard (Antenna Control is its 8th item in Gpredict 2.3).
engage() { # DISPLAY LANE_DIR
    local d=$1 dir=$2 main rot w h try
    export DISPLAY=$d
    wait_for 60 xdotool search --name '^Gpredict: BIRDCAGE$' >/dev/null ||
        { echo "gpredict-loop: Gpredict's main window did not appear on $d" >&2; return 1; }
    main=$(xdotool search --name '^Gpredict: BIRDCAGE$' | head -1)
    eval "$(xdotool getwindowgeometry --shell "$main")"; w=$WIDTH
    for try in 1 2 3 4 5; do
        xdotool mousemove --window "$main" $((w - 19)) 45 click 1
        sleep 0.5
        xdotool key Down Down Down Down Down Down Down Down Return
        if wait_for 5 xdotool search --name '^Gpredict Rotator Control' >/dev/null; then break; fi
        xdotool key Escape
    done
    rot=$(xdotool search --name '^Gpredict Rotator Control' | head -1) ||
        { echo "gpredict-loop: Antenna Control did not open on $d" >&2; return 1; }
    xdotool windowmove "$rot" "$w" 0
    sleep 0.5
    xdotool mousemove --window "$rot" 419 196 click 1   # Track
    sleep 0.3
    xdotool mousemove --window "$rot" 779 196 click 1   # Engage
    if ! wait_for 30 grep -q '> P ' "$dir/proxy.log"; then
        import -window root "$dir/not-engaged.png" || true
        echo "gpredict-loop: Gpredict sent no P on $d (screen: $dir/not-engaged.png)" >&2
        return 1
    fi
}

declare -A lane_dir lane_display lane_threshold lane_limits
lanes=()
for thr in $thresholds; do
    for setting in $limit_settings; do
        # The dish's limits keep the lane directory readers of earlier runs expect.
        lane="$thr"; [[ $setting == dish ]] || lane="$thr-$setting"
        lanes+=("$lane")
        lane_threshold[$lane]=$thr
        lane_limits[$lane]=$setting
    done
done
i=0
for lane in "${lanes[@]}"; do
    thr=${lane_threshold[$lane]}
    setting=${lane_limits[$lane]}
    dir="$out/threshold-$lane"
    rm -rf "$dir"; mkdir -p "$dir"
    lane_dir[$lane]=$dir
    take_port; rot_port=$port
    take_port; proxy_port=$port
    write_gpredict_config "$work/$i" "$proxy_port" "$thr" "${min_el[$setting]}" "${max_el[$setting]}"
    "$sim" --variant g2 --link "$work/$i.dish" --az 300 --el 20 --truth "$dir/truth.csv" >"$dir/sim.log" 2>&1 &
    pids+=($!)
    wait_for 10 test -e "$work/$i.dish"
    env LD_PRELOAD="$preload" ASAN_OPTIONS=detect_leaks=0 \
        rotctld -vvvv -m 90105 -C latitude=45.0 "${conf[@]}" -r "$work/$i.dish" -T 127.0.0.1 -t "$rot_port" >"$dir/rotctld.log" 2>&1 &
    pids+=($!)
    wait_for_listener 60 "$rot_port" "$!" ||
        { echo "gpredict-loop: rotctld did not start:"; cat "$dir/rotctld.log"; exit 1; }
    "$python" "$helper" proxy --listen "$proxy_port" --upstream "$rot_port" \
        --log "$dir/proxy.log" --poll-log "$dir/positions.log" >"$dir/proxy.err" 2>&1 &
    pids+=($!)
    exec {fd}>"$work/$i.display"
    Xvfb -displayfd "$fd" -screen 0 1540x710x24 -nolisten tcp >"$dir/xvfb.log" 2>&1 &
    pids+=($!)
    exec {fd}>&-
    wait_for 20 test -s "$work/$i.display"
    lane_display[$lane]=":$(head -1 "$work/$i.display")"
    env HOME="$work/$i/home" XDG_CONFIG_HOME="$work/$i/home/.config" DISPLAY="${lane_display[$lane]}" \
        NO_AT_BRIDGE=1 LD_PRELOAD="$faketime_lib" FAKETIME="$offset" FAKETIME_DONT_FAKE_MONOTONIC=1 \
        gpredict >"$dir/gpredict.log" 2>&1 &
    pids+=($!)
    i=$((i + 1))
done
for lane in "${lanes[@]}"; do
    engage "${lane_display[$lane]}" "${lane_dir[$lane]}"
    echo "gpredict-loop: threshold ${lane_threshold[$lane]} deg, ${lane_limits[$lane]} limits:" \
        "Gpredict engaged and tracking (display ${lane_display[$lane]})"
done

wait_until_wall "$(wall_of $screenshot_s)"
for lane in "${lanes[@]}"; do
    DISPLAY=${lane_display[$lane]} import -window root "${lane_dir[$lane]}/gpredict.png"
done
wait_until_wall "$(wall_of $stop_s)"
cleanup
pids=()
trap - EXIT

status=0
printf '\n%9s %-12s %8s %8s %8s %8s %10s %12s %18s %6s\n' threshold "limits (el)" "P sent" RMS max p95 "mean lead" \
    "sat el" "AZ travel dish/sat" starts
for lane in "${lanes[@]}"; do
    dir=${lane_dir[$lane]}
    thr=${lane_threshold[$lane]}
    setting=${lane_limits[$lane]}
    bounds=()
    # Engaged and tracking: Gpredict kept sending targets through the pass, and the dish stayed on
    # the satellite within what the threshold allows: Gpredict moves the dish once it is a threshold
    # off and then aims up to a threshold ahead, so twice the threshold, plus 1 deg for a loaded
    # machine whose Gpredict runs late.
    ((check)) && bounds=(--min-p 4 --max-error "$("$python" -c "print(2 * $thr + 1.0)")")
    "$python" "$helper" analyse --tle "$tle" --offset "$offset" --log "$dir/proxy.log" \
        --poll-log "$dir/positions.log" --from $measure_from_s --to $measure_to_s --threshold "$thr" \
        --limits "$setting" --min-el "${min_el[$setting]}" --max-el "${max_el[$setting]}" \
        --out "$dir/summary.json" --series "$dir/error.csv" --truth "$dir/truth.csv" "${bounds[@]}" || status=1
done
echo "window: $measure_from_s–$measure_to_s s after the TLE epoch; files in $out"
exit $status
