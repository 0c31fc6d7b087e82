#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# Puts the SPDX licence header at the top of every source file git tracks (C/C++, CMake, shell,
# Python), after a shebang line if there is one. Idempotent: a file that already names an SPDX
# licence in its first lines is left alone. --check changes nothing and fails, naming the files,
# when one lacks the header (ctest `docs: every source file carries the licence header`).
#   scripts/license-headers.sh [--check]
set -euo pipefail
# All in one function: bash reads a script as it runs it, and this one may rewrite itself.
main() {
    root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
    cd "$root"
    check=0
    [[ ${1:-} == --check ]] && check=1

    spdx='SPDX-License-Identifier: LGPL-2.1-or-later'
    copyright='Copyright (C) 2026 the birdcage authors'

    # The comment leader of a source file, or nothing when the file is not source.
    leader() {
        case "$1" in
        *.cpp | *.hpp | *.h | *.cpp.in | *.hpp.in) echo '//' ;;
        CMakeLists.txt | */CMakeLists.txt | *.cmake | *.sh | *.py) echo '#' ;;
        .ci/run | debian/rules | debian/*.postinst | debian/*.postrm | packaging/birdcage-launcher.in | \
            packaging/bash-completion/*) echo '#' ;;
        esac
    }

    missing=()
    while IFS= read -r -d '' file; do
        lead=$(leader "$file")
        [[ -n $lead && -f $file ]] || continue
        head -n 5 "$file" | grep -q 'SPDX-License-Identifier:' && continue
        if ((check)); then
            missing+=("$file")
            continue
        fi
        header="$lead $spdx"$'\n'"$lead $copyright"$'\n'
        tmp=$(mktemp)
        if head -c 2 "$file" | grep -q '^#!'; then
            { head -n 1 "$file"; printf '%s' "$header"; tail -n +2 "$file"; } >"$tmp"
        else
            { printf '%s\n' "$header"; cat "$file"; } >"$tmp"
        fi
        cat "$tmp" >"$file"   # keeps the file's mode (scripts stay executable)
        rm -f "$tmp"
    done < <(git ls-files -z)

    if ((check)); then
        if ((${#missing[@]})); then
            printf 'FAIL: no SPDX licence header in %s\n' "${missing[@]}"
            echo "(scripts/license-headers.sh adds it)"
            exit 1
        fi
        echo "ok: every source file carries the LGPL-2.1-or-later header"
    fi
}
main "$@"
