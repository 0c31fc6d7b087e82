#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# birdcage-mcp's tests (this directory) as one ctest: installs the package (mcp/) with its test
# extras from PyPI into a venv in the build directory, then runs pytest against the build tree's
# emulator and backend behind the distribution's rotctld.
#
#   tests/mcp/run.sh --python PYTHON3 --venv DIR --sim BIRDCAGE_SIM --preload LD_PRELOAD --track BIRDCAGE_TRACK
#                    [pytest args]
#
# No network is an error, not a skip: a test that cannot install what it tests has not passed.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
python=python3 venv="" sim="" preload="" track=""
while (($#)); do
    case "$1" in
    --python) python=$2; shift 2 ;;
    --venv) venv=$2; shift 2 ;;
    --sim) sim=$2; shift 2 ;;
    --preload) preload=$2; shift 2 ;;
    --track) track=$2; shift 2 ;;
    *) break ;;
    esac
done
[[ -n $venv && -n $sim && -n $preload && -n $track ]] ||
    { echo "run.sh: --venv, --sim, --preload and --track are required" >&2; exit 2; }

if [[ ! -x $venv/bin/python ]]; then
    "$python" -m venv "$venv" || {
        echo "run.sh: '$python -m venv' failed; Debian needs python3-venv (scripts/test.sh installs it)" >&2
        exit 1
    }
fi
# A copy, so that the build's byproducts (build/, *.egg-info, __pycache__) stay out of the source tree.
copy=$(dirname "$venv")/mcp-src
rm -rf "$copy"
cp -r "$root/mcp" "$copy"
if ! "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "$copy[test]"; then
    echo "run.sh: FAILED to install birdcage-mcp and its dependencies (the mcp SDK) from PyPI into $venv;" >&2
    echo "run.sh: this test needs network access to PyPI (or a pip configured with a reachable index)" >&2
    exit 1
fi
here=$root/tests/mcp
# Nothing written into the source tree: no cache, no bytecode; the rootdir is this directory, so
# pytest reads no configuration from elsewhere in the tree.
cd "$(dirname "$venv")"
BIRDCAGE_SIM=$sim BIRDCAGE_PRELOAD=$preload BIRDCAGE_TRACK=$track BIRDCAGE_MCP=$venv/bin/birdcage-mcp \
    PYTHONDONTWRITEBYTECODE=1 \
    exec "$venv/bin/python" -m pytest -p no:cacheprovider --rootdir "$here" -c /dev/null -v "$@" "$here"
