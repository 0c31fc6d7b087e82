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

# ---- a stock rotctld with the backend preloaded, against the emulator (trixie-smoke.sh,
# arm-test.sh). Both run another system's rotctld through its own loader:
#   LOADER --library-path LIBS --preload BACKEND ROTCTLD ...
# where LOADER may itself be a command line (qemu-aarch64-static -L / /lib/ld-linux-aarch64.so.1).

# say TEXT: a progress line with the seconds since the script started (sourcing lib.sh).
SECONDS=0
say() { printf '[%3ds] %s\n' "$SECONDS" "$*"; }

# The servers a script starts in the background (pids+=($!)); stop_servers ends them all.
pids=()
stop_servers() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    wait 2>/dev/null || true
    pids=()
}

# winegard_models RUNNER...: how many Winegard models `RUNNER... -l` (a preloaded rotctld) lists.
winegard_models() { "$@" -l 2>/dev/null | grep -c Winegard || true; }

# arrive AZ EL SIM_LOG ROTCTLD_LOG ROTCTL...: polls `ROTCTL... p` until the backend reads AZ EL
# within 0.1 deg and the emulator's trace (SIM_LOG, --trace) shows the dish's own words for it:
# the G2's `Angle[0] = AZ.00` / `Angle[1] = EL.00`, or the older consoles' `AZ = AZ.00 EL = EL.00`.
arrive() {
    local az=$1 el=$2 sim_log=$3 rotctld_log=$4 reading=
    shift 4
    local deadline=$((SECONDS + 60))
    while ((SECONDS < deadline)); do
        reading=$("$@" p 2>/dev/null | tr '\n' ' ') || true
        if awk -v r="$reading" -v az="$az" -v el="$el" 'BEGIN {
                split(r, v, " "); d = v[1] - az; if (d < 0) d = -d; e = v[2] - el; if (e < 0) e = -e
                exit !(v[2] != "" && d < 0.1 && e < 0.1) }' &&
            { { grep -q "Angle\[0\] = $az.00" "$sim_log" && grep -q "Angle\[1\] = $el.00" "$sim_log"; } ||
                grep -q "AZ = $az.00 EL = $el.00" "$sim_log"; }; then
            say "p: $reading(at P $az $el; the dish printed it)"
            return 0
        fi
        sleep 0.2
    done
    echo "FAIL: the dish did not reach $az $el (last p: $reading); rotctld log:" >&2
    tail -30 "$rotctld_log" >&2
    return 1
}

# track_pass PORT SCALE STEP SECONDS CSV: tracks a pass (bench/passes/*.csv: t,az,el) through a
# rotctld the way Gpredict does: one connection, and every STEP seconds of pass time a `p` then a
# `P az el`, from where the pass rises above 20 deg (every dish's lowest elevation is below that)
# for at most SECONDS of pass time. The pass clock runs SCALE times faster than the wall clock,
# like the emulated dish. Every command must be answered; prints "COUNT AZ EL" of the last `P`.
track_pass() {
    local port=$1 scale=$2 step=$3 seconds=$4 csv=$5 t az el reply sent=0 last=
    exec 3<>"/dev/tcp/127.0.0.1/$port"
    while IFS=, read -r t az el; do
        printf 'p\n' >&3
        IFS= read -r -t 30 reply <&3 && IFS= read -r -t 30 reply <&3 ||
            { echo "FAIL: no answer to p at pass t=$t" >&2; exec 3>&-; return 1; }
        printf 'P %s %s\n' "$az" "$el" >&3
        IFS= read -r -t 30 reply <&3 || reply="(no answer)"
        [[ $reply == "RPRT 0" ]] || { echo "FAIL: P $az $el at pass t=$t: $reply" >&2; exec 3>&-; return 1; }
        sent=$((sent + 1)) last="$az $el"
        sleep "$(awk -v s="$scale" -v d="$step" 'BEGIN { print d / s }')"
    done < <(awk -F, -v step="$step" -v n="$seconds" '/^[0-9]/ && $3 >= 20 {
                if (t0 == "") t0 = $1
                if ($1 - t0 > n) exit
                if (($1 - t0) % step == 0) print $1 "," $2 "," $3 }' "$csv")
    exec 3>&-
    echo "$sent $last"
}
