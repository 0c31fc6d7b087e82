#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# One command-line convention of one program, as a ctest:
#   cli_conventions.sh help    PROGRAM                    --help: stdout, exit 0, nothing on stderr
#   cli_conventions.sh version PROGRAM VERSION            --version: "PROGRAM VERSION" on stdout, exit 0
#   cli_conventions.sh usage   PROGRAM EXPECTED ARGS...   ARGS is a usage error: exit 2, nothing on
#                                                         stdout, one stderr line naming the program
#                                                         and containing EXPECTED
set -uo pipefail
mode=$1 program=$2
shift 2
name=$(basename "$program")
out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT
fail() { echo "FAIL: $name: $*"; echo "--- stdout:"; cat "$out"; echo "--- stderr:"; cat "$err"; exit 1; }

case $mode in
help)
    "$program" --help >"$out" 2>"$err"; status=$?
    ((status == 0)) || fail "--help exited $status, expected 0"
    [[ ! -s $err ]] || fail "--help wrote to stderr"
    grep -q '^Usage: ' "$out" || fail "--help has no 'Usage:' line"
    grep -q -- '--version' "$out" || fail "--help does not list --version"
    ;;
version)
    "$program" --version >"$out" 2>"$err"; status=$?
    ((status == 0)) || fail "--version exited $status, expected 0"
    [[ "$(head -1 "$out")" == "$name $1" ]] || fail "--version printed '$(head -1 "$out")', expected '$name $1'"
    [[ ! -s $err ]] || fail "--version wrote to stderr"
    ;;
usage)
    expected=$1
    shift
    "$program" "$@" >"$out" 2>"$err" </dev/null; status=$?
    ((status == 2)) || fail "'$*' exited $status, expected 2"
    [[ ! -s $out ]] || fail "'$*' wrote to stdout"
    (($(wc -l <"$err") == 1)) || fail "'$*' wrote $(wc -l <"$err") lines to stderr, expected one"
    grep -q "^$name: " "$err" || fail "the error line does not start with '$name: '"
    grep -qF -- "$expected" "$err" || fail "the error line does not say '$expected'"
    ;;
*) echo "cli_conventions.sh: unknown mode '$mode'" >&2; exit 2 ;;
esac
echo "ok: $name $mode"
