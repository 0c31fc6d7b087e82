#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Installs dependencies, builds with warnings as errors, and runs the whole test suite (ctest).
#
#   scripts/test.sh [--repeat N] [-L label | -R regex]... [-- cmake args]
#
# --repeat N runs every selected test up to N times and stops at its first failure (ctest's
# --repeat until-fail:N): how a flaky test is found. A flaky test is a bug to fix at its cause.
# -L/-R select tests as ctest does (labels: matrix, dialects, clients, regress, sim, tui, mcp, docs;
# names start with core:, sim:, e2e:, matrix:, dialects:, replay:, ...). Anything after -- goes to cmake.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${BIRDCAGE_BUILD_DIR:-$root/build}

usage() { sed -n '6,11s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; }
ctest_args=()
cmake_args=()
while (($#)); do
    case "$1" in
    -h | --help) usage; exit 0 ;;
    --repeat) [[ $# -ge 2 && $2 =~ ^[1-9][0-9]*$ ]] || { echo "test.sh: --repeat needs a positive count" >&2; exit 2; }
        ctest_args+=(--repeat "until-fail:$2"); shift 2 ;;
    --repeat=*) n=${1#--repeat=}; [[ $n =~ ^[1-9][0-9]*$ ]] || { echo "test.sh: --repeat needs a positive count" >&2; exit 2; }
        ctest_args+=(--repeat "until-fail:$n"); shift ;;
    -L | -R | -LE | -E) [[ $# -ge 2 ]] || { echo "test.sh: $1 needs an argument" >&2; exit 2; }
        ctest_args+=("$1" "$2"); shift 2 ;;
    --) shift; cmake_args+=("$@"); break ;;
    -D*) cmake_args+=("$1"); shift ;;   # earlier callers passed cmake definitions directly
    *) echo "test.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
    esac
done

# Debian packages for the test suite only: the gpredict test's (tests/gpredict/CMakeLists.txt),
# the venv module for the mcp test (tests/mcp/CMakeLists.txt) and tmux, in which the tui test
# drives birdcage-tui (tui/CMakeLists.txt); clang-format 14 for the build's format check
# (cmake/BirdcageFormat.cmake); pytest with skyfield and astropy, the independent implementations
# the sky tools are checked against (tests/sky/CMakeLists.txt).
export BIRDCAGE_SETUP_EXTRA="${BIRDCAGE_SETUP_EXTRA:-} gpredict xvfb xdotool imagemagick faketime python3-sgp4 python3-ephem python3-numpy python3-venv tmux clang-format python3-pytest python3-skyfield python3-astropy"
"$root/scripts/build.sh" -DBIRDCAGE_BUILD_TESTS=ON "${cmake_args[@]}"
cd "$build"
ctest --output-on-failure --timeout 600 -j "$(nproc)" "${ctest_args[@]}"
