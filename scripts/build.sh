#!/usr/bin/env bash
# Configures and builds into build/ (or $BIRDCAGE_BUILD_DIR). Extra arguments go to cmake.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
"$root/scripts/setup.sh"
cmake -S "$root" -B "$build" -DBIRDCAGE_WERROR=ON "$@" >/dev/null
cmake --build "$build" -j "$(nproc)"
