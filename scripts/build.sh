#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Configures and builds into build/ (or $BIRDCAGE_BUILD_DIR). Extra arguments go to cmake.
#   scripts/build.sh [--no-tests] [cmake args]
# --no-tests builds only what is installed (backend, programs, man pages): about 40 s instead of
# about 5 min on 2 cores. The choice stays in the build directory's cache until changed;
# scripts/test.sh always turns the tests back on.
set -euo pipefail
tests=()
if [[ "${1:-}" == --no-tests ]]; then
    tests=(-DBIRDCAGE_BUILD_TESTS=OFF)
    shift
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
cmake -S "$root" -B "$build" -DBIRDCAGE_WERROR=ON "${tests[@]}" "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
