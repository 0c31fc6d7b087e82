#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
# The backend inside Hamlib's own tree: no preload, `rotctld -m <winegard model>` from a Hamlib
# built from source (docs/hamlib-versions.md, "The in-tree route"; upstream/hamlib/README.md).
#  1. unpacks a Hamlib source tarball (a `git archive` of a tag or of master) into BUILD_DIR,
#     `git init`s it and commits the pristine tree;
#  2. adds the contribution, generated from this project's sources at this moment (the caps in
#     src/hamlib/, the C++ beside them and the whole core), in two commits, and writes them
#     as `git format-patch` files into BUILD_DIR/patches;
#  3. bootstraps, configures (no bindings, no static library, no optional backends), builds
#     libhamlib with rotctld/rotctl and the rest of what `make check` needs, runs Hamlib's own
#     `make check`;
#  4. checks that `rotctl -l` lists the Winegard models under their new numbers, then runs that
#     rotctld against the emulator (lib.sh's dish_e2e: auto-detect, `_`, `P`/`p`, a tracked pass,
#     `S`), with no LD_PRELOAD in any process of the tree.
# Prints each stage's time; exits non-zero with one FAIL line on any failure.
#
#   scripts/hamlib-intree.sh [--patches DIR] [--sim BIRDCAGE_SIM] TARBALL [BUILD_DIR]
# BUILD_DIR: default build-hamlib/<tarball name> in the clone (git-ignored), kept afterwards:
# hamlib/ (the patched git tree), build/ (Hamlib's build: build/tests/rotctld, build/tests/rotctl),
# patches/, logs/, birdcage/ (this project's CMake build, for the emulator), times.txt.
# --sim: an emulator already built (default: built here from the project).
# HAMLIB_WINEGARD_FAMILY: the rotator backend number proposed for the Winegard models (default
# 29, the next free one in Hamlib 4.6.2, 4.7.2 and master; the script checks it is free).
set -euo pipefail
# Nothing this script starts may inherit a preload (the check below looks for it).
unset LD_PRELOAD
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
family=${HAMLIB_WINEGARD_FAMILY:-29}

fail() { echo "hamlib-intree: FAIL: $*" >&2; exit 1; }
# Any other command that fails ends the script (set -e) with one line naming it.
trap 'echo "hamlib-intree: FAIL: line $LINENO: $BASH_COMMAND" >&2' ERR
usage() { sed -n '19,25s/^# \{0,1\}//p' "${BASH_SOURCE[0]}"; }

patches= sim= args=()
while (($#)); do
    case "$1" in
    --patches) [[ $# -ge 2 ]] || fail "--patches needs a directory"; patches=$2; shift 2 ;;
    --sim) [[ $# -ge 2 ]] || fail "--sim needs the emulator's path"; sim=$2; shift 2 ;;
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
BIRDCAGE_SETUP_EXTRA="autoconf automake libtool ${BIRDCAGE_SETUP_EXTRA:-}" "$root/scripts/setup.sh"

# ---- the project: the emulator, and the compiler's view of the backend (its include paths) ------
project=$out/birdcage
mkdir -p "$logs"
cmake -S "$root" -B "$project" -DBIRDCAGE_BUILD_TESTS=OFF -DBIRDCAGE_WERROR=ON >"$logs/project-cmake.log" 2>&1 ||
    { tail -20 "$logs/project-cmake.log" >&2; fail "configuring the project"; }
if [[ -z $sim ]]; then
    say "building the emulator (birdcage-sim) in $project"
    nice cmake --build "$project" -j2 --target birdcage-sim >"$logs/project-build.log" 2>&1 ||
        { tail -30 "$logs/project-build.log" >&2; fail "building birdcage-sim"; }
    sim=$project/sim/birdcage-sim
fi
[[ -x $sim ]] || fail "no emulator at $sim"
sim=$(cd "$(dirname "$sim")" && pwd)/$(basename "$sim")

# ---- 1. the pristine tree -----------------------------------------------------------------------
say "unpacking $tarball into $tree"
rm -rf "$tree" "$build" "$patches"
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
python3 - "$root" "$project" "$tree" "$family" <<'PY' || fail "generating the contribution (above)"
import json, os, re, shutil, sys

root, project, tree, family = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
backend = os.path.join(tree, "rotators", "winegard")

def die(message):
    print("hamlib-intree: " + message, file=sys.stderr)
    sys.exit(1)

# Where a project file goes in the backend's directory: the caps and the C++ of src/hamlib at its
# top, as every Hamlib backend is laid out; the core keeps its paths below src/ (core/...).
def tree_path(rel):
    if rel.startswith("src/hamlib/"):
        return rel[len("src/hamlib/"):]
    if rel.startswith("src/"):
        return rel[len("src/"):]
    return rel

def project_files(top, suffixes):
    found = []
    for directory, _, names in os.walk(os.path.join(root, top)):
        for n in names:
            if n.endswith(suffixes):
                found.append(os.path.relpath(os.path.join(directory, n), root))
    return sorted(found)

# The backend's own files (not preload/: that is the preload build's) and the whole core, except
# what needs libserialport (the backend talks through Hamlib's fd; Hamlib has no libserialport).
files = [os.path.join("src/hamlib", n) for n in sorted(os.listdir(os.path.join(root, "src/hamlib")))
          if n.endswith((".c", ".cpp", ".h", ".hpp"))]
core = project_files("src/core", (".cpp", ".hpp", ".h"))
skipped = [f for f in core if f.endswith(".cpp") and "<libserialport.h>" in open(os.path.join(root, f)).read()]
files += [f for f in core if f not in skipped]

# The include paths the project's own build compiles the backend with, as the tree's.
commands = json.load(open(os.path.join(project, "compile_commands.json")))
ops = [c for c in commands if c["file"].endswith("src/hamlib/winegard_ops.cpp")]
if not ops:
    die("the project's compile_commands.json has no src/hamlib/winegard_ops.cpp")
# The C++ standard too: the one the project builds the core with (C++17), not a second copy of it.
standard = re.findall(r"(?:^|\s)(-std=\S+)", ops[0]["command"])
if not standard:
    die("the project's compile command for winegard_ops.cpp names no -std=")
includes = []
for flag in re.findall(r"(?:^|\s)-I\s*(\S+)", ops[0]["command"]):
    path = os.path.realpath(flag)
    if not path.startswith(root + os.sep) or path.startswith(os.path.realpath(project) + os.sep):
        continue
    rel = os.path.relpath(path, root)
    if rel in ("src/hamlib", "src/hamlib/preload") or rel.startswith("build"):
        continue
    mapped = tree_path(rel + "/").rstrip("/")
    includes.append("-I$(srcdir)" + ("/" + mapped if mapped else ""))

for f in files:
    target = os.path.join(backend, tree_path(f))
    os.makedirs(os.path.dirname(target), exist_ok=True)
    shutil.copyfile(os.path.join(root, f), target)
shutil.copyfile(os.path.join(root, "upstream/hamlib/README.md"), os.path.join(backend, "README.winegard.md"))

sources = [tree_path(f) for f in files]
sources.sort(key=lambda s: (s.count("/"), s))
template = open(os.path.join(root, "upstream/hamlib/Makefile.am.in")).read()
makefile = template.replace("@WINEGARD_INCLUDES@", " ".join(["-I$(srcdir)"] + includes))
makefile = makefile.replace("@WINEGARD_CXX_STD@", standard[-1])
makefile = makefile.replace("@WINEGARD_SOURCES@", " \\\n".join("\t" + s for s in sources))
open(os.path.join(backend, "Makefile.am"), "w").write(makefile)
print("contribution: %d files from the project (%s left out: they need libserialport)"
      % (len(files), ", ".join(skipped) or "none"))
PY
g add -A
g commit -q -F - <<EOF
rotators/winegard: new backend for Winegard motorised satellite dishes

Trav'ler, Trav'ler Pro, Carryout and Carryout G2 dishes driven through their
serial consoles, with one model that identifies the firmware variant at open.
The caps are C (winegard.c); the operations are C++17 behind the C interface
in winegard.h, over the birdcage core (core/), as rotators/indi does. See
README.winegard.md.
EOF

python3 - "$tree" "$family" "$root/src/hamlib/rotlist.h.in" <<'PY' || fail "editing Hamlib's lists (above)"
import re, sys

tree, family, fragment = sys.argv[1], int(sys.argv[2]), sys.argv[3]

def die(message):
    print("hamlib-intree: " + message, file=sys.stderr)
    sys.exit(1)

def edit(path, change):
    full = tree + "/" + path
    lines = open(full).read().split("\n")
    change(lines)
    open(full, "w").write("\n".join(lines))

def last(lines, pattern, what):
    hits = [i for i, line in enumerate(lines) if re.search(pattern, line)]
    if not hits:
        die("%s: no line for %s" % (what, pattern))
    return hits[-1]

def rotlist(lines):
    taken = {int(m.group(1)) for line in lines for m in [re.match(r"#define ROT_[A-Z0-9_]+\s+(\d+)\s*(?:/[/*].*)?$", line)] if m}
    if family in taken:
        die("rotator backend number %d is taken in this Hamlib's rotlist.h (set HAMLIB_WINEGARD_FAMILY)" % family)
    i = last(lines, r"^#define ROT_MODEL_\w+\s+ROT_MAKE_MODEL\(", "rotlist.h")
    text = open(fragment).read().replace("@ROT_WINEGARD@", str(family)).rstrip("\n")
    lines[i + 1:i + 1] = text.split("\n")

def rot_reg(lines):
    i = last(lines, r"^DEFINE_INITROT_BACKEND\(", "rot_reg.c")
    if lines[i + 1].startswith("#endif"):
        i += 1
    lines[i + 1:i + 1] = ["#if HAVE_WINEGARD", "DEFINE_INITROT_BACKEND(winegard);", "#endif"]
    end = last(lines, r"^\s*\{\s*0,\s*NULL\s*\}", "rot_reg.c's rot_backend_list")
    entries = sum(1 for line in lines if "ROT_FUNCNAMA(" in line)
    limit = int(re.search(r"#define ROT_BACKEND_MAX (\d+)", "\n".join(lines)).group(1))
    if entries + 2 > limit:
        die("rot_reg.c: %d backends + winegard + the end mark exceed ROT_BACKEND_MAX %d" % (entries, limit))
    lines[end:end] = ["#if HAVE_WINEGARD",
                      "    { ROT_WINEGARD, ROT_BACKEND_WINEGARD, ROT_FUNCNAMA(winegard) },",
                      "#endif"]

def configure(lines):
    # Before the loop that turns ROT_BACKEND_LIST into libraries, and before its heading.
    i = last(lines, r"^for be in \$\{ROT_BACKEND_LIST\}", "configure.ac")
    while i > 0 and (lines[i - 1].strip() == "" or lines[i - 1].startswith("#")):
        i -= 1
    lines[i:i] = [
        "dnl The Winegard rotators are a C++17 backend (rotators/winegard/README.winegard.md):",
        "dnl built when a C++ compiler is present, as rotators/indi.",
        "dnl libhamlib is linked as C: WINEGARD_LIBS brings the C++ runtime the backend needs.",
        "AS_IF([test x\"${cf_with_cxx}\" = \"xyes\"],",
        "    [ROT_BACKEND_LIST=\"$ROT_BACKEND_LIST rotators/winegard\"",
        "     WINEGARD_LIBS=\"-lstdc++\"",
        "     AC_DEFINE([HAVE_WINEGARD], [1], [Define if the Winegard rotator backend is built])],",
        "    [ROT_BACKEND_OPTIONAL_LIST=\"$ROT_BACKEND_OPTIONAL_LIST rotators/winegard\"])",
        "AC_SUBST([WINEGARD_LIBS])",
        "",
    ]
    j = last(lines, r"^rotators/indi/Makefile$", "configure.ac's AC_CONFIG_FILES")
    lines[j + 1:j + 1] = ["rotators/winegard/Makefile"]

def src_makefile(lines):
    i = last(lines, r"^libhamlib_la_LIBADD\s*=", "src/Makefile.am")
    while lines[i].rstrip().endswith("\\"):
        i += 1
    lines[i + 1:i + 1] = ["libhamlib_la_LIBADD += $(WINEGARD_LIBS)"]

edit("include/hamlib/rotlist.h", rotlist)
edit("src/rot_reg.c", rot_reg)
edit("configure.ac", configure)
edit("src/Makefile.am", src_makefile)
PY
g add -A
g commit -q -F - <<EOF
Register the Winegard backend as rotator backend $family

rotlist.h: ROT_WINEGARD $family and its six models, ${family}00 (auto-detect) to
${family}05. rot_reg.c lists it, and configure.ac builds it, when a C++ compiler
is present; libhamlib then links the C++ runtime (WINEGARD_LIBS).
EOF
g format-patch -q -o "$patches" "$pristine"..HEAD
patch_stat=$(g diff --shortstat "$pristine" HEAD)
say "patches: $(ls "$patches" | tr '\n' ' ')($(echo $patch_stat))"

# ---- 3. bootstrap, configure, build, make check --------------------------------------------------
stage_start=$SECONDS
(cd "$tree" && ./bootstrap) >"$logs/bootstrap.log" 2>&1 || { tail -30 "$logs/bootstrap.log" >&2; fail "bootstrap"; }
stage bootstrap

stage_start=$SECONDS
mkdir -p "$build"
# Only what rotctld and rotctl need: no static library, no language bindings, no optional
# hardware backends that pull in libraries.
(cd "$build" && "$tree/configure" --disable-static --without-cxx-binding --without-perl-binding \
    --without-python-binding --without-tcl-binding --without-lua-binding --disable-winradio \
    --without-indi --without-libusb --disable-html-matrix --without-readline) >"$logs/configure.log" 2>&1 ||
    { tail -30 "$logs/configure.log" >&2; fail "configure"; }
grep -q '^ROT_BACKEND_LIST = .*rotators/winegard' "$build/Makefile" &&
    grep -q '^#define HAVE_WINEGARD 1' "$build/include/hamlib/config.h" ||
    fail "configure did not add rotators/winegard (no C++ compiler?); see $logs/configure.log"
stage configure

stage_start=$SECONDS
# Everything `make check` builds anyway: libhamlib needs every backend, and check-recursive makes
# `all` in every directory first; rotctld and rotctl are two of tests/' programs.
nice make -j2 -C "$build" >"$logs/build.log" 2>&1 ||
    { grep -E "error|Error" "$logs/build.log" | head -20 >&2; fail "build (see $logs/build.log)"; }
warnings=$(grep -c "rotators/winegard/.*warning:" "$logs/build.log" || true)
((warnings == 0)) || { grep "rotators/winegard/.*warning:" "$logs/build.log" | head -10 >&2; fail "$warnings compiler warnings in rotators/winegard"; }
stage build

stage_start=$SECONDS
nice make -j2 -C "$build" check >"$logs/check.log" 2>&1 ||
    { grep -E "^(FAIL|ERROR)|Error" "$logs/check.log" | head -20 >&2; fail "Hamlib's make check (see $logs/check.log)"; }
say "make check: $(grep -hE "^# (PASS|FAIL|ERROR):" "$logs/check.log" | tr -s ' ' | tr '\n' ' ')"
stage check

# ---- 4. rotctl -l and the emulated dishes, no preload -------------------------------------------
stage_start=$SECONDS
rotctld=$build/tests/rotctld rotctl=$build/tests/rotctl
[[ -x $rotctld && -x $rotctl ]] || fail "no rotctld/rotctl in $build/tests"
say "rotctld: $("$rotctld" --version | head -1)"
listed=$("$rotctl" -l | awk '/Winegard/ {print $1}' | sort -n | tr '\n' ' ')
expected=$(for i in 0 1 2 3 4 5; do echo $((family * 100 + i)); done | tr '\n' ' ')
[[ $listed == "$expected" ]] || fail "rotctl -l lists the Winegard models as '$listed', expected '$expected'"
say "rotctl -l: Winegard models $listed"

# No process of this tree may carry LD_PRELOAD, and rotctld must not have loaded a preload build.
e2e_while_running() {
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
    say "no LD_PRELOAD in ${#tree_pids[@]} processes of this tree; rotctld runs $build/src/.libs/libhamlib.so"
}
descendants() {
    local p
    for p in $(ps -o pid= --ppid "$1"); do
        echo "$p"
        descendants "$p"
    done
}

e2e_sim=$sim e2e_work=$logs
e2e_client=("$rotctl")
for dish in "g2:Carryout G2" "hal205:Trav'ler HAL 2.05"; do
    dish_e2e intree "${dish%%:*}" "${dish#*:}" $((family * 100)) "$rotctld" ||
        fail "the from-source rotctld with the emulated ${dish%%:*} (logs: $logs/intree-${dish%%:*}.*)"
done
stage e2e

{
    echo "hamlib: $name"
    echo "patch: $(ls "$patches" | wc -l) files,$patch_stat"
    for s in bootstrap configure build check e2e; do echo "$s: ${took[$s]} s"; done
} >"$out/times.txt"
say "PASS: $name with the Winegard backend in-tree: make check, rotctl -l, the emulated G2 and Trav'ler" \
    "(bootstrap ${took[bootstrap]} s, configure ${took[configure]} s, build ${took[build]} s," \
    "make check ${took[check]} s, e2e ${took[e2e]} s); kept in $out"
