#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Writes the Winegard contribution into an unpacked Hamlib tree, one commit's worth at a time
(scripts/hamlib-intree.sh commits each): the project's sources are the one source of truth, and
nothing here comes from a build of the project.

  hamlib_contribution.py hook ROOT TREE        rot_caps.send_cmd, and rotctl's w using it
  hamlib_contribution.py backend [--update] ROOT TREE
                                               rotators/winegard/, from src/hamlib and src/core
                                               (--update: over an existing one, writing what changed)
  hamlib_contribution.py register ROOT TREE [FAMILY]
                                               rotlist.h, rot_reg.c, configure.ac, src/Makefile.am;
                                               prints the backend number used

backend: the files the backend's entry points reach, and only those. From the glue (the caps and
C interface in src/hamlib/caps/, the operations in src/hamlib/, the in-tree parts in
src/hamlib/intree/), every `#include "..."` of the core is followed, and a core source joins when
it implements a header reached (its first project include is that header, the project's rule).
Blocks under `#if defined(BIRDCAGE_PRELOAD)` are the preload build's own and are left out (those
under `#if !defined(BIRDCAGE_PRELOAD)` are kept without the condition); an include of a Hamlib
header the tree lacks is dropped (4.6 has no hamlib/port.h or hamlib/rot_state.h, which master
split out of rig.h). Prints the file list, its size, and the conf keys of the generated table.
"""
import os
import re
import sys

BACKEND = "rotators/winegard"
PRELOAD = "BIRDCAGE_PRELOAD"


def die(message):
    print("hamlib-contribution: " + message, file=sys.stderr)
    sys.exit(1)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)


def write_changed(path, text):
    """Writes only what changed, so that a rebuild of a reused tree compiles only that."""
    if os.path.isfile(path) and read(path) == text:
        return
    write(path, text)


def edit(tree, rel, change):
    path = os.path.join(tree, rel)
    lines = read(path).split("\n")
    change(lines)
    write(path, "\n".join(lines))


def last(lines, pattern, what, start=0, end=None):
    hits = [i for i in range(start, len(lines) if end is None else end) if re.search(pattern, lines[i])]
    if not hits:
        die("%s: no line for %s" % (what, pattern))
    return hits[-1]


def first(lines, pattern, what, start=0):
    for i in range(start, len(lines)):
        if re.search(pattern, lines[i]):
            return i
    die("%s: no line for %s" % (what, pattern))


# ---- hook ---------------------------------------------------------------------------------------

def hook(root, tree):
    def rotator_h(lines):
        start = first(lines, r"^struct rot_caps\s*\{", "rotator.h")
        end = first(lines, r"^\};", "rotator.h's struct rot_caps", start)
        lines[end:end] = [
            "    int (*send_cmd)(ROT *rot, const char *cmd, char *reply, int reply_len); /*!< Pointer to backend "
            "implementation of rotctl's raw send_cmd (w): a backend that holds a session with its device sends "
            "the text through it, or refuses it. NULL: rotctl writes the text to the port itself. */",
        ]

    def rotctl_parse(lines):
        start = first(lines, r"^declare_proto_rot\(send_cmd\)", "rotctl_parse.c")
        i = first(lines, r"^\s*char eom_buf\[4\]", "rotctl_parse.c's send_cmd", start)
        lines[i + 1:i + 1] = [
            "",
            "    /* A backend that holds a session with its device takes the text itself. */",
            "    if (rot->caps->send_cmd)",
            "    {",
            "        buf[0] = '\\0';",
            "        retval = rot->caps->send_cmd(rot, arg1, (char *) buf, BUFSZ);",
            "",
            "        if (retval == RIG_OK)",
            "        {",
            "            if (interactive && prompt)",
            "            {",
            "                fprintf(fout, \"%s: \", cmd->arg2);",
            "            }",
            "",
            "            fprintf(fout, \"%s\\n\", buf);",
            "        }",
            "",
            "        return retval;",
            "    }",
        ]

    edit(tree, "include/hamlib/rotator.h", rotator_h)
    edit(tree, "tests/rotctl_parse.c", rotctl_parse)


# ---- backend ------------------------------------------------------------------------------------

def unifdef(text, path):
    """Drops what only the preload build has: `#if defined(BIRDCAGE_PRELOAD)` blocks (and the
    `#else` half of `#if !defined(...)`), keeping the other half without its condition."""
    out, stack = [], []  # stack: [is_preload_condition, keep]
    for number, line in enumerate(text.split("\n"), 1):
        s = line.strip()
        m = re.match(r"#\s*if\s+(!?)\s*defined\s*\(\s*" + PRELOAD + r"\s*\)\s*$", s)
        if m:
            stack.append([True, m.group(1) == "!"])
            continue
        if PRELOAD in s and s.startswith("#"):
            die("%s:%d: only `#if defined(%s)`, `#if !defined(%s)`, #else and #endif are understood"
                % (path, number, PRELOAD, PRELOAD))
        if re.match(r"#\s*if", s):
            stack.append([False, True])
        elif re.match(r"#\s*el", s) and stack and stack[-1][0]:
            if not s.startswith("#else"):
                die("%s:%d: no #elif after a %s condition" % (path, number, PRELOAD))
            stack[-1][1] = not stack[-1][1]
            continue
        elif re.match(r"#\s*endif", s):
            if not stack:
                die("%s:%d: #endif without #if" % (path, number))
            if stack.pop()[0]:
                continue
        if all(keep for preload, keep in stack if preload):
            out.append(line)
    if stack:
        die("%s: unterminated #if" % path)
    return "\n".join(out)


def project_includes(text):
    return re.findall(r'^\s*#\s*include\s+"([^"]+)"', text, re.M)


def backend(root, tree, update=False):
    hamlib_src = os.path.join(root, "src/hamlib")
    core = os.path.join(root, "src/core")
    # The glue: the caps and C interface, the operations, the in-tree parts.
    glue = [os.path.join("caps", n) for n in ("winegard.c", "winegard.h")]
    glue += sorted(n for n in os.listdir(hamlib_src) if n.endswith((".cpp", ".hpp")))
    glue += sorted(os.path.join("intree", n) for n in os.listdir(os.path.join(hamlib_src, "intree")))
    texts = {}  # path in the backend directory -> text
    for rel in glue:
        name = os.path.basename(rel)
        if name in texts:
            die("two glue files named %s" % name)
        texts[name] = unifdef(read(os.path.join(hamlib_src, rel)), rel)

    # Which core source implements which header: its first project include.
    implements = {}
    for directory, _, names in os.walk(core):
        for n in names:
            if n.endswith(".cpp"):
                rel = os.path.relpath(os.path.join(directory, n), core)
                found = project_includes(read(os.path.join(core, rel)))
                if found:
                    implements.setdefault(found[0], []).append(rel)
    reached, queue = set(), [t for t in texts.values()]
    while queue:
        for inc in project_includes(queue.pop()):
            if inc in reached or not os.path.isfile(os.path.join(core, inc)):
                continue
            reached.add(inc)
            queue.append(read(os.path.join(core, inc)))
            for source in implements.get(inc, []):
                if source not in reached:
                    reached.add(source)
                    queue.append(read(os.path.join(core, source)))
    for rel in sorted(reached):
        texts[os.path.join("core", rel)] = unifdef(read(os.path.join(core, rel)), "src/core/" + rel)

    # Hamlib's headers as this tree has them.
    def hamlib_headers(text):
        def keep(m):
            return m.group(0) if os.path.isfile(os.path.join(tree, "include", m.group(1))) else ""
        return re.sub(r'^#include "(hamlib/[a-z_]+\.h)"[^\n]*\n', keep, text, flags=re.M)

    backend_dir = os.path.join(tree, BACKEND)
    if os.path.exists(backend_dir) and not update:
        die("%s exists in this Hamlib already" % BACKEND)
    texts = {rel: hamlib_headers(text) for rel, text in texts.items()}
    for rel, text in texts.items():
        write_changed(os.path.join(backend_dir, rel), text)

    sources = sorted(texts, key=lambda s: (s.count("/"), s))
    template = read(os.path.join(root, "upstream/hamlib/Makefile.am.in"))
    # The C library's sources are written in the template; the C++ library has the others.
    c_sources = re.search(r"^libhamlib_winegard_la_SOURCES = (.*)$", template, re.M).group(1).split()
    if sorted(c_sources) != sorted(s for s in sources if s in ("winegard.c", "winegard.h")):
        die("upstream/hamlib/Makefile.am.in's C sources are not the caps (winegard.c, winegard.h)")
    makefile = template.replace("@WINEGARD_SOURCES@",
                                " \\\n".join("\t" + s for s in sources if s not in c_sources))
    write_changed(os.path.join(backend_dir, "Makefile.am"), makefile)
    if update:  # what the backend no longer has
        for directory, _, names in os.walk(backend_dir):
            for n in names:
                rel = os.path.relpath(os.path.join(directory, n), backend_dir)
                if rel not in texts and rel != "Makefile.am" and not rel.startswith(("Makefile", ".")) \
                        and rel.endswith((".c", ".h", ".cpp", ".hpp")):
                    os.remove(os.path.join(directory, n))

    # Every include resolves within the backend, to Hamlib, or to the system.
    for rel, text in texts.items():
        for inc in project_includes(text):
            here = os.path.join(os.path.dirname(os.path.join(backend_dir, rel)), inc)
            if not any(os.path.isfile(p) for p in (here, os.path.join(backend_dir, inc),
                                                   os.path.join(backend_dir, "core", inc),
                                                   os.path.join(tree, "src", inc),
                                                   os.path.join(tree, "include", inc))):
                die("%s includes \"%s\", which the contribution does not have" % (rel, inc))

    # The conf keys the generated table declares (rotctl -L must list these).
    conf = texts["winegard_conf.cpp"]
    table = conf[conf.index("kConfParams[] = {"):conf.index("};", conf.index("kConfParams[] = {"))]
    keys = re.findall(r'\{\s*\d+,\s*"([a-z_0-9]+)"', table)
    lines = sum(t.count("\n") + 1 for t in texts.values()) + makefile.count("\n") + 1
    print("backend: %d files, %d lines (%d of the glue, %d of the core; %d core files left out)"
          % (len(texts) + 1, lines, len(glue), len(reached),
             sum(1 for _, _, ns in os.walk(core) for n in ns if n.endswith((".cpp", ".hpp", ".h"))) - len(reached)))
    print("files: " + " ".join(["Makefile.am"] + sources))
    print("conf keys: " + " ".join(keys))


# ---- register -----------------------------------------------------------------------------------

def register(root, tree, family_arg):
    # The next number after the backends rot_reg.c lists (rotlist.h also reserves numbers for
    # backends not written yet), unless FAMILY says; it must be free in rotlist.h.
    rotlist_h = read(os.path.join(tree, "include/hamlib/rotlist.h"))
    numbers = dict(re.findall(r"^#define (ROT_[A-Z0-9_]+)\s+(\d+)\b", rotlist_h, re.M))
    listed = re.findall(r"^\s*\{\s*(ROT_\w+)\s*,\s*ROT_BACKEND_\w+\s*,",
                        read(os.path.join(tree, "src/rot_reg.c")), re.M)
    if not listed or any(name not in numbers for name in listed):
        die("rot_reg.c lists backends rotlist.h does not number")
    family = int(family_arg) if family_arg else max(int(numbers[name]) for name in listed) + 1
    if str(family) in numbers.values():
        die("rotator backend number %d is taken in this Hamlib's rotlist.h" % family)

    def rotlist(lines):
        i = last(lines, r"^#define ROT_MODEL_\w+\s+ROT_MAKE_MODEL\(", "rotlist.h")
        text = read(os.path.join(root, "src/hamlib/rotlist.h.in")).replace("@ROT_WINEGARD@", str(family))
        lines[i + 1:i + 1] = ["", ""] + text.rstrip("\n").split("\n")

    def rot_reg(lines):
        i = last(lines, r"^DEFINE_INITROT_BACKEND\(", "rot_reg.c")
        if lines[i + 1].startswith("#endif"):
            i += 1
        lines[i + 1:i + 1] = ["#if HAVE_WINEGARD", "DEFINE_INITROT_BACKEND(winegard);", "#endif"]
        # The entries of rot_backend_list, however many are built (#if'd ones count: they may be).
        start = first(lines, r"^\}\s*rot_backend_list\[ROT_BACKEND_MAX\]\s*=", "rot_reg.c's rot_backend_list")
        end = first(lines, r"^\s*\{\s*0,\s*NULL\s*\}", "rot_reg.c's rot_backend_list end", start)
        entry = r"^\s*\{\s*ROT_\w+\s*,\s*ROT_BACKEND_\w+\s*,\s*ROT_FUNCNAMA\(\w+\)\s*\}\s*,"
        entries = sum(1 for line in lines[start:end] if re.match(entry, line))
        limit = int(re.search(r"#define ROT_BACKEND_MAX (\d+)", "\n".join(lines)).group(1))
        if entries == 0 or entries + 2 > limit:
            die("rot_reg.c: %d backends + winegard + the end mark do not fit ROT_BACKEND_MAX %d" % (entries, limit))
        lines[end:end] = ["#if HAVE_WINEGARD",
                          "    { ROT_WINEGARD, ROT_BACKEND_WINEGARD, ROT_FUNCNAMA(winegard) },",
                          "#endif"]

    def configure(lines):
        # Beside INDI's switch (the other C++ rotator backend), before the HTML matrix's; but
        # after configure's C++11 check wherever that is (4.6 makes it late): it appends its -std
        # to CXX, and the last -std wins.
        i = first(lines, r"^dnl Check if libgd-dev is installed", "configure.ac")
        cxx11 = first(lines, r"^\s*AX_CXX_COMPILE_STDCXX\(\[11\]", "configure.ac's C++11 check")
        if cxx11 > i:
            i = cxx11 + 1
        lines[i:i] = [""] + read(os.path.join(root, "upstream/hamlib/configure.ac.in")).rstrip("\n").split("\n") + [""]
        if first(lines, r"cf_with_cxx=|\[cf_with_cxx\]", "configure.ac's C++ check") > i:
            die("configure.ac checks for a C++ compiler after the Winegard switch")
        j = last(lines, r"^rotators/indi/Makefile$", "configure.ac's AC_CONFIG_FILES")
        lines[j + 1:j + 1] = ["rotators/winegard/Makefile"]
        k = last(lines, r"^\s*With INDI support\s", "configure.ac's summary")
        m = re.match(r"(\s*)With INDI support(\s*)\$\{cf_with_indi_support\}", lines[k])
        gap = m.group(2)[4:] if m.group(2).startswith("     ") else m.group(2)
        lines[k + 1:k + 1] = [m.group(1) + "With Winegard backend" + gap + "${cf_with_winegard}"]

    def src_makefile(lines):
        # After libhamlib's LIBADD and DEPENDENCIES, which it appends to.
        i = max(last(lines, r"^libhamlib_la_LIBADD\s*=", "src/Makefile.am"),
                last(lines, r"^libhamlib_la_DEPENDENCIES\s*=", "src/Makefile.am"))
        while lines[i].rstrip().endswith("\\"):
            i += 1
        lines[i + 1:i + 1] = [""] + read(os.path.join(root, "upstream/hamlib/src-Makefile.am.in")).rstrip("\n").split("\n")

    edit(tree, "include/hamlib/rotlist.h", rotlist)
    edit(tree, "src/rot_reg.c", rot_reg)
    edit(tree, "configure.ac", configure)
    edit(tree, "src/Makefile.am", src_makefile)
    print(family)


def main(argv):
    if len(argv) >= 3 and argv[0] == "hook":
        hook(argv[1], argv[2])
    elif len(argv) >= 4 and argv[0] == "backend" and argv[1] == "--update":
        backend(argv[2], argv[3], update=True)
    elif len(argv) >= 3 and argv[0] == "backend":
        backend(argv[1], argv[2])
    elif len(argv) >= 3 and argv[0] == "register":
        register(argv[1], argv[2], argv[3] if len(argv) > 3 else "")
    else:
        print(__doc__, file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
