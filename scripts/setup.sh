#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Installs what birdcage needs from Debian's packages (bookworm). Idempotent: installs only what is
# missing. As root it runs apt-get; otherwise it prints the exact command to run and fails.
#
#   scripts/setup.sh [--arch arm64|armhf]...
# --arch ARCH also installs what a cross build for that Debian architecture needs on this machine
# (Raspberry Pi OS: arm64, armhf): Debian's cross toolchain (crossbuild-essential-ARCH, this
# machine's own packages with their own libc for ARCH) and qemu-user-static, which runs the ARM
# programs at build time (help2man, the test list) and in scripts/arm-test.sh. No ARCH package is
# installed and dpkg gets no foreign architecture: the libraries a cross build links are Debian's
# ARCH packages unpacked into a sysroot (scripts/lib.sh's pi_sysroot, which arm-test.sh and
# package.sh call).
# BIRDCAGE_SETUP_EXTRA="pkg ..." adds packages of the build machine's own architecture.
set -euo pipefail

cross=()
while (($#)); do
    case "$1" in
    --arch) [[ $# -ge 2 ]] || { echo "setup: --arch needs arm64 or armhf" >&2; exit 2; }
        cross+=("$2"); shift 2 ;;
    --arch=*) cross+=("${1#--arch=}"); shift ;;
    *) echo "setup: unknown argument '$1'" >&2; exit 2 ;;
    esac
done

packages=(
    build-essential cmake pkg-config
    libhamlib-dev libhamlib-utils   # headers + the stock rotctl/rotctld the tests and demo drive
    libserialport-dev
    libncurses-dev                  # birdcage-tui
    catch2
    help2man                        # the section-1 man pages: a source install has all 7 pages
    python3                         # the doc check (tests/docs)
    # birdcage-track and birdcage-align (tools/sky): SGP4, PyEphem, the fit, the plot
    python3-sgp4 python3-ephem python3-numpy python3-scipy python3-matplotlib
)
if [[ "${BIRDCAGE_SETUP_EXTRA:-}" != "" ]]; then
    read -r -a extra <<<"${BIRDCAGE_SETUP_EXTRA}"
    packages+=("${extra[@]}")
fi

for arch in "${cross[@]}"; do
    case $arch in
    arm64 | armhf) ;;
    *) echo "setup: --arch $arch: only arm64 and armhf are supported" >&2; exit 2 ;;
    esac
    if [[ $arch != "$(dpkg --print-architecture)" ]]; then
        packages+=("crossbuild-essential-$arch" qemu-user-static)
    fi
done

missing=()
for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$p")
    fi
done
if ((${#missing[@]} == 0)); then
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    echo "setup: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    # One index that fails to download (a mirror mid-sync) need not stop the install: apt-get
    # install below fails by itself if what it needs is not in the lists it has.
    apt-get update -qq || echo "setup: apt-get update reported errors; trying the install with the lists it has" >&2
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    echo "setup: installing ${missing[*]} with sudo" >&2
    sudo DEBIAN_FRONTEND=noninteractive apt-get update -qq || echo "setup: apt-get update reported errors; trying the install with the lists it has" >&2
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
    echo "setup: missing Debian packages. Run:" >&2
    echo "  sudo apt-get install ${missing[*]}" >&2
    exit 1
fi
