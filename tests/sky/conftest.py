# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The sky tools' tests: paths from the environment (tests/sky/CMakeLists.txt sets them from the
build tree), the package importable from the sources, and helpers to run the two programs."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "sky"))
sys.path.insert(0, str(Path(__file__).resolve().parent))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def program(name: str) -> str:
    variable = {"birdcage-track": "BIRDCAGE_TRACK", "birdcage-align": "BIRDCAGE_ALIGN"}[name]
    path = os.environ.get(variable)
    if not path:
        pytest.fail(f"{variable} is not set (tests/sky/CMakeLists.txt sets it from the build tree)", pytrace=False)
    return path


def run(name: str, *args, timeout: float = 300, check_exit: int | None = 0, env: dict | None = None):
    """Runs a program; returns (exit status, stdout, stderr)."""
    full_env = dict(os.environ, **(env or {}))
    proc = subprocess.run([program(name), *map(str, args)], capture_output=True, text=True, timeout=timeout,
                          env=full_env)
    if check_exit is not None and proc.returncode != check_exit:
        raise AssertionError(f"{name} {' '.join(map(str, args))} exited {proc.returncode}, expected {check_exit}\n"
                             f"stdout: {proc.stdout[-3000:]}\nstderr: {proc.stderr[-3000:]}")
    return proc.returncode, proc.stdout, proc.stderr


def json_lines(text: str) -> list[dict]:
    return [json.loads(line) for line in text.splitlines() if line.strip()]


@pytest.fixture
def source_root() -> Path:
    return ROOT
