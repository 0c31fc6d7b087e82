#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The core's layers, held against its includes: each file of src/core/<layer>/ may include only
headers ("<layer>/X.hpp", src/core being the include root) of its own layer or of the layers it
rests on (docs/architecture.md). Prints every include that runs back up and exits 1; exits 0 when none
does. `--self-test` also checks that a planted upward include is caught.

    layers_check.py SOURCE_DIR [--self-test]
"""
import pathlib, re, shutil, sys, tempfile

# Which layers each layer may include from, besides itself. console and tracking are siblings:
# neither knows the other.
RESTS_ON = {
    'base': set(),
    'firmware': {'base'},
    'console': {'base', 'firmware'},
    'tracking': {'base', 'firmware'},
    'dish': {'base', 'firmware', 'console', 'tracking'},
    'service': {'base', 'firmware', 'console', 'tracking', 'dish'},
}
INCLUDE = re.compile(r'#\s*include\s+"(' + '|'.join(RESTS_ON) + r')/[a-z_]+\.hpp"')


def violations(root: pathlib.Path):
    found, files = [], 0
    for top in (root / 'src/core',):
        if not top.is_dir():
            found.append(f'{top}: missing')
            continue
        for path in sorted(top.rglob('*')):
            if path.suffix not in ('.cpp', '.hpp') or not path.is_file():
                continue
            rel = path.relative_to(top)
            if len(rel.parts) != 2:
                found.append(f'{path.relative_to(root)}: not in a layer folder')
                continue
            layer = rel.parts[0]
            if layer not in RESTS_ON:
                found.append(f'{path.relative_to(root)}: unknown layer {layer!r}')
                continue
            files += 1
            for number, line in enumerate(path.read_text(encoding='utf-8').splitlines(), 1):
                match = INCLUDE.search(line)
                if match and match[1] != layer and match[1] not in RESTS_ON[layer]:
                    found.append(f'{path.relative_to(root)}:{number}: {layer} includes {match[1]} ({line.strip()})')
    return found, files


def main():
    root = pathlib.Path(sys.argv[1])
    found, files = violations(root)
    for line in found:
        print(line)
    if found:
        print(f'layers: {len(found)} include(s) against the layering')
        return 1
    print(f'layers: {files} files, no include runs back up')
    if '--self-test' in sys.argv:
        with tempfile.TemporaryDirectory() as tmp:
            copy = pathlib.Path(tmp)
            shutil.copytree(root / 'src/core', copy / 'src/core')
            planted = copy / 'src/core/base/planted.cpp'
            planted.write_text('#include "service/rotator_service.hpp"\n')
            caught, _ = violations(copy)
            if not any('planted.cpp:1: base includes service' in line for line in caught):
                print('layers self-test: a planted upward include was not caught')
                return 1
        print('layers self-test: a planted upward include is caught')
    return 0


if __name__ == '__main__':
    sys.exit(main())
