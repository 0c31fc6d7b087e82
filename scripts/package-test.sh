#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# What CI does with the package, as root on a Debian machine: installs
# ./birdcage_*_<arch>.deb (scripts/package.sh builds it) with apt, runs the demo service from the
# installed paths only (birdcage-sim@demo + birdcage-rotctld@demo), moves the emulated dish with
# the stock rotctl and reads the position back, then purges the package and checks that nothing
# it installed or created is left.
#
# With systemd as PID 1 the units run through systemctl. Without it (CI containers) each unit's
# ExecStart line runs by hand the way systemd would: as its User=, with its EnvironmentFile=
# sourced, %i replaced by the instance and its RuntimeDirectory= created; the rotctld port is
# then a free one instead of the defaults file's 4533, so a busy machine cannot collide with it.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# This machine's own architecture: a cross-built package (package.sh --arch) may lie beside it.
debs=("$root"/birdcage_*_"$(dpkg --print-architecture)".deb)
[[ -f ${debs[0]} ]] || { echo "package-test.sh: no birdcage_*_$(dpkg --print-architecture).deb in $root (run scripts/package.sh)" >&2; exit 1; }
[[ $(id -u) -eq 0 ]] || { echo "package-test.sh: installs a package: run as root" >&2; exit 1; }
unitdir=/lib/systemd/system
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
}
trap cleanup EXIT

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"

echo "== install ${debs[0]##*/}"
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${debs[0]}" >/dev/null
mapfile -t installed < <(dpkg -L birdcage | sort)
for program in birdcage-rotctld birdcage-rotctl birdcage-sim birdcage-probe birdcage-skyscan birdcage-tui; do
    [[ $(command -v "$program") == /usr/bin/$program ]] || { echo "FAIL: $program is not /usr/bin/$program" >&2; exit 1; }
done
getent passwd _birdcage >/dev/null || { echo "FAIL: no user _birdcage" >&2; exit 1; }
id -nG _birdcage | grep -qw dialout || { echo "FAIL: _birdcage is not in dialout" >&2; exit 1; }
birdcage-rotctl -l | grep -q '^ *90105 .*Winegard' || { echo "FAIL: birdcage-rotctl -l lists no Winegard model" >&2; exit 1; }
if command -v man >/dev/null; then
    man -w birdcage-rotctld birdcage-rotctl birdcage-sim birdcage-probe birdcage-skyscan birdcage-tui 7 birdcage >/dev/null
fi

# run_unit UNIT INSTANCE [VAR=VALUE...]: the unit's ExecStart without systemd; the assignments
# override the EnvironmentFile's.
run_unit() {
    local unit=$unitdir/$1 instance=$2 user exec envfile runtime log=/tmp/birdcage-package-test.${1%@.service}.log
    shift 2
    user=$(sed -n 's/^User=//p' "$unit")
    exec=$(sed -n 's/^ExecStart=//p' "$unit")
    envfile=$(sed -n 's/^EnvironmentFile=//p' "$unit")
    runtime=$(sed -n 's/^RuntimeDirectory=//p' "$unit")
    exec=${exec//%i/$instance} envfile=${envfile//%i/$instance}
    if [[ -n $runtime ]]; then install -d -o "$user" -g "$user" -m 755 "/run/$runtime"; fi
    echo "   as $user: $exec   (environment: $envfile $*; output: $log)"
    runuser -u "$user" -- env "$@" bash -c 'set -a; . "$1"; for a in "${@:3}"; do export "$a"; done; set +a; eval "exec $2"' \
        run_unit "$envfile" "$exec" "$@" >"$log" 2>&1 &
    pids+=($!)
}

if [[ -d /run/systemd/system ]]; then
    echo "== systemctl start birdcage-sim@demo birdcage-rotctld@demo"
    systemctl start birdcage-sim@demo birdcage-rotctld@demo
    port=4533
    wait_for 60 bash -c "exec 3<>/dev/tcp/127.0.0.1/$port" || { echo "FAIL: rotctld does not listen on $port" >&2; exit 1; }
else
    echo "== no systemd here (PID 1 is $(ps -p 1 -o comm=)): the units' ExecStart lines by hand"
    port=$(free_port 4650 4699)
    run_unit birdcage-sim@.service demo
    wait_for 20 test -e /run/birdcage/demo.tty || { echo "FAIL: the emulator made no pty" >&2; exit 1; }
    run_unit birdcage-rotctld@.service demo PORT="$port"
    wait_for_listener 60 "$port" "${pids[-1]}" || { echo "FAIL: rotctld does not listen on $port" >&2; exit 1; }
fi

echo "== rotctl -m 2 -r 127.0.0.1:$port P 180 40, then p"
rotctl -m 2 -r "127.0.0.1:$port" P 180 40
arrived() {
    local az el
    read -r az el < <(rotctl -m 2 -r "127.0.0.1:$port" p | tr '\n' ' ')
    echo "   p: $az $el"
    awk -v az="$az" -v el="$el" 'BEGIN { exit !((az - 180) ^ 2 < 0.25 && (el - 40) ^ 2 < 0.25) }'
}
# The emulated G2 runs 10 times faster than a real one (the demo defaults): seconds, not minutes.
wait_for 120 arrived || { echo "FAIL: the dish did not reach 180 40" >&2; exit 1; }

if [[ -d /run/systemd/system ]]; then
    systemctl stop birdcage-rotctld@demo birdcage-sim@demo
else
    cleanup
    pids=()
    rm -rf /run/birdcage   # what systemd does with a RuntimeDirectory at reboot
fi

echo "== apt purge birdcage"
DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq birdcage >/dev/null
left=()
for path in "${installed[@]}"; do
    # Directories the package shares with others (/usr, /etc/default, ...) stay.
    [[ -e $path && ! -d $path ]] && left+=("$path")
    [[ -d $path && $path == *birdcage* ]] && left+=("$path")
done
if getent passwd _birdcage >/dev/null; then left+=("user _birdcage"); fi
if getent group _birdcage >/dev/null; then left+=("group _birdcage"); fi
if dpkg-query -W -f='${Status}' birdcage 2>/dev/null | grep -q .; then left+=("dpkg status entry"); fi
if ((${#left[@]})); then
    echo "FAIL: left after purge: ${left[*]}" >&2
    exit 1
fi
echo "package-test: installed, moved the dish to 180 40 through the installed birdcage-rotctld, purged with nothing left"
