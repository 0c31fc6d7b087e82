#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Formats every C/C++ source file git tracks with the project's .clang-format, or with --check
# changes nothing and fails naming the files that differ (the build runs the check:
# cmake/BirdcageFormat.cmake). The style is pinned to clang-format 14, Debian 12's: other major
# versions format some constructs differently, so they are refused rather than obeyed.
#   scripts/format.sh [--check]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
check=0
[[ ${1:-} == --check ]] && check=1
clang_format=${CLANG_FORMAT:-clang-format}
version=$("$clang_format" --version 2>/dev/null | sed -n 's/.*version \([0-9]*\)\..*/\1/p')
if [[ $version != 14 ]]; then
    echo "format.sh: needs clang-format 14 (Debian 12's package clang-format); found '${version:-none}'" >&2
    exit 2
fi
mapfile -d '' files < <(git ls-files -z -- '*.cpp' '*.hpp' '*.h' '*.c')
if ((check)); then
    "$clang_format" --dry-run --Werror "${files[@]}"
else
    "$clang_format" -i "${files[@]}"
fi
