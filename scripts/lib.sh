# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

# Shell helpers shared by the project's scripts (sourced, not run).

# wait_for SECONDS COMMAND...: runs COMMAND until it succeeds; fails after SECONDS.
wait_for() {
    local deadline=$((SECONDS + $1)); shift
    until "$@" 2>/dev/null; do
        ((SECONDS < deadline)) || return 1
        sleep 0.1
    done
}

# free_port FIRST LAST: prints a TCP port in FIRST..LAST that nothing on 127.0.0.1 listens on.
# For scripts a person runs (a demo, a package check), where the race with another program
# taking the port in between is acceptable; the test harness lets rotctld pick its port instead.
free_port() {
    local p
    for p in $(seq "$1" "$2"); do
        if ! (exec 3<>/dev/tcp/127.0.0.1/"$p") 2>/dev/null; then echo "$p"; return; fi
    done
    echo "no free port in $1..$2" >&2
    return 1
}
