#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The backend built here, preloaded into Debian 13 (trixie)'s own rotctld (Hamlib 4.6), against the
# emulated G2 and Trav'ler: lib.sh's dish_e2e (auto-detect, `_`, `P`/`p`, a tracked pass, `S`, no
# hazardous command), the check every rotctld route passes. Nothing is installed: trixie's
# libhamlib4t64, libhamlib-utils and the libraries they need are fetched with apt-get download
# through a private apt configuration (its own sources and lists in a temporary directory), unpacked
# with dpkg-deb -x and run with trixie's own loader:
#   ld-linux-x86-64.so.2 --library-path <trixie libs> --preload <backend> rotctld ...
#
#   scripts/trixie-smoke.sh [BUILD_DIR]      (default: $BIRDCAGE_BUILD_DIR or build/; needs the
#                                             backend and birdcage-sim built there, and network)
# BIRDCAGE_TRIXIE_DIR=DIR keeps the downloads in DIR between runs (default: a temporary directory).
# BIRDCAGE_BACKEND=FILE tries another build of the backend (e.g. one built against trixie's headers).
# BIRDCAGE_TRIXIE_MIRROR=URL picks the Debian mirror (default: the one this machine's apt sources
# use for its own Debian release).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-${BIRDCAGE_BUILD_DIR:-$root/build}}
backend=${BIRDCAGE_BACKEND:-$build/src/hamlib/libhamlib-winegard.so}
sim=$build/sim/birdcage-sim
# The mirror this machine already uses for Debian's main archive (one-line or deb822 sources).
system_mirror() {
    local codename
    codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
    cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
        awk -v c="$codename" '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^(https?|file):/ && $(i + 1) == c) { print $i; exit } }'
    cat /etc/apt/sources.list.d/*.sources 2>/dev/null |
        awk -v c="$codename" '/^URIs:/ { u = $2 } /^Suites:/ { for (i = 2; i <= NF; i++) if ($i == c && u != "") { print u; exit } } /^$/ { u = "" }'
}
mirror=${BIRDCAGE_TRIXIE_MIRROR:-$(system_mirror | head -1)}
[[ -n $mirror ]] || { echo "trixie-smoke: no Debian mirror in /etc/apt/sources* (set BIRDCAGE_TRIXIE_MIRROR)" >&2; exit 2; }
for f in "$backend" "$sim"; do
    [[ -x $f || -f $f ]] || { echo "trixie-smoke: $f is missing (build first)" >&2; exit 2; }
done
case $(dpkg --print-architecture) in
amd64) ;;
*) echo "trixie-smoke: amd64 only (trixie's ld-linux-x86-64.so.2)" >&2; exit 2 ;;
esac

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"

if [[ -n ${BIRDCAGE_TRIXIE_DIR:-} ]]; then
    store=$BIRDCAGE_TRIXIE_DIR
    mkdir -p "$store"
else
    store=$(mktemp -d /tmp/birdcage-trixie.XXXXXX)
fi
work=$(mktemp -d /tmp/birdcage-trixie-run.XXXXXX)
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    rm -rf "$work"
    [[ -n ${BIRDCAGE_TRIXIE_DIR:-} ]] || rm -rf "$store"
}
trap cleanup EXIT

# ---- trixie's packages, through a private apt configuration -----------------------------------
mkdir -p "$store/lists/partial" "$store/cache/archives/partial" "$store/debs" "$store/root"
echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror trixie main" >"$store/sources.list"
apt_options=(
    -o "Dir::Etc::sourcelist=$store/sources.list" -o Dir::Etc::sourceparts=/nonexistent
    -o Dir::Etc::parts=/nonexistent -o "Dir::State::lists=$store/lists" -o "Dir::Cache=$store/cache"
    -o Dir::State::status=/dev/null -o Debug::NoLocking=1 -o APT::Sandbox::User=root
    -o Acquire::Languages=none
)
if [[ ! -e $store/root/usr/bin/rotctld ]]; then
    say "apt-get update (trixie main, private lists in $store)"
    apt-get "${apt_options[@]}" -qq update
    # rotctld, libhamlib and everything they load, plus the C++ runtime and libserialport the
    # backend loads, so that only the backend itself comes from this machine.
    mapfile -t packages < <(apt-cache "${apt_options[@]}" depends --recurse --no-recommends --no-suggests \
        --no-conflicts --no-breaks --no-replaces --no-enhances \
        libhamlib-utils libhamlib4t64 libstdc++6 libserialport0 | grep -v '^[ <]' | sort -u)
    say "apt-get download ${packages[*]}"
    (cd "$store/debs" && apt-get "${apt_options[@]}" -qq download "${packages[@]}")
    for deb in "$store"/debs/*.deb; do dpkg-deb -x "$deb" "$store/root"; done
fi
libs=$store/root/usr/lib/x86_64-linux-gnu
loader=$libs/ld-linux-x86-64.so.2
libpath=$libs:$store/root/lib/x86_64-linux-gnu
trixie() { "$loader" --library-path "$libpath" "$@"; }
rotctld=$store/root/usr/bin/rotctld
rotctl=$store/root/usr/bin/rotctl

say "trixie: $(trixie "$rotctld" --version | head -1); $(trixie --version | head -1 | grep -oE 'GLIBC [^)]*')"
say "backend: $backend"

# ---- the models register in trixie's Hamlib -----------------------------------------------------
models=$(winegard_models trixie --preload "$backend" "$rotctld")
if [[ $models -ne 6 ]]; then
    echo "trixie-smoke: FAIL: trixie's rotctld lists $models Winegard models, expected 6" >&2
    trixie --preload "$backend" "$rotctld" -l >&2 || true
    exit 1
fi
say "trixie's rotctld -l lists the 6 Winegard models"

# ---- the end-to-end check every rotctld route passes (lib.sh's dish_e2e) -------------------------
# trixie's rotctld (through its loader, with the backend preloaded) and trixie's rotctl as client.
e2e_sim=$sim e2e_work=$work
e2e_client=("$loader" --library-path "$libpath" "$rotctl")
for dish in "g2:Carryout G2" "hal205:Trav'ler HAL 2.05"; do
    dish_e2e trixie "${dish%%:*}" "${dish#*:}" 90100 "$loader" --library-path "$libpath" --preload "$backend" "$rotctld" ||
        { echo "trixie-smoke: FAIL: trixie's rotctld with the emulated ${dish%%:*}" >&2; exit 1; }
done
# The backend's load-time ABI check names both Hamlibs at open (-vvvv).
note=$(grep -m1 -o "built for Hamlib.*" "$work/trixie-g2.rotctld.log" || true)
say "ABI check: ${note:-(no note: the same Hamlib release)}"
say "PASS: $backend under trixie's rotctld: the emulated G2 and Trav'ler (auto-detect, P/p, a tracked pass, S)"
