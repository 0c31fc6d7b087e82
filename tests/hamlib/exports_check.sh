#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The preload build's library exports its Hamlib entry point and nothing else (the reason is in
# src/hamlib/preload/exports.map): lists the dynamic symbols it defines and fails, naming the
# others, when there is any other or the entry point is missing.
#   exports_check.sh NM LIBRARY
set -euo pipefail
nm=$1 library=$2
expected=initrots4_winegard

# Defined dynamic symbols, names only; a versioned name (name@@VERSION) counts by its name.
mapfile -t defined < <("$nm" -D --defined-only --format=posix "$library" | awk '{ sub(/@.*/, "", $1); print $1 }' | sort -u)
others=()
found=0
for name in "${defined[@]}"; do
    if [[ $name == "$expected" ]]; then
        found=1
    else
        others+=("$name")
    fi
done
((found)) || { echo "FAIL: $library does not export $expected"; exit 1; }
if ((${#others[@]})); then
    echo "FAIL: $library exports ${#others[@]} symbol(s) besides $expected, e.g.:"
    printf '  %s\n' "${others[@]:0:20}"
    exit 1
fi
echo "ok: $library exports $expected alone"
