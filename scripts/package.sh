#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Builds the Debian package (debian/, dpkg-buildpackage) into the repository root as
# birdcage_<version>_<arch>.deb, then runs lintian on it and fails on any error or warning.
# The tests are not built (DEB_BUILD_OPTIONS=nocheck, BIRDCAGE_BUILD_TESTS=OFF in debian/rules):
# scripts/test.sh runs them. Then: sudo apt install ./birdcage_*_<arch>.deb
#
#   scripts/package.sh [--arch arm64|armhf] [--no-lintian]
# --arch cross-builds for a Raspberry Pi (arm64: Raspberry Pi OS 64-bit, Pi 3/4/5; armhf: the
# 32-bit OS) with Debian's cross toolchain (scripts/setup.sh --arch installs it on first use)
# against Debian 12's own packages for that architecture, unpacked into build-sysroot-<arch>/ and
# never installed (scripts/lib.sh's pi_sysroot; needs network the first time).
# Environment: BIRDCAGE_PACKAGE_BUILD_DIR (default build-deb, build-deb-<arch> for --arch), where
# the source is copied and built.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
native=$(dpkg --print-architecture)
arch=$native
lintian=1
while (($#)); do
    case "$1" in
    --no-lintian) lintian=0; shift ;;
    --arch) [[ $# -ge 2 ]] || { echo "package.sh: --arch needs arm64 or armhf" >&2; exit 2; }
        arch=$2; shift 2 ;;
    --arch=*) arch=${1#--arch=}; shift ;;
    -h | --help) sed -n '4,15s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "package.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
    esac
done
build_args=()
setup_args=()
if [[ $arch == "$native" ]]; then
    work=${BIRDCAGE_PACKAGE_BUILD_DIR:-$root/build-deb}
else
    case $arch in
    arm64 | armhf) ;;
    *) echo "package.sh: --arch $arch: only arm64 and armhf are supported" >&2; exit 2 ;;
    esac
    work=${BIRDCAGE_PACKAGE_BUILD_DIR:-$root/build-deb-$arch}
    # The cross profile brings qemu-user-static into the build-dependencies (debian/control).
    # The ARCH build-dependencies are the sysroot's, which dpkg does not know of: -d.
    build_args=(-a "$arch" -Pcross -d)
    setup_args=(--arch "$arch")
fi

BIRDCAGE_SETUP_EXTRA="dpkg-dev debhelper help2man lintian ${BIRDCAGE_SETUP_EXTRA:-}" "$root/scripts/setup.sh" "${setup_args[@]}"

# The changelog names the package's version; it must be the one CMake gives every --version.
cmake_version=$(sed -n '/^project(birdcage/,/)/s/^ *VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
deb_version=$(cd "$root" && dpkg-parsechangelog -S Version)
if [[ "$cmake_version" != "$deb_version" ]]; then
    echo "package.sh: debian/changelog says $deb_version, CMakeLists.txt says $cmake_version: add a changelog entry" >&2
    exit 1
fi

sysroot_env=()
if [[ $arch != "$native" ]]; then
    # shellcheck source=scripts/lib.sh
    . "$root/scripts/lib.sh"
    pi_sysroot "$arch"
    # debian/rules builds against it (cmake/debian-cross.cmake) and reads its packages' symbols.
    sysroot_env=(BIRDCAGE_SYSROOT="$root/build-sysroot-$arch/root")
fi

# dpkg-buildpackage builds in the source tree and writes next to it: build a copy of the tree
# (without build directories) so the checkout stays clean.
rm -rf "$work"
mkdir -p "$work/src"
tar -C "$root" --exclude=./.git --exclude='./build*' --exclude=./.cache --exclude='./birdcage_*' -cf - . |
    tar -C "$work/src" -xf -
jobs=$(nproc); ((jobs <= 2)) || jobs=2
(cd "$work/src" && env "${sysroot_env[@]}" DEB_BUILD_OPTIONS="nocheck parallel=$jobs" dpkg-buildpackage -b -us -uc "${build_args[@]}" >"$work/build.log" 2>&1) || {
    tail -40 "$work/build.log" >&2
    echo "package.sh: dpkg-buildpackage failed (whole log: $work/build.log)" >&2
    exit 1
}
deb=birdcage_${deb_version}_${arch}.deb
rm -f "$root"/birdcage_*_"$arch".deb
cp "$work/$deb" "$root/$deb"
echo "package.sh: built $deb ($(du -k "$root/$deb" | cut -f1) KiB)"
dpkg-deb --info "$root/$deb" | sed -n 's/^ \(Depends\|Version\|Installed-Size\):/  \1:/p'

if ((lintian)); then
    # Root is fine here: lintian only unpacks the archive into a temporary directory.
    lintian --fail-on error,warning --display-info "$root/$deb"
    echo "package.sh: lintian: no errors or warnings"
fi
