#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The backend inside Hamlib's own tree: no preload, `rotctld -m <winegard model>` from a Hamlib
# built from source (docs/hamlib-versions.md, "The in-tree route"; upstream/hamlib/README.md).
#  1. unpacks a Hamlib source tarball (a `git archive` of a tag or of master) into BUILD_DIR,
#     `git init`s it and commits the pristine tree;
#  2. adds the contribution, generated from this project's sources at this moment, in three
#     commits written out as `git format-patch` files into BUILD_DIR/patches: rotctl's `w` hook
#     for backends, the backend's directory (the files its entry points reach, in-tree variants),
#     its registration behind configure's --with-winegard;
#  3. bootstraps, configures with --with-winegard (no bindings, no static library, no optional
#     backends), builds libhamlib, rotctld and rotctl only;
#  4. checks libhamlib's exports, that `rotctl -l` lists the models, rotctld's open bound on a
#     silent port, then drives the emulated G2 and Trav'ler HAL 2.05 with the built rotctld at
#     -vvvvv: auto-detection, the console bytes in Hamlib's own I/O log, `P`/`p`, rotctl's raw `w`
#     refused for hazard words, `S`, no hazard at the emulator, no LD_PRELOAD anywhere;
#  5. with --mingw: configures the patched tree without the switch for Windows (Hamlib's
#     windows-cross-no-features line, Debian's mingw-w64) and compiles what the patch touches.
# Prints each stage's time; exits non-zero with one FAIL line on any failure.
#
#   scripts/hamlib-intree.sh [--patches DIR] [--sim BIRDCAGE_SIM] [--mingw] [--full] [--reuse] TARBALL [BUILD_DIR]
# BUILD_DIR: default build-hamlib/<tarball name> in the clone (git-ignored), kept afterwards:
# hamlib/ (the patched git tree), build/ (Hamlib's build), patches/, logs/, birdcage/ (this
# project's CMake build, for the emulator), times.txt, summary.txt.
# --sim: an emulator already built (default: built here from the project).
# --mingw: the Windows cross check of step 5 (needs g++-mingw-w64-x86-64-posix).
# --full: build the whole tree instead (with the switch, then without it, and with --mingw the
#   whole Windows cross build), and check that libhamlib needs no C++ runtime without the switch.
# --reuse: keep BUILD_DIR's patched, configured tree and write only rotators/winegard afresh (for
#   work on the backend; the patches are not rewritten).
# HAMLIB_WINEGARD_FAMILY: the rotator backend number proposed (default: the next free one in the
# tree's rotlist.h).
set -euo pipefail
# Nothing this script starts may inherit a preload (the check below looks for it).
unset LD_PRELOAD
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

fail() { echo "hamlib-intree: FAIL: $*" >&2; exit 1; }
# Any other command that fails ends the script (set -e) with one line naming it.
trap 'echo "hamlib-intree: FAIL: line $LINENO: $BASH_COMMAND" >&2' ERR
usage() { sed -n '21,33s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; }

patches= sim= mingw=0 full=0 reuse=0 args=()
while (($#)); do
    case "$1" in
    --patches) [[ $# -ge 2 ]] || fail "--patches needs a directory"; patches=$2; shift 2 ;;
    --sim) [[ $# -ge 2 ]] || fail "--sim needs the emulator's path"; sim=$2; shift 2 ;;
    --mingw) mingw=1; shift ;;
    --full) full=1; shift ;;
    --reuse) reuse=1; shift ;;
    -h | --help) usage; exit 0 ;;
    -*) echo "hamlib-intree: unknown option '$1'" >&2; usage >&2; exit 2 ;;
    *) args+=("$1"); shift ;;
    esac
done
((${#args[@]} >= 1 && ${#args[@]} <= 2)) || { usage >&2; exit 2; }
tarball=${args[0]}
[[ -f $tarball ]] || fail "no Hamlib tarball at $tarball"
tarball=$(cd "$(dirname "$tarball")" && pwd)/$(basename "$tarball")
name=$(basename "$tarball")
name=${name%.tar.*}
out=${args[1]:-$root/build-hamlib/$name}
mkdir -p "$out"
out=$(cd "$out" && pwd)
tree=$out/hamlib build=$out/build logs=$out/logs
patches=${patches:-$out/patches}

# shellcheck source=scripts/lib.sh
. "$root/scripts/lib.sh"
trap stop_servers EXIT

declare -A took=()
stage() { took[$1]=$((SECONDS - stage_start)); say "$1: ${took[$1]} s"; }

# Hamlib's bootstrap needs the autotools; everything else is the project's own list.
extra="autoconf automake libtool"
((mingw)) && extra+=" g++-mingw-w64-x86-64-posix"
BIRDCAGE_SETUP_EXTRA="$extra ${BIRDCAGE_SETUP_EXTRA:-}" "$root/scripts/setup.sh"

# ---- the emulator ------------------------------------------------------------------------------
mkdir -p "$logs"
if [[ -z $sim ]]; then
    project=$out/birdcage
    say "building the emulator (birdcage-sim) in $project"
    cmake -S "$root" -B "$project" -DBIRDCAGE_BUILD_TESTS=OFF -DBIRDCAGE_WERROR=ON >"$logs/project-cmake.log" 2>&1 ||
        { tail -20 "$logs/project-cmake.log" >&2; fail "configuring the project"; }
    nice cmake --build "$project" -j2 --target birdcage-sim >"$logs/project-build.log" 2>&1 ||
        { tail -30 "$logs/project-build.log" >&2; fail "building birdcage-sim"; }
    sim=$project/sim/birdcage-sim
fi
[[ -x $sim ]] || fail "no emulator at $sim"
sim=$(cd "$(dirname "$sim")" && pwd)/$(basename "$sim")

# The patched tree, its patches, and its configured build (all but --reuse).
make_tree() {
# ---- 1. the pristine tree -----------------------------------------------------------------------
say "unpacking $tarball into $tree"
rm -rf "$tree" "$build" "$patches" "$out/build-off" "$out/build-mingw"
mkdir -p "$tree" "$patches"
tar -xf "$tarball" -C "$tree" --strip-components=1
[[ -f $tree/include/hamlib/rotlist.h && -f $tree/src/rot_reg.c && -f $tree/configure.ac ]] ||
    fail "$tarball is not a Hamlib source tree (no include/hamlib/rotlist.h, src/rot_reg.c, configure.ac)"
author=$(git -C "$root" log -1 --format='%an <%ae>' 2>/dev/null || echo "birdcage <birdcage@invalid>")
g() {
    git -C "$tree" -c user.name="${author% <*}" -c user.email="$(echo "${author#* <}" | tr -d '>')" \
        -c commit.gpgsign=false "$@"
}
g init -q
g add -A
g commit -q -m "Hamlib $name, as unpacked"
pristine=$(g rev-parse HEAD)

# ---- 2. the contribution, from the project's sources --------------------------------------------
python3 "$root/scripts/hamlib_contribution.py" hook "$root" "$tree" || fail "rotctl's w hook (above)"
g add -A
g commit -q -F - <<'EOF'
rotators: let a backend take rotctl's raw w command (rot_caps.send_cmd)

rotctl's w (send_cmd) writes the client's text straight to the rotator's
port with write_block, and rotctld passes it from any TCP client. A backend
that holds a session with its device (a menu, a state, commands that harm
it) cannot let text go around it. A backend that sets the new
rot_caps.send_cmd gets the text instead, and sends it through its own
session or refuses it; without it, w works as before.
EOF

python3 "$root/scripts/hamlib_contribution.py" backend "$root" "$tree" >"$out/summary.txt" ||
    fail "generating the backend (above)"
cat "$out/summary.txt"
g add -A
g commit -q -F - <<'EOF'
rotators/winegard: new backend for Winegard motorised satellite dishes

Trav'ler, Trav'ler Pro, Carryout and Carryout G2 dishes driven through their
serial consoles, with one model that identifies the firmware variant at
open. The caps are C (winegard.c); the operations are C++17 behind the C
interface in winegard.h, over the dish-control core in core/, as
rotators/indi does it. Every byte goes through Hamlib's port I/O; every C
entry point catches and returns -RIG_E* codes; logging is rig_debug only;
only the init function is visible outside libhamlib.
EOF

family=$(python3 "$root/scripts/hamlib_contribution.py" register "$root" "$tree" "${HAMLIB_WINEGARD_FAMILY:-}") ||
    fail "registering the backend (above)"
g add -A
g commit -q -F - <<EOF
Register the Winegard backend as rotator backend $family (--with-winegard)

rotlist.h: ROT_WINEGARD $family and its models. rot_reg.c lists it, and
configure.ac builds it, only with --with-winegard (default: no) on a POSIX
host with a C++17 compiler; libhamlib is then linked by the C++ compiler
(libtool adds the C++ runtime), and stays C otherwise.
EOF
g format-patch -q -o "$patches" "$pristine"..HEAD
patch_stat=$(g diff --shortstat "$pristine" HEAD)
say "patches: $(ls "$patches" | tr '\n' ' ')($(echo $patch_stat))"
}

# Only what rotctld and rotctl need: no static library, no language bindings, no optional
# hardware backends that pull in libraries.
configure_hamlib() {
    local dir=$1
    shift
    mkdir -p "$dir"
    (cd "$dir" && "$tree/configure" --disable-static --without-cxx-binding --without-perl-binding \
        --without-python-binding --without-tcl-binding --without-lua-binding --disable-winradio \
        --without-indi --without-libusb --disable-html-matrix --without-readline "$@")
}

if ((reuse)) && [[ -f $build/Makefile && -d $tree/.git ]]; then
    say "reusing $tree and $build: rotators/winegard written afresh"
    python3 "$root/scripts/hamlib_contribution.py" backend --update "$root" "$tree" >"$out/summary.txt" ||
        fail "generating the backend (above)"
    family=$(sed -n 's/^#define ROT_WINEGARD \([0-9]*\)$/\1/p' "$tree/include/hamlib/rotlist.h")
    patch_stat="(reused tree)"
else
    make_tree

    # ---- 3. bootstrap, configure, build ----------------------------------------------------------
    stage_start=$SECONDS
    (cd "$tree" && ./bootstrap) >"$logs/bootstrap.log" 2>&1 || { tail -30 "$logs/bootstrap.log" >&2; fail "bootstrap"; }
    stage bootstrap

    stage_start=$SECONDS
    configure_hamlib "$build" --with-winegard >"$logs/configure.log" 2>&1 ||
        { tail -30 "$logs/configure.log" >&2; fail "configure --with-winegard"; }
    grep -q '^ROT_BACKEND_LIST = .*rotators/winegard' "$build/Makefile" &&
        grep -q '^#define HAVE_WINEGARD 1' "$build/include/hamlib/config.h" ||
        fail "configure --with-winegard did not add rotators/winegard; see $logs/configure.log"
    stage configure
fi

# libhamlib with every backend it links, then the two programs; the rest of the tree (the other
# utilities, tests, docs) is not needed here. The top Makefile's own SUBDIRS loop, narrowed to
# those directories.
build_hamlib() {
    local dir=$1 log=$2 upto_src
    if ((full)); then
        nice make -j2 -C "$dir" >"$log" 2>&1
    else
        upto_src=$(make -s -C "$dir" -f Makefile -f - print-subdirs <<<'print-subdirs: ; @echo $(SUBDIRS)' |
            tr ' ' '\n' | sed '/^src$/q' | tr '\n' ' ')
        nice make -j2 -C "$dir" SUBDIRS="$upto_src" >"$log" 2>&1 &&
            nice make -j2 -C "$dir/tests" rotctld rotctl >>"$log" 2>&1
    fi
}
stage_start=$SECONDS
build_hamlib "$build" "$logs/build.log" ||
    { grep -E "error|Error" "$logs/build.log" | head -20 >&2; fail "build (see $logs/build.log)"; }
warnings=$(grep -c "rotators/winegard/.*warning:" "$logs/build.log" || true)
((warnings == 0)) || { grep "rotators/winegard/.*warning:" "$logs/build.log" | head -10 >&2; fail "$warnings compiler warnings in rotators/winegard"; }
stage build

# ---- 4. the built library and programs -----------------------------------------------------------
stage_start=$SECONDS
library=$(ls "$build"/src/.libs/libhamlib.so.* | head -1)
ours=$(nm -D --defined-only "$library" | c++filt | grep -c 'birdcage' || true)
((ours == 0)) || { nm -D --defined-only "$library" | c++filt | grep birdcage | head -5 >&2; fail "libhamlib exports $ours symbols of the birdcage namespace"; }
entry=$(nm -D --defined-only "$library" | awk '$3 ~ /winegard/ {print $3}' | tr '\n' ' ')
[[ $entry == "initrots"[0-9]"_winegard " ]] || fail "libhamlib's Winegard exports are '$entry', expected the init function alone"
say "libhamlib exports of the backend: $entry(no birdcage symbol)"

rotctld=$build/tests/rotctld rotctl=$build/tests/rotctl
[[ -x $rotctld && -x $rotctl ]] || fail "no rotctld/rotctl in $build/tests"
say "rotctld: $("$rotctld" --version | head -1)"
# The models rotlist.h.in defines, numbered in this backend: N01 (auto-detect) onwards.
expected=$(sed -n 's/.*ROT_MAKE_MODEL(ROT_WINEGARD, \([0-9]*\)).*/\1/p' "$root/src/hamlib/rotlist.h.in" |
    awk -v f="$family" '{print f * 100 + $1}' | tr '\n' ' ')
listed=$("$rotctl" -l | awk '/Winegard/ {print $1}' | sort -n | tr '\n' ' ')
[[ $listed == "$expected" ]] || fail "rotctl -l lists the Winegard models as '$listed', expected '$expected'"
auto_model=${expected%% *}
say "rotctl -l: Winegard models $listed"
# The conf keys the generated conf table has are the ones rotctl -L lists beside Hamlib's own
# (those another serial rotator, the GS-232A, lists too).
conf_keys() {
    "$rotctl" -m "$1" -r /nonexistent/port -L 2>/dev/null | sed -n 's/^\([a-z_0-9]*\): ".*/\1/p' | sort || true
}
conf_expected=$(sed -n 's/^conf keys: //p' "$out/summary.txt" | tr ' ' '\n' | sort | tr '\n' ' ')
serial_model=$("$rotctl" -l | awk '$NF == "ROT_MODEL_GS232A" {print $1}')
conf_listed=$(comm -23 <(conf_keys "$auto_model") <(conf_keys "$serial_model") | tr '\n' ' ')
[[ -n $conf_expected && $conf_listed == "$conf_expected" ]] ||
    fail "rotctl -L lists '$conf_listed' beside Hamlib's keys, the conf table '$conf_expected'"
say "rotctl -L: the conf table's ${conf_expected// /, }"

# rot_open on a port where nothing answers: an error within boot_timeout (here 1 s: the
# synchroniser still gives a console three rounds, about 5 s), never a wait without end.
silent=$logs/silent.tty
python3 -c 'import os, sys, time, pty
m, s = pty.openpty(); os.symlink(os.ttyname(s), sys.argv[1]); time.sleep(120)' "$silent" &
pids+=($!)
wait_for 10 test -e "$silent" || fail "no silent pty"
open_start=$SECONDS
g2_model=$("$rotctl" -l | awk '/Winegard/ && /Carryout G2/ {print $1}')
if timeout 60 "$rotctld" -m "$g2_model" -r "$silent" -T 127.0.0.1 -t 0 -C boot_timeout=1 -vvvv \
    >"$logs/silent.log" 2>&1; then
    fail "rotctld opened a port where nothing answers"
fi
open_took=$((SECONDS - open_start))
grep -q "rot_open: error" "$logs/silent.log" || { tail -5 "$logs/silent.log" >&2; fail "rotctld on a silent port did not report the failed open"; }
((open_took <= 15)) || fail "rot_open on a silent port took $open_took s"
say "rot_open on a silent port: error after $open_took s ($(grep -m1 -o 'console did not come into sync[^;]*' "$logs/silent.log" || true))"
stop_servers

# No process of this tree may carry LD_PRELOAD, and rotctld must not have loaded a preload build.
check_no_preload() {
    local rotctld_pid=$1 p
    local -a tree_pids=()
    mapfile -t tree_pids < <(descendants $$)
    for p in "${tree_pids[@]}"; do
        # A process that ended since the list was taken (ps itself) has nothing to check.
        if { tr '\0' '\n' <"/proc/$p/environ"; } 2>/dev/null | grep -q '^LD_PRELOAD='; then
            fail "process $p ($(tr '\0' ' ' <"/proc/$p/cmdline")) has LD_PRELOAD in its environment"
        fi
    done
    ! grep -q "libhamlib-winegard" "/proc/$rotctld_pid/maps" || fail "rotctld loaded a preload build of the backend"
    grep -q "$build/src/.libs/libhamlib.so" "/proc/$rotctld_pid/maps" ||
        fail "rotctld (pid $rotctld_pid) did not load the libhamlib built in $build"
}
descendants() {
    local p
    for p in $(ps -o pid= --ppid "$1"); do
        echo "$p"
        descendants "$p"
    done
}

# One rotctld line (a raw TCP exchange, as any client may send it): prints its answer.
ask() {
    local port=$1 line=$2 reply
    exec 4<>"/dev/tcp/127.0.0.1/$port"
    printf '%s\n' "$line" >&4
    IFS= read -r -t 30 reply <&4 || reply="(no answer)"
    exec 4>&-
    echo "$reply"
}

# The emulated VARIANT at real time (the in-tree backend has no time_scale key) with fast motors,
# opened as the auto-detecting model by rotctld -vvvvv.
intree_e2e() {
    local variant=$1 name=$2 log=$logs/intree-$1 dev port sim_pid rotctld_pid info word reply
    dev=$log.tty
    port=$(free_port 4750 4799)
    "$sim" --variant "$variant" --link "$dev" --motor-speed 60,60 --motor-accel 240 --az 100 --el 30 --trace \
        >"$log.sim.log" 2>&1 &
    sim_pid=$!
    pids+=("$sim_pid")
    wait_for 10 test -e "$dev" || fail "the emulator did not start"
    "$rotctld" -m "$auto_model" -r "$dev" -T 127.0.0.1 -t "$port" -vvvvv >"$log.rotctld.log" 2>&1 &
    rotctld_pid=$!
    pids+=("$rotctld_pid")
    wait_for_listener 120 "$port" "$rotctld_pid" || { tail -20 "$log.rotctld.log" >&2; fail "$variant: rotctld did not listen"; }
    check_no_preload "$rotctld_pid"
    rc() { "$rotctl" -m 2 -r "127.0.0.1:$port" "$@"; }
    info=$(rc _ | tr '\n' ' ')
    say "$variant _: $info"
    [[ $info == *"$name"*"(auto-detected)"* ]] || fail "$variant: auto-detect did not name $name"
    rc P 200 40
    arrive 200 40 "$log.sim.log" "$log.rotctld.log" rc || fail "$variant: P 200 40"
    # rotctl's raw w: refused by the backend (RPRT -9, -RIG_ERJCTED), nothing reaches the console.
    for word in r e life q reboot; do
        reply=$(ask "$port" "w $word")
        [[ $reply == "RPRT -9" ]] || fail "$variant: w $word answered '$reply', expected RPRT -9"
    done
    rc P 150 35
    arrive 150 35 "$log.sim.log" "$log.rotctld.log" rc || fail "$variant: P 150 35"
    rc S || fail "$variant: S was refused"
    kill "$rotctld_pid"; wait "$rotctld_pid" 2>/dev/null || true
    kill "$sim_pid"; wait "$sim_pid" 2>/dev/null || true
    pids=()
    grep -q "hazards received: 0$" "$log.sim.log" || fail "$variant: $(grep "hazards received" "$log.sim.log")"
    # The console's bytes in Hamlib's own I/O log: write_block's and read_block's dumps.
    local tx rx
    tx=$(grep -c "write_block(): TX" "$log.rotctld.log" || true)
    rx=$(grep -c "read_block.*RX" "$log.rotctld.log" || true)
    ((tx > 0 && rx > 0)) || fail "$variant: rotctld -vvvvv shows $tx write_block and $rx read_block dumps"
    say "$variant: P/p, w r|e|life|q|reboot refused, S; 0 hazards; $tx write_block and $rx read_block dumps at -vvvvv"
}

intree_e2e g2 "Carryout G2"
intree_e2e hal205 "Trav'ler HAL 2.05"
stage e2e

# ---- 5. without the switch: no C++ in libhamlib, and Windows -----------------------------------
if ((full)); then
    stage_start=$SECONDS
    configure_hamlib "$out/build-off" >"$logs/configure-off.log" 2>&1 || fail "configure without --with-winegard"
    ! grep -q '^ROT_BACKEND_LIST = .*rotators/winegard' "$out/build-off/Makefile" || fail "rotators/winegard built without the switch"
    build_hamlib "$out/build-off" "$logs/build-off.log" || fail "build without the switch (see $logs/build-off.log)"
    off_library=$(ls "$out"/build-off/src/.libs/libhamlib.so.* | head -1)
    needed=$(readelf -d "$off_library" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p' | tr '\n' ' ')
    [[ $needed != *"stdc++"* && $needed != *"c++"* ]] || fail "libhamlib without the switch needs $needed"
    say "without --with-winegard: libhamlib needs $needed"
    stage off
fi
if ((mingw)); then
    stage_start=$SECONDS
    # Hamlib's windows-cross-no-features configure line, with Debian's posix-threads mingw-w64.
    mkdir -p "$out/build-mingw"
    (cd "$out/build-mingw" && "$tree/configure" --host=x86_64-w64-mingw32 CC=x86_64-w64-mingw32-gcc-posix \
        CXX=x86_64-w64-mingw32-g++-posix --without-cxx-binding --without-libusb --without-samplerate \
        --disable-static) >"$logs/configure-mingw.log" 2>&1 || { tail -20 "$logs/configure-mingw.log" >&2; fail "mingw configure"; }
    if ((full)); then
        nice make -j2 -C "$out/build-mingw" >"$logs/build-mingw.log" 2>&1 ||
            { grep -E "error" "$logs/build-mingw.log" | head >&2; fail "the mingw build"; }
        say "mingw: $(ls "$out"/build-mingw/src/.libs/*.dll | xargs -n1 basename) and $(ls "$out"/build-mingw/tests/.libs/rotctld.exe "$out"/build-mingw/tests/rotctld.exe 2>/dev/null | head -1 | xargs -r basename)"
    else
        # What the patch touches on this host: rot_reg.c, rotator.h's rot_caps, rotctl's w.
        nice make -C "$out/build-mingw/src" hamlibdatetime.h rot_reg.lo rotator.lo >"$logs/build-mingw.log" 2>&1 &&
            nice make -C "$out/build-mingw/tests" rotctld-rotctl_parse.o rotctl-rotctl_parse.o >>"$logs/build-mingw.log" 2>&1 ||
            { grep -E "error" "$logs/build-mingw.log" | head >&2; fail "compiling the patched files for Windows"; }
        say "mingw: the patched rot_reg.c, rotator.c and rotctl_parse.c compile for x86_64-w64-mingw32"
    fi
    stage mingw
fi

{
    echo "hamlib: $name"
    echo "patch: $(ls "$patches" | wc -l) files,$patch_stat"
    for s in bootstrap configure build e2e off mingw; do [[ -n ${took[$s]:-} ]] && echo "$s: ${took[$s]} s"; done
} >"$out/times.txt"
say "PASS: $name with the Winegard backend in-tree (backend $family): $(tr '\n' ' ' <"$out/times.txt"); kept in $out"
