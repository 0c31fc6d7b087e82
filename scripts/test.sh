#!/usr/bin/env bash
# Installs dependencies, builds with warnings as errors, and runs the whole test suite (ctest).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}
"$root/scripts/build.sh" "$@"
cd "$build"
ctest --output-on-failure --timeout 600 -j "$(nproc)"
