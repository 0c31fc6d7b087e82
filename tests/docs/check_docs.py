#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Holds the user-facing docs to the tree they describe.

Checked docs: README.md, docs/*.md, sim/README.md. A doc fails when it names

  path     a repository path that does not exist: a link target (relative to the doc, with its
           #anchor checked against the target's headings), or a token anywhere in the text whose
           first component is a top-level entry of the repository (src/..., docs/..., ...; `<x>`
           and `*` are wildcards that must match something); `build/<dir>/...` needs <dir> in the
           source tree; a bare file name with one of this project's extensions (.cpp .hpp .h .sh
           .cmake .md) must exist somewhere in the tree; another project's path is written with
           that project's name first (gpredict/src/rotor-conf.c) and not checked;
  section  `docs/X.md §n` (or `X.md §n`, or a bare §n in README.md or docs/variants.md, which
           cite docs/firmware.md) for a section number X.md has no heading for; `(X.md, "Heading")`
           or `(README, "Heading")` for a heading that does not exist;
  type     a C++ type (CamelCase with two or more capitalised parts, or Name::member) as a whole
           backticked span or in a fenced block with no language (the drawings of the code)
           that no source file defines (class, struct, enum, union, using, typedef), or a
           Type::member / `function()` whose name no source file contains;
  conf key `-C key=`, "conf `key`", a `key=value` in backticks or a row of a conf table (a
           table whose first header cell is `key`) naming a key the backend does not declare;
  section  also in any file of the tree: `docs/X.md §n` or `docs/X.md n.n` (code comments,
           transcripts' Source: headers) for a section X.md does not have;
  reference (in any file of the tree) "issue N", "seed NNN" or the predecessor's journal: nothing a
           clone can follow;
  figure   a figure marked <!--fig:NAME-->VALUE that docs/benchmarks.md (where every marked
           figure comes from) does not mark, or marks with another value. VALUE is the number or
           range right after the marker with its unit, e.g. `2.4–3.2°`, `45 minutes`.

  check_docs.py ROOT [--rotctl ROTCTL --backend SO | --conf-keys k1,k2,...]
  check_docs.py --self-test      breaks a copy of a small tree once per kind; each must be caught
"""
import fnmatch
import glob
import os
import re
import subprocess
import sys
import tempfile

# Bare names only of the kinds this project writes; upstream clients' scripts (*.py) are named bare.
SOURCE_EXTS = (".cpp", ".hpp", ".h", ".sh", ".cmake", ".md")
CODE_EXTS = (".cpp", ".hpp", ".h", ".cpp.in", ".hpp.in")
TYPE_DEF = re.compile(r"\b(?:class|struct|union|enum(?:\s+class|\s+struct)?)\s+(?:\[\[[^\]]*\]\]\s*)?([A-Za-z_]\w*)"
                      r"|\busing\s+([A-Za-z_]\w*)\s*=|\btypedef\b[^;]*?\b([A-Za-z_]\w*)\s*;")
CAMEL = re.compile(r"(?<![\w/.-])((?:[A-Z][a-z0-9]+){2,}[A-Z]?)(?![\w/-])")
SCOPED = re.compile(r"(?<![\w/.-])([A-Z]\w*)::([a-z_]\w*|[A-Z]\w*)(\(\))?")
CALL = re.compile(r"^([a-z_][a-z0-9_]*)\([^()]*\)$")
FIGURE = re.compile(r"<!--\s*fig:([\w.-]+)\s*-->")
FIGURE_VALUE = re.compile(r"\s*([~≈]?[−-]?\d[\d.,]*(?:\s?[–-]\s?[−-]?\d[\d.,]*)?"
                          r"(?:\s?(?:°|ms|minutes|min|s|%|×))?)(?![\w])")
# In any file of the tree (code comments, transcripts' headers): docs/X.md §n, or docs/X.md n.n.
CODE_SECTION_REF = re.compile(r"docs/([\w-]+\.md)`?,?\s+§?\s?(\d+(?:\.\d+)*)\b")
SECTION_REF = re.compile(r"(?:docs/)?([\w-]+\.md)`?,?\s+§\s?(\d+(?:\.\d+)*)")
HEADING_REF = re.compile(r"\(`?((?:[\w.-]+/)*(?:README|[\w.-]+\.md))`?,\s*\"([^\"]+)\"")
TOKEN_SPLIT = re.compile(r"[\s()\[\]{}`\"'=,;|]+")


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


class Tree:
    """The repository as the docs may name it: files, top-level entries, types, identifiers."""

    def __init__(self, root):
        self.root = root
        self.files = []
        for dirpath, dirnames, filenames in os.walk(root):
            rel = os.path.relpath(dirpath, root)
            if rel == ".":
                # Build trees, caches and VCS data are not the repository's content.
                dirnames[:] = [d for d in dirnames
                               if not d.startswith(("build", "Testing")) and (d == ".ci" or not d.startswith("."))]
            for name in filenames:
                self.files.append(os.path.normpath(os.path.join(rel, name)))
        self.top = {p.split(os.sep)[0] for p in self.files}
        self.basenames = {os.path.basename(p) for p in self.files}
        self.types = set()
        self.code = []
        for p in self.files:
            if p.endswith(CODE_EXTS):
                text = read(os.path.join(root, p))
                self.code.append(text)
                for m in TYPE_DEF.finditer(text):
                    self.types.add(next(g for g in m.groups() if g))
        self.code_text = "\n".join(self.code)

    def exists(self, rel):
        rel = rel.rstrip("/")
        pattern = re.sub(r"<[^>]*>", "*", rel)
        if pattern != rel or "*" in pattern:
            return bool(glob.glob(os.path.join(self.root, pattern)))
        # A program or a data set may be named by its source without the extension
        # (bench/position_model_bench, bench/passes/iss-45).
        return os.path.exists(os.path.join(self.root, rel)) or bool(glob.glob(os.path.join(self.root, rel) + ".*"))

    def names(self, word):
        return re.search(r"\b" + re.escape(word) + r"\b", self.code_text) is not None


def slug(heading):
    """GitHub's anchor for a heading."""
    text = re.sub(r"<[^>]*>", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def headings(text):
    return [m.group(1).strip() for m in re.finditer(r"^#{1,6}\s+(.*)$", text, re.M)]


def section_numbers(text):
    return {m.group(1) for h in headings(text) for m in [re.match(r"(\d+(?:\.\d+)*)\.?\s", h + " ")] if m}


def strip_comments(text):
    """Without HTML comments (figure markers stay); line numbers stay as in the file."""
    return re.sub(r"<!--(?!\s*fig:).*?-->", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)


def split_blocks(text):
    """(prose, drawings): the text outside ``` blocks, and that of the blocks with no language
    (the drawings of the code's parts; a ```sh or ```ini block names no C++ types)."""
    prose, fenced = [], []
    inside, drawing = False, False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            inside = not inside
            drawing = inside and line.strip() == "```"
            continue
        if not inside:
            prose.append(line)
        elif drawing:
            fenced.append(line)
    return "\n".join(prose), "\n".join(fenced)


def line_of(text, needle):
    for n, line in enumerate(text.splitlines(), 1):
        if needle in line:
            return n
    return 0


def check_path_token(tree, token, fail):
    """A token of a doc's text that may be a path of the repository, relative to its root."""
    # Trailing punctuation only: a leading ".." is a relative path, not punctuation.
    token = token.rstrip(".:!?*").lstrip("*").removeprefix("./")
    # The backend is installed in a folder of its own under the libdir, where only the launchers
    # look (CMakeLists.txt, BIRDCAGE_BACKEND_INSTALL_DIR): an installed path elsewhere is wrong.
    if token.startswith("/") and token.endswith("libhamlib-winegard.so") and "/birdcage/" not in token:
        fail(token, "the backend installs under <libdir>/birdcage/, not here")
    if not token or token.startswith(("/", "~", "$", "-", ".")) or "://" in token or "…" in token:
        return
    first = token.split("/")[0]
    if "/" in token and first in tree.top:
        if not tree.exists(token.split("#")[0]):
            fail(token, "no such file or directory in the repository")
    elif "/" in token and re.fullmatch(r"build(-[\w]+)?", first):
        parts = token.split("/")
        if len(parts) > 2 and parts[1] and not tree.exists(parts[1]):
            fail(token, f"a build path whose source folder {parts[1]}/ does not exist")
    elif "/" not in token and token.endswith(SOURCE_EXTS) and re.fullmatch(r"[\w.<>*-]+", token):
        pattern = re.sub(r"<[^>]*>", "*", token)
        if not any(fnmatch.fnmatch(b, pattern) for b in tree.basenames):
            fail(token, "no file of that name in the repository")


# The docs whose bare §n cite docs/firmware.md (they say so at the top).
BARE_SECTIONS_CITE_FIRMWARE = ("README.md", "docs/variants.md")


def check_doc(tree, doc, conf_keys, figures, problems):
    text = strip_comments(read(os.path.join(tree.root, doc)))
    prose, fenced = split_blocks(text)
    docdir = os.path.dirname(doc)

    def fail(kind, what, why, line=None):
        problem = f"{doc}:{line or line_of(text, what)}: {kind}: {what}: {why}"
        if problem not in problems:
            problems.append(problem)

    # Links, relative to the doc; anchors against the target's headings.
    for target in re.findall(r"\]\(([^)\s]+)\)", prose):
        if re.match(r"[a-z]+:", target):
            continue
        path, _, anchor = target.partition("#")
        resolved = os.path.normpath(os.path.join(docdir, path)) if path else doc
        if not tree.exists(resolved):
            fail("path", target, f"no such file or directory ({resolved})")
        elif anchor and resolved.endswith(".md"):
            if anchor not in {slug(h) for h in headings(read(os.path.join(tree.root, resolved)))}:
                fail("path", target, f"{resolved} has no heading with the anchor #{anchor}")

    # Paths anywhere in the text, relative to the repository root.
    for number, line in enumerate(text.splitlines(), 1):
        for token in TOKEN_SPLIT.split(line):
            check_path_token(tree, token, lambda what, why: fail("path", what, why, number))

    # Sections and headings another doc is cited by.
    for name, number in SECTION_REF.findall(text):
        target = "README.md" if name == "README.md" else ("sim/README.md" if name == "README.md" else f"docs/{name}")
        if not os.path.exists(os.path.join(tree.root, target)):
            continue  # a missing doc is reported as a path
        if number not in section_numbers(read(os.path.join(tree.root, target))):
            fail("section", f"{name} §{number}", f"{target} has no section {number}")
    if doc in BARE_SECTIONS_CITE_FIRMWARE and os.path.exists(os.path.join(tree.root, "docs/firmware.md")):
        known = section_numbers(read(os.path.join(tree.root, "docs/firmware.md")))
        # A § after a doc's name cites that doc (checked above).
        for number in re.findall(r"(?<![\w.])(?<!\.md )(?<!\.md` )(?<!\.md, )§\s?(\d+(?:\.\d+)*)", text):
            if number not in known:
                fail("section", f"§{number}", f"docs/firmware.md (which {doc}'s bare § cite) has no such section")
    for name, title in HEADING_REF.findall(text):
        title = " ".join(title.split())  # a citation wrapped across lines reads as one
        target = "README.md" if name == "README" else name
        if not target.startswith(("docs/", "sim/")) and target != "README.md":
            target = os.path.normpath(os.path.join(docdir, target))
        if not os.path.exists(os.path.join(tree.root, target)):
            continue
        if not any(title.lower() in h.lower() for h in headings(read(os.path.join(tree.root, target)))):
            fail("section", f'{name}, "{title}"', f"{target} has no heading containing it")

    # Types and functions, in backticks and in fenced blocks.
    spans = re.findall(r"`([^`\n]+)`", prose)
    # A span is a type only when it is nothing else (`-w NoTests` is an option, not a type).
    typeish = [s for s in spans if re.fullmatch(r"(?:[A-Z]\w*::)*\w+(?:::\w+)?(?:\(\))?", s.strip())]
    for chunk in typeish + [fenced]:
        for m in SCOPED.finditer(chunk):
            scope, member = m.group(1), m.group(2)
            if scope not in tree.types:
                fail("type", scope, "no class, struct, enum or alias of that name in the sources")
            elif not tree.names(member):
                fail("type", f"{scope}::{member}", f"no source file names {member}")
        for m in CAMEL.finditer(chunk):
            if m.group(1) not in tree.types:
                fail("type", m.group(1), "no class, struct, enum or alias of that name in the sources")
    for span in spans:
        m = CALL.match(span.strip())
        if m and not re.search(r"\b" + re.escape(m.group(1)) + r"\s*\(", tree.code_text):
            fail("type", span, f"no source file has a function {m.group(1)}")

    # Conf keys.
    named = re.findall(r"-C\s+\"?([a-z_][a-z0-9_]*)=", text)
    named += re.findall(r"\bconf\s+`([a-z_][a-z0-9_]*)`", prose)
    named += [s.split("=")[0] for s in spans if re.fullmatch(r"[a-z][a-z0-9]*_[a-z0-9_]*=[\w.]+|"
                                                                r"(?:variant|pointing|deadband|leapfrog)=[\w.]+", s)]
    in_conf_table = False
    for line in prose.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.lstrip().startswith("|") else []
        if not cells:
            in_conf_table = False
        elif cells[0] == "key":
            # A conf table gives each key its default (docs/usage.md); a table of keyboard keys
            # (docs/tui.md) does not.
            in_conf_table = any(c.startswith("default") for c in cells[1:])
        elif in_conf_table and not set(cells[0]) <= set("-: "):
            named += re.findall(r"`([a-z_][a-z0-9_]*)`", cells[0])
    if conf_keys is not None:
        for key in sorted(set(named) - {"key"}):  # `-C key=value`: the placeholder
            if key not in conf_keys:
                fail("conf key", key, "the backend declares no such conf key (rotctl -L)")

    # Figures (a marker inside `code` is an example of one, shown rather than hidden).
    text = re.sub(r"`[^`\n]*`", lambda m: " " * len(m.group(0)), text)
    for m in FIGURE.finditer(text):
        name = m.group(1)
        value = FIGURE_VALUE.match(text, m.end())
        if not value:
            fail("figure", m.group(0), "a figure marker with no number after it")
            continue
        value = value.group(1)
        if doc == "docs/benchmarks.md":
            figures.setdefault(name, set()).add(value)
        else:
            figures.setdefault(("quoted", name), []).append((doc, line_of(text, m.group(0)), value))


# References a clone cannot follow: an issue number, a seed document, the predecessor's journal.
# (Spelt so that this file does not match itself: a `git grep` for them finds nothing either.)
UNFOLLOWABLE = re.compile(r"\b(?:issue[s]? #?\d+|issue-\d+|seed[s]? \d{3}(?:/\d{3})*|birdcage[ ]journal)\b", re.I)


def check(root, conf_keys):
    tree = Tree(root)
    docs = ["README.md", "sim/README.md"] + sorted(
        os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "docs", "*.md")))
    docs = [d for d in docs if os.path.exists(os.path.join(root, d))]
    problems, figures = [], {}
    for doc in docs:
        check_doc(tree, doc, conf_keys, figures, problems)
    for path in tree.files:
        if path.endswith((".png", ".csv")):
            continue
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            for n, line in enumerate(f, 1):
                for m in UNFOLLOWABLE.finditer(line):
                    problems.append(f"{path}:{n}: reference: '{m.group(0)}' cannot be followed from a clone; "
                                    "cite a section of the docs instead")
                if path.endswith(".md") and not path.startswith("tests/"):
                    continue  # the docs' own citations are checked above, with their § rules
                for name, number in CODE_SECTION_REF.findall(line):
                    cited = os.path.join(root, "docs", name)
                    if os.path.exists(cited) and number not in section_numbers(read(cited)):
                        problems.append(f"{path}:{n}: section: docs/{name} {number}: no such section there")
    for name, values in figures.items():
        if isinstance(name, str) and len(values) > 1:
            problems.append(f"docs/benchmarks.md: figure: {name}: marked with different values {sorted(values)}")
    for key, quotes in figures.items():
        if isinstance(key, str):
            continue
        source = figures.get(key[1])
        for doc, line, value in quotes:
            if source is None:
                problems.append(f"{doc}:{line}: figure: {key[1]}: docs/benchmarks.md marks no such figure")
            elif value not in source:
                problems.append(f"{doc}:{line}: figure: {key[1]}: {value} here, {'/'.join(sorted(source))} "
                                "in docs/benchmarks.md")
    return docs, problems


def backend_conf_keys(rotctl, backend):
    def keys(model, preload):
        env = dict(os.environ)
        if preload:
            env["LD_PRELOAD"] = preload
        out = subprocess.run([rotctl, "-m", model, "-r", "/nonexistent", "-L"], env=env,
                             capture_output=True, text=True).stdout
        return set(re.findall(r"^([a-z_0-9]+): \"", out, re.M))
    preload = ":".join(p for p in [os.environ.get("BIRDCAGE_PRELOAD_FIRST"), backend] if p)
    # Hamlib's serial frontend adds its keys to every model: taken from a stock serial rotator.
    return keys("90105", preload) - keys("202", None)


SELF_TEST_DOCS = {
    "README.md": "# t\n\n## Usage\n\nSee [docs/a.md](docs/a.md#part-one), `src/core/real.cpp`, "
                 "docs/a.md §1, (§2), `RealType`, `RealType::member`, `real_function()`, `-C good_key=1`.\n"
                 "RMS <!--fig:rms-->1.5–2.0° and <!--fig:time-->45 minutes.\n",
    "docs/a.md": "# A\n\n## Part one\n\n### 1 First\n\n## 2. Second\n\nBack to the [README](../README.md), "
                 "(README, \"Usage\"), `src/core/<part>.cpp`, `build/src/x.so`.\n\n| key | default |\n|---|---|\n"
                 "| `good_key` | 1 |\n",
    "docs/benchmarks.md": "# B\n\nRMS <!--fig:rms-->1.5–2.0°, about <!--fig:time-->45 minutes.\n",
    "docs/firmware.md": "# F\n\n## 1. One\n\n### 2 Two\n",
    "docs/variants.md": "# V\n\nAs §1, and a.md §2.\n",
    "src/core/real.cpp": "struct RealType { int member; };\nint real_function() { return 0; }\n",
}
# Each break: (file, text to append, the kind and name the check must report).
SELF_TEST_BREAKS = [
    ("README.md", "See `src/core/moved.cpp`.\n", "path: src/core/moved.cpp"),
    ("docs/a.md", "See [it](../src/gone.hpp).\n", "path: ../src/gone.hpp"),
    ("docs/a.md", "See [it](../README.md#no-such-part).\n", "path: ../README.md#no-such-part"),
    ("README.md", "See `gone_file.cpp`.\n", "path: gone_file.cpp"),
    ("docs/a.md", "LD_PRELOAD=/usr/local/lib/libhamlib-winegard.so rotctld\n", "path: /usr/local/lib/libhamlib-winegard.so"),
    ("README.md", "See docs/a.md §7.\n", "section: a.md §7"),
    ("README.md", "As (§9).\n", "section: §9"),
    ("docs/variants.md", "As (§8).\n", "section: §8"),
    ("docs/a.md", "(README, \"Nowhere\")\n", 'section: README, "Nowhere"'),
    ("README.md", "The `HamlibFdTransport`.\n", "type: HamlibFdTransport"),
    ("docs/a.md", "```\n  transport  MissingTransport over an fd\n```\n", "type: MissingTransport"),
    ("docs/a.md", "```\n  a part  RealType, then Other::thing()\n```\n", "type: Other"),
    ("README.md", "`RealType::gone_member`\n", "type: RealType::gone_member"),
    ("README.md", "`gone_function()`\n", "type: gone_function()"),
    ("README.md", "Run with `-C bad_key=1`.\n", "conf key: bad_key"),
    ("docs/a.md", "\n| key | default |\n|---|---|\n| `other_bad` | 0 |\n", "conf key: other_bad"),
    ("README.md", "RMS <!--fig:rms-->1.4–2.0°.\n", "figure: rms: 1.4–2.0° here"),
    ("README.md", "About <!--fig:unknown-->3 s.\n", "figure: unknown: docs/benchmarks.md marks no such"),
    ("docs/benchmarks.md", "Again <!--fig:time-->40 minutes.\n", "figure: time: marked with different values"),
    ("src/core/real.cpp", "// as decided in " + "issue" + " 12\n", "reference: '" + "issue" + " 12'"),
    ("src/core/real.cpp", "// the rule of docs/firmware.md §7\n", "section: docs/firmware.md 7"),
    ("docs/a.md", "Quoted by " + "seed" + " 000.\n", "reference: '" + "seed" + " 000'"),
    ("docs/a.md", "As the " + "birdcage" + " journal says.\n", "reference: '" + "birdcage" + " journal'"),
]


def self_test():
    failures = 0
    with tempfile.TemporaryDirectory() as base:
        def build(extra):
            root = tempfile.mkdtemp(dir=base)
            for path, text in SELF_TEST_DOCS.items():
                os.makedirs(os.path.join(root, os.path.dirname(path)), exist_ok=True)
                with open(os.path.join(root, path), "w", encoding="utf-8") as f:
                    f.write(text + (extra[1] if extra and extra[0] == path else ""))
            return root
        _, problems = check(build(None), {"good_key"})
        if problems:
            failures += 1
            print("FAIL: the intact tree is reported:\n  " + "\n  ".join(problems))
        for path, text, expected in SELF_TEST_BREAKS:
            _, problems = check(build((path, text)), {"good_key"})
            if not any(expected in p for p in problems):
                failures += 1
                print(f"FAIL: {path} + {text.strip()!r} should report '{expected}'; reported: {problems}")
            else:
                print(f"caught: {next(p for p in problems if expected in p)}")
    print(f"{'ok' if not failures else 'FAIL'}: {len(SELF_TEST_BREAKS)} kinds of break, {failures} missed")
    return 1 if failures else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) < 2:
        print(__doc__)
        return 2
    root, args = argv[1], argv[2:]
    conf_keys = None
    if "--conf-keys" in args:
        conf_keys = set(args[args.index("--conf-keys") + 1].split(","))
    elif "--rotctl" in args:
        conf_keys = backend_conf_keys(args[args.index("--rotctl") + 1], args[args.index("--backend") + 1])
        if not conf_keys:
            print("FAIL: could not read the backend's conf keys through rotctl -L")
            return 1
    docs, problems = check(root, conf_keys)
    for p in problems:
        print("FAIL: " + p)
    if not problems:
        print(f"ok: {len(docs)} docs name only paths, sections, types, conf keys and figures that exist")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
