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
# Keep FIRST..LAST below the kernel's ephemeral range (/proc/sys/net/ipv4/ip_local_port_range,
# 32768-60999 on Debian): there no test's `rotctld -t 0` takes the port, and a probe of a port
# nothing listens on yet cannot connect to itself. Inside the range it can: the kernel may give the
# probe that very port as its own, the loopback connection "succeeds", and the demo once took a
# rotctld still opening the G2 for ready and had its first command refused.
free_port() {
    local p
    for p in $(seq "$1" "$2"); do
        if ! (exec 3<>/dev/tcp/127.0.0.1/"$p") 2>/dev/null; then echo "$p"; return; fi
    done
    echo "no free port in $1..$2" >&2
    return 1
}

# wait_for_listener SECONDS PORT PID: waits until something listens on 127.0.0.1:PORT; fails at
# once if PID (the server being waited for) has exited, e.g. rot_open failed.
wait_for_listener() {
    local deadline=$((SECONDS + $1)) port=$2 pid=$3
    until (exec 3<>/dev/tcp/127.0.0.1/"$port") 2>/dev/null; do
        kill -0 "$pid" 2>/dev/null || return 1
        ((SECONDS < deadline)) || return 1
        sleep 0.1
    done
    kill -0 "$pid" 2>/dev/null
}
