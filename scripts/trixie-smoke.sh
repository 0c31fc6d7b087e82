#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The backend built here, preloaded into Debian 13 (trixie)'s own rotctld (Hamlib 4.6), against the
# emulated G2 and Trav'ler: lib.sh's dish_e2e (auto-detect, `_`, `P`/`p`, a tracked pass, `S`, no
# hazardous command), the check every rotctld route passes. Nothing is installed: trixie's
# libhamlib4t64, libhamlib-utils and the libraries they need are fetched with apt-get download
# through a private apt configuration (lib.sh's debian_root: its own sources and lists in a
# temporary directory), unpacked with dpkg-deb -x and run with trixie's own loader:
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

# ---- trixie's packages, through a private apt configuration (lib.sh's debian_root) -------------
# rotctld, libhamlib and everything they load, plus the C++ runtime and libserialport the backend
# loads, so that only the backend itself comes from this machine.
debian_mirror=${BIRDCAGE_TRIXIE_MIRROR:-} debian_root amd64 trixie "$store" \
    libhamlib-utils libhamlib4t64 libstdc++6 libserialport0
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
