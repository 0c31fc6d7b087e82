# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""Fixtures: the dish emulator on a pty, the distribution's rotctld with the birdcage backend
preloaded, and birdcage-mcp spawned over stdio by the MCP SDK's own client.

Paths come from the environment (tests/mcp/run.sh sets them from the build tree):
  BIRDCAGE_SIM       birdcage-sim
  BIRDCAGE_PRELOAD   LD_PRELOAD for rotctld (the backend, after the sanitizer runtime if any)
  ROTCTLD            rotctld (default /usr/bin/rotctld)
  BIRDCAGE_MCP       the server command (default: birdcage-mcp next to this Python)
  BIRDCAGE_TRACK     birdcage-track (the build tree's, tools/sky/)
"""

from __future__ import annotations

import contextlib
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
from mcp.client.session import ClientSession
from mcp.client.stdio import StdioServerParameters, stdio_client

# The emulator and the backend's clock run this many times faster than real time.
TIME_SCALE = 20


def required_path(variable: str) -> str:
    value = os.environ.get(variable)
    if not value:
        pytest.fail(f"{variable} is not set (tests/mcp/run.sh sets it from the build tree)", pytrace=False)
    return value


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(predicate, timeout: float, what: str) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.02)
    pytest.fail(f"timed out after {timeout:g} s waiting for {what}", pytrace=False)


def listening(port: int) -> bool:
    with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=0.2):
        return True
    return False


class Rig:
    """An emulated dish (or none: Hamlib's dummy rotator) behind a preloaded rotctld."""

    def __init__(self, workdir: Path, model: int, variant: str | None, conf: str = "",
                 time_scale: float = TIME_SCALE, port: int | None = None):
        self.workdir = workdir
        self.model = model
        self.variant = variant
        self.conf = conf
        self.time_scale = time_scale
        self.port = port or free_port()
        self.processes: list[subprocess.Popen] = []
        self.rotctld: subprocess.Popen | None = None

    def start(self) -> "Rig":
        args = [os.environ.get("ROTCTLD", "/usr/bin/rotctld"), "-m", str(self.model), "-T", "127.0.0.1",
                "-t", str(self.port)]
        env = dict(os.environ)
        if self.variant:
            link = self.workdir / f"{self.variant}-{self.port}.tty"
            sim = subprocess.Popen(
                [required_path("BIRDCAGE_SIM"), "--variant", self.variant, "--link", str(link),
                 "--time-scale", f"{self.time_scale:g}", "--az", "100", "--el", "30"],
                stdout=open(self.workdir / f"{self.variant}-{self.port}.sim.log", "w"), stderr=subprocess.STDOUT)
            self.processes.append(sim)
            wait_until(link.exists, 10, f"the emulator's pty {link}")
            args += ["-r", str(link), "-C", f"time_scale={self.time_scale:g}" + (f",{self.conf}" if self.conf else "")]
            env["LD_PRELOAD"] = required_path("BIRDCAGE_PRELOAD")
        self.start_rotctld(args, env)
        return self

    def start_rotctld(self, args: list[str], env: dict[str, str]) -> None:
        self._rotctld_args, self._rotctld_env = args, env
        log = open(self.workdir / f"rotctld-{self.model}-{self.port}.log", "a")
        self.rotctld = subprocess.Popen(args, env=env, stdout=log, stderr=subprocess.STDOUT)
        self.processes.append(self.rotctld)
        wait_until(lambda: listening(self.port) or self.rotctld.poll() is not None, 60, "rotctld to listen")
        if self.rotctld.poll() is not None:
            pytest.fail(f"rotctld exited with {self.rotctld.returncode}; see {log.name}", pytrace=False)

    def stop_rotctld(self) -> None:
        self.rotctld.terminate()
        self.rotctld.wait(10)

    def restart_rotctld(self) -> None:
        self.start_rotctld(self._rotctld_args, self._rotctld_env)

    def close(self) -> None:
        for process in reversed(self.processes):
            if process.poll() is None:
                process.terminate()
                try:
                    process.wait(10)
                except subprocess.TimeoutExpired:
                    process.kill()
                    process.wait()

    def ask(self, *commands: str) -> list[list[str]]:
        """Asks rotctld directly, beside the server under test: what the rotator says, not what the
        server made of it. One reply (its lines up to RPRT) per command."""
        replies = []
        with socket.create_connection(("127.0.0.1", self.port), timeout=10) as connection:
            stream = connection.makefile("rw")
            for command in commands:
                stream.write(f"+{command}\n")
                stream.flush()
                lines = []
                while not (line := stream.readline().rstrip("\n")).startswith("RPRT"):
                    lines.append(line)
                assert line == "RPRT 0", f"rotctld answered {command!r} with {line}"
                replies.append(lines)
        return replies

    def position(self) -> tuple[float, float]:
        lines = self.ask("p")[0]
        return float(lines[1].split(":")[1]), float(lines[2].split(":")[1])

    def moving(self) -> bool:
        return "MOVING" in self.ask("s")[0][1]


@pytest.fixture(scope="session")
def workdir():
    path = Path(tempfile.mkdtemp(prefix="birdcage-mcp-test-"))
    yield path
    shutil.rmtree(path, ignore_errors=True)


@contextlib.contextmanager
def rig(workdir: Path, model: int, variant: str | None, conf: str = "", time_scale: float = TIME_SCALE):
    r = Rig(workdir, model, variant, conf, time_scale)
    try:
        yield r.start()
    finally:
        r.close()


@pytest.fixture(scope="module")
def g2(workdir):
    # pointing=none: predictive pointing would aim a scan's stepping targets ahead of themselves.
    with rig(workdir, 90105, "g2", "pointing=none") as r:
        yield r


@pytest.fixture(scope="module")
def g2_real(workdir):
    """A G2 at real speed: a 200 degree azimuth leg lasts about 3 s, long enough to stop it midway."""
    with rig(workdir, 90105, "g2", "pointing=none", time_scale=1) as r:
        yield r


@pytest.fixture(scope="module")
def travler(workdir):
    with rig(workdir, 90102, "hal205") as r:
        yield r


@pytest.fixture(scope="module")
def dummy(workdir):
    with rig(workdir, 1, None) as r:
        yield r


@pytest.fixture
def anyio_backend():
    return "asyncio"


def server_command() -> tuple[str, list[str]]:
    command = os.environ.get("BIRDCAGE_MCP")
    if command:
        return command, []
    beside = Path(sys.executable).with_name("birdcage-mcp")
    if beside.exists():
        return str(beside), []
    return sys.executable, ["-m", "birdcage_mcp.server"]


@contextlib.asynccontextmanager
async def session_for(port: int, message_handler=None, extra_args: list[str] | None = None):
    """A client session with birdcage-mcp spawned over stdio, talking to rotctld on `port`;
    `message_handler` receives the server's notifications; `extra_args` go to the server."""
    command, args = server_command()
    params = StdioServerParameters(command=command,
                                   args=[*args, "--host", "127.0.0.1", "--port", str(port), *(extra_args or [])])
    async with stdio_client(params) as (read, write), \
            ClientSession(read, write, message_handler=message_handler) as session:
        await session.initialize()
        yield session
