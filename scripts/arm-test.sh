#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The Raspberry Pi builds, tested on this amd64 machine under Debian's qemu-user-static (invoked
# directly, no binfmt registration needed). Per architecture, against a sysroot of Debian 12's own
# packages for it, fetched with apt-get download and unpacked, never installed (lib.sh's
# pi_sysroot, kept in build-sysroot-<arch>/ between runs):
#  1. the core and emulator unit tests (ctest -R '^(core|sim):'), cross-built with
#     cmake/debian-cross.cmake against the sysroot and run by ctest under qemu with the sysroot as
#     its root (CMAKE_CROSSCOMPILING_EMULATOR);
#  2. Debian 12's own rotctld for that architecture (the sysroot's libhamlib-utils) run under qemu
#     with the ARM backend preloaded, against this machine's birdcage-sim on a pty: an emulated
#     Carryout G2 and a Trav'ler HAL 2.05, each opened as model 90100 (auto-detect): `_` names the
#     dish, `P`/`p`, then a short pass tracked the way Gpredict does it (one connection, a `P`
#     every few pass seconds).
#
#   scripts/arm-test.sh [--arch arm64|armhf]...      (default: arm64)
# Needs root or sudo the first time (scripts/setup.sh --arch installs the cross toolchain and
# qemu-user-static, both this machine's own packages), and network for the sysroot.
# BIRDCAGE_BUILD_DIR: the native build whose birdcage-sim emulates the dish (default build/; its
# birdcage-sim is built if missing). The ARM builds go to build-<arch>/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
native_build=${BIRDCAGE_BUILD_DIR:-$root/build}
arches=()
while (($#)); do
    case "$1" in
    --arch) [[ $# -ge 2 ]] || { echo "arm-test: --arch needs arm64 or armhf" >&2; exit 2; }
        arches+=("$2"); shift 2 ;;
    --arch=*) arches+=("${1#--arch=}"); shift ;;
    -h | --help) sed -n '4,21s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "arm-test: unknown argument '$1' (try --help)" >&2; exit 2 ;;
    esac
done
((${#arches[@]})) || arches=(arm64)

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"
work=$(mktemp -d /tmp/birdcage-arm.XXXXXX)
trap 'stop_servers; rm -rf "$work"' EXIT

setup_args=()
for arch in "${arches[@]}"; do setup_args+=(--arch "$arch"); done
"$root/scripts/setup.sh" "${setup_args[@]}"

# The emulator is the native one: only the backend and rotctld are under test on ARM.
sim=$native_build/sim/birdcage-sim
if [[ ! -x $sim ]]; then
    say "building the native birdcage-sim in $native_build"
    [[ -f $native_build/CMakeCache.txt ]] || cmake -S "$root" -B "$native_build" -DBIRDCAGE_WERROR=ON >/dev/null
    cmake --build "$native_build" -j2 --target birdcage-sim >/dev/null
fi

# The e2e (lib.sh's dish_e2e) runs each ARM rotctld with this machine's emulator and rotctl.
e2e_sim=$sim e2e_work=$work
e2e_client=(rotctl)

for arch in "${arches[@]}"; do
    case $arch in
    arm64) triplet=aarch64-linux-gnu qemu=qemu-aarch64-static ld=/lib/ld-linux-aarch64.so.1 ;;
    armhf) triplet=arm-linux-gnueabihf qemu=qemu-arm-static ld=/lib/ld-linux-armhf.so.3 ;;
    *) echo "arm-test: --arch $arch: only arm64 and armhf" >&2; exit 2 ;;
    esac
    build=$root/build-$arch
    pi_sysroot "$arch"
    sysroot=$root/build-sysroot-$arch/root
    say "== $arch: cross build (cmake/debian-cross.cmake) in $build"
    cmake -S "$root" -B "$build" -DCMAKE_TOOLCHAIN_FILE="$root/cmake/debian-cross.cmake" -DBIRDCAGE_DEB_ARCH="$arch" \
        -DBIRDCAGE_SYSROOT="$sysroot" \
        -DBIRDCAGE_WERROR=ON -DBIRDCAGE_BUILD_TESTS=ON -DBIRDCAGE_BUILD_BENCH=OFF -DBIRDCAGE_MANPAGES=OFF >/dev/null
    nice cmake --build "$build" -j2 --target test_core test_core_emulated test_sim birdcage-sim hamlib-winegard >"$work/build.log" 2>&1 ||
        { tail -40 "$work/build.log" >&2; echo "arm-test: FAIL: $arch build" >&2; exit 1; }
    # All of tests/core and tests/sim but the tests labelled `figures` (tests/core/CMakeLists.txt):
    # they fit orbits to whole passes, pure double arithmetic, 36 s of the core's 38 s natively and
    # ~60x slower under qemu (6 s became 365 s); the native suite runs them. A test that grows as
    # slow fails here by the timeout instead of stretching the stage.
    say "== $arch: unit tests under $qemu"
    (cd "$build" && ctest --output-on-failure --timeout 120 -j "$(nproc)" -R '^(core|sim):' -LE figures)

    say "== $arch: Debian 12's $arch rotctld under $qemu, the $arch backend preloaded"
    # The sysroot's loader, with the sysroot as qemu's root: it loads rotctld's libraries from there.
    loader=("$qemu" -L "$sysroot" "$sysroot$ld")
    libpath=$sysroot/usr/lib/$triplet:$sysroot/lib/$triplet
    rotctld=$sysroot/usr/bin/rotctld
    backend=$build/src/hamlib/libhamlib-winegard.so
    say "$arch: $("${loader[@]}" --library-path "$libpath" "$rotctld" --version | head -1)"
    models=$(winegard_models "${loader[@]}" --library-path "$libpath" --preload "$backend" "$rotctld")
    [[ $models -eq 6 ]] || { echo "arm-test: FAIL: the $arch rotctld lists $models Winegard models, expected 6" >&2; exit 1; }
    say "$arch: rotctld -l lists the 6 Winegard models"
    for dish in "g2:Carryout G2" "hal205:Trav'ler HAL 2.05"; do
        dish_e2e "$arch" "${dish%%:*}" "${dish#*:}" 90100 \
            "${loader[@]}" --library-path "$libpath" --preload "$backend" "$rotctld" ||
            { echo "arm-test: FAIL: $arch ${dish%%:*}" >&2; exit 1; }
    done
done
say "PASS: ${arches[*]}: unit tests and the ARM rotctld e2e under qemu"
