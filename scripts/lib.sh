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

# doc_block DOC NAME: the lines of the fenced block that follows the line <!--run:NAME--> in DOC
# (docs/usage.md marks the commands a newcomer runs; the demo prints them, tests/docs runs them).
doc_block() {
    awk -v mark="<!--run:$2-->" '
        $0 == mark { found = 1; next }
        found && /^```/ { if (inside) exit; inside = 1; next }
        inside { print }' "$1"
}

# ---- Debian's packages for another system, unpacked, not installed (arm-test.sh, package.sh,
# trixie-smoke.sh).

# system_mirror: the mirror this machine's apt sources use for Debian's main archive (one-line or
# deb822 sources), for its own release.
system_mirror() {
    local codename
    codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-}")
    {
        cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
            awk -v c="$codename" '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^(https?|file):/ && $(i + 1) == c) { print $i; exit } }'
        cat /etc/apt/sources.list.d/*.sources 2>/dev/null |
            awk -v c="$codename" '/^URIs:/ { u = $2 } /^Suites:/ { for (i = 2; i <= NF; i++) if ($i == c && u != "") { print u; exit } } /^$/ { u = "" }'
    } | head -1
}

# debian_root ARCH SUITE DIR [--deps] PACKAGE... [--no-deps PACKAGE...]: Debian's PACKAGEs for
# ARCH from SUITE (main), fetched with apt-get download through a private apt configuration (its
# own sources, lists and cache in DIR; this machine's dpkg and apt state is neither read nor
# changed, and ARCH need not be one dpkg knows) and unpacked with dpkg-deb -x into DIR/root, never
# installed. The packages after --deps (the default) come with everything they depend on,
# recursively; those after --no-deps alone (the -dev packages: their headers and links, not the
# host toolchain's libc6-dev again). DIR/root also holds what a build needs to know of the
# packages without dpkg: DIR/root/var/lib/dpkg/status (their control, for dpkg-query --admindir)
# and DIR/root/DEBIAN/symbols and shlibs (theirs, merged, for dpkg-shlibdeps -S DIR/root).
# DIR is a cache: a call with the same arguments to the same debian_root (DIR/key holds both)
# reuses it; other arguments or a changed debian_root fetch again.
# The mirror is $debian_mirror, or this machine's (system_mirror).
debian_root() {
    local arch=$1 suite=$2 dir=$3 mirror=${debian_mirror:-} key deb
    shift 3
    [[ -n $mirror ]] || mirror=$(system_mirror)
    [[ -n $mirror ]] || { echo "debian_root: no Debian mirror in /etc/apt/sources* (set debian_mirror)" >&2; return 2; }
    key="$arch $suite $mirror $* $(declare -f debian_root | md5sum | cut -c1-12)"
    if [[ -f $dir/key && $(<"$dir/key") == "$key" ]]; then return 0; fi
    rm -rf "$dir/key" "$dir/sources.list" "$dir/empty" "$dir/lists" "$dir/cache" "$dir/debs" "$dir/root" "$dir/control"
    mkdir -p "$dir/empty" "$dir/lists/partial" "$dir/cache/archives/partial" "$dir/debs" "$dir/root/DEBIAN" "$dir/root/var/lib/dpkg/info"
    echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror $suite main" >"$dir/sources.list"
    local -a apt_options=(
        -o "APT::Architecture=$arch" -o "APT::Architectures::=$arch"
        -o "Dir::Etc::sourcelist=$dir/sources.list" -o "Dir::Etc::sourceparts=$dir/empty"
        -o "Dir::Etc::parts=$dir/empty" -o "Dir::Etc::preferencesparts=$dir/empty"
        -o "Dir::State::lists=$dir/lists" -o "Dir::Cache=$dir/cache"
        -o Dir::State::status=/dev/null -o Debug::NoLocking=1 -o APT::Sandbox::User=root
        -o Acquire::Languages=none
    )
    say "apt-get update ($suite main for $arch, private lists in $dir)"
    apt-get "${apt_options[@]}" -qq update || return 1
    local -a deps=() plain=() packages=()
    local mode=deps p
    for p in "$@"; do
        case $p in
        --deps) mode=deps ;;
        --no-deps) mode=plain ;;
        *) if [[ $mode == deps ]]; then deps+=("$p"); else plain+=("$p"); fi ;;
        esac
    done
    if ((${#deps[@]})); then
        mapfile -t packages < <(apt-cache "${apt_options[@]}" depends --recurse --no-recommends --no-suggests \
            --no-conflicts --no-breaks --no-replaces --no-enhances "${deps[@]}" | grep -v '^[ <]' | sort -u)
    fi
    packages+=("${plain[@]}")
    say "apt-get download ${packages[*]}"
    (cd "$dir/debs" && apt-get "${apt_options[@]}" -qq download "${packages[@]}") || return 1
    local control=$dir/control
    for deb in "$dir"/debs/*.deb; do
        dpkg-deb -x "$deb" "$dir/root"
        rm -rf "$control" && dpkg-deb -e "$deb" "$control"
        if [[ -f $control/symbols ]]; then cat "$control/symbols" >>"$dir/root/DEBIAN/symbols"; fi
        if [[ -f $control/shlibs ]]; then cat "$control/shlibs" >>"$dir/root/DEBIAN/shlibs"; fi
        { sed '/^Package:/a Status: install ok installed' "$control/control"; echo; } >>"$dir/root/var/lib/dpkg/status"
    done
    rm -rf "$control"
    # A link to an absolute path (libtinfo.so -> /lib/<triplet>/libtinfo.so.6) points into this
    # machine, not the root: make it relative, within the root.
    local link target
    while IFS= read -r -d '' link; do
        target=$(readlink "$link")
        ln -sfn "$(realpath -m -s --relative-to="$(dirname "$link")" "$dir/root$target")" "$link"
    done < <(find "$dir/root" -type l -lname '/*' -print0)
    echo "$key" >"$dir/key"
}

# pi_sysroot ARCH: the sysroot of the Raspberry Pi builds (arm-test.sh, package.sh) for Debian
# ARCH (arm64, armhf), as debian_root makes it in $root/build-sysroot-ARCH, whose root/ is the
# sysroot: Debian 12's libraries the build links and their -dev packages, the C++ runtime and the
# ARM loader and libc that qemu-user runs the programs with (-L), Catch2 for the unit tests, and
# Debian 12's own rotctld (libhamlib-utils) that arm-test.sh drives.
pi_sysroot() {
    debian_root "$1" bookworm "$root/build-sysroot-$1" \
        --deps libhamlib-utils libhamlib4 libserialport0 libncurses6 libtinfo6 libstdc++6 \
        --no-deps libhamlib-dev libusb-1.0-0-dev libserialport-dev libncurses-dev catch2
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
# `P az el`, from where the pass rises above 20 deg (every dish's lowest elevation is below that;
# MIN_EL, the optional sixth argument, sets another) for at most SECONDS of pass time. The pass clock runs SCALE times faster than the wall clock,
# like the emulated dish. Every command must be answered; prints "COUNT AZ EL" of the last `P`.
track_pass() {
    local port=$1 scale=$2 step=$3 seconds=$4 csv=$5 min_el=${6:-20} t az el reply sent=0 last=
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
    done < <(awk -F, -v step="$step" -v n="$seconds" -v min_el="$min_el" '/^[0-9]/ && $3 >= min_el {
                if (t0 == "") t0 = $1
                if ($1 - t0 > n) exit
                if (($1 - t0) % step == 0) print $1 "," $2 "," $3 }' "$csv")
    exec 3>&-
    echo "$sent $last"
}

# dish_e2e LABEL VARIANT NAME MODEL ROTCTLD...: the end-to-end check every preload route passes
# (arm-test.sh: an ARM rotctld under qemu with the backend preloaded; trixie-smoke.sh: Debian 13's
# rotctld through its own loader with the backend preloaded; hamlib-intree.sh has its own, at real
# time: the in-tree backend has no time_scale key). ROTCTLD... is the command line that runs
# that rotctld (a loader and its options first, if any). It opens the emulated VARIANT as MODEL
# (the auto-detecting model, no -s: auto-detection finds the baud rate too); `_` must name NAME
# as auto-detected; `P`/`p` reach a target the dish itself prints; a pass is tracked the way
# Gpredict does it (one connection, a `P` every few pass seconds); `P` after the pass lands
# exactly; `S` is answered; the emulator reports 0 hazardous commands at exit.
# Globals: e2e_sim (birdcage-sim), e2e_work (logs), e2e_client (the rotctl command line, default
# this machine's rotctl), root (the project). If the caller defines e2e_while_running, it is
# called with rotctld's pid while rotctld serves.
dish_e2e() {
    local label=$1 variant=$2 name=$3 model=$4 time_scale=20 dev port sim_pid rotctld_pid log
    shift 4
    log=$e2e_work/$label-$variant
    dev=$log.tty
    port=$(free_port 4700 4749)
    "$e2e_sim" --variant "$variant" --link "$dev" --time-scale "$time_scale" --az 100 --el 30 --trace \
        >"$log.sim.log" 2>&1 &
    sim_pid=$!
    pids+=("$sim_pid")
    wait_for 10 test -e "$dev" || { echo "FAIL: the emulator did not start" >&2; return 1; }
    "$@" -m "$model" -r "$dev" -T 127.0.0.1 -t "$port" -C "time_scale=$time_scale" -vvvv >"$log.rotctld.log" 2>&1 &
    rotctld_pid=$!
    pids+=("$rotctld_pid")
    if ! wait_for_listener 120 "$port" "$rotctld_pid"; then
        echo "FAIL: $label rotctld did not listen; its log:" >&2
        tail -20 "$log.rotctld.log" >&2
        return 1
    fi
    if declare -F e2e_while_running >/dev/null; then e2e_while_running "$rotctld_pid" || return 1; fi
    local -a client=("${e2e_client[@]:-rotctl}")
    rc() { "${client[@]}" -m 2 -r "127.0.0.1:$port" "$@"; }
    local info
    info=$(rc _ | tr '\n' ' ')
    say "$label $variant _: $info"
    [[ $info == *"$name"*"(auto-detected)"* ]] || { echo "FAIL: auto-detect did not name $name" >&2; return 1; }
    rc P 200 40
    arrive 200 40 "$log.sim.log" "$log.rotctld.log" rc || return 1

    local sent last_az last_el
    read -r sent last_az last_el < <(track_pass "$port" "$time_scale" 5 1000 "$root/bench/passes/iss-45.csv") ||
        return 1
    [[ $sent -gt 10 ]] || { echo "FAIL: the pass sent $sent P commands" >&2; return 1; }
    # Tracking, the dish aims ahead of the satellite and leaves it alone within a deadband: it
    # ends near the pass's last point (it started at 200 40, 120 deg away), not exactly on it.
    local deadline=$((SECONDS + 60)) reading=
    until awk -v r="$reading" -v az="$last_az" -v el="$last_el" 'BEGIN {
            split(r, v, " "); d = v[1] - az; if (d < 0) d = -d; e = v[2] - el; if (e < 0) e = -e
            exit !(v[2] != "" && d < 3 && e < 3) }'; do
        ((SECONDS < deadline)) || { echo "FAIL: after the pass the dish is at $reading, not near $last_az $last_el" >&2; return 1; }
        sleep 0.2
        reading=$(rc p | tr '\n' ' ')
    done
    say "$label $variant: p $reading after the pass (its last point: $last_az $last_el)"
    # Manual pointing after the pass: exactly where it is sent.
    rc P 150 35
    arrive 150 35 "$log.sim.log" "$log.rotctld.log" rc || return 1
    rc S || { echo "FAIL: $label $variant: S was refused" >&2; return 1; }
    say "$label $variant: tracked iss-45 above 20 deg ($sent P commands), then P 150 35, then S"
    # rotctld first, then the emulator, which reports at exit what the hazard rule caught.
    kill "$rotctld_pid"; wait "$rotctld_pid" 2>/dev/null || true
    kill "$sim_pid"; wait "$sim_pid" 2>/dev/null || true
    pids=()
    grep -q "hazards received: 0$" "$log.sim.log" ||
        { echo "FAIL: $label $variant: $(grep "hazards received" "$log.sim.log")" >&2; return 1; }
    say "$label $variant: 0 hazards"
}
