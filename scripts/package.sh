#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Builds the Debian package (debian/, dpkg-buildpackage) into the repository root as
# birdcage_<version>_<arch>.deb, then runs lintian on it and fails on any error or warning.
# The tests are not built (DEB_BUILD_OPTIONS=nocheck, BIRDCAGE_BUILD_TESTS=OFF in debian/rules):
# scripts/test.sh runs them. Then: sudo apt install ./birdcage_*.deb
#
#   scripts/package.sh [--no-lintian]
# Environment: BIRDCAGE_PACKAGE_BUILD_DIR (default build-deb), where the source is copied and built.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
work=${BIRDCAGE_PACKAGE_BUILD_DIR:-$root/build-deb}
lintian=1
case "${1:-}" in
"") ;;
--no-lintian) lintian=0 ;;
-h | --help) sed -n '4,10s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; exit 0 ;;
*) echo "package.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac

BIRDCAGE_SETUP_EXTRA="dpkg-dev debhelper help2man lintian ${BIRDCAGE_SETUP_EXTRA:-}" "$root/scripts/setup.sh"

# The changelog names the package's version; it must be the one CMake gives every --version.
cmake_version=$(sed -n '/^project(birdcage/,/)/s/^ *VERSION \([0-9.]*\).*/\1/p' "$root/CMakeLists.txt")
deb_version=$(cd "$root" && dpkg-parsechangelog -S Version)
if [[ "$cmake_version" != "$deb_version" ]]; then
    echo "package.sh: debian/changelog says $deb_version, CMakeLists.txt says $cmake_version: add a changelog entry" >&2
    exit 1
fi

# dpkg-buildpackage builds in the source tree and writes next to it: build a copy of the tree
# (without build directories) so the checkout stays clean.
rm -rf "$work"
mkdir -p "$work/src"
tar -C "$root" --exclude=./.git --exclude='./build*' --exclude=./.cache --exclude='./birdcage_*' -cf - . |
    tar -C "$work/src" -xf -
jobs=$(nproc); ((jobs <= 2)) || jobs=2
(cd "$work/src" && DEB_BUILD_OPTIONS="nocheck parallel=$jobs" dpkg-buildpackage -b -us -uc >"$work/build.log" 2>&1) || {
    tail -40 "$work/build.log" >&2
    echo "package.sh: dpkg-buildpackage failed (whole log: $work/build.log)" >&2
    exit 1
}
arch=$(dpkg --print-architecture)
deb=birdcage_${deb_version}_${arch}.deb
rm -f "$root"/birdcage_*.deb
cp "$work/$deb" "$root/$deb"
echo "package.sh: built $deb"
dpkg-deb --info "$root/$deb" | sed -n 's/^ \(Depends\|Version\|Installed-Size\):/  \1:/p'

if ((lintian)); then
    # Root is fine here: lintian only unpacks the archive into a temporary directory.
    lintian --fail-on error,warning --display-info "$root/$deb"
    echo "package.sh: lintian: no errors or warnings"
fi
