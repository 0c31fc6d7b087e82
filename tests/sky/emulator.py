# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The emulated dish behind the distribution's rotctld with the birdcage backend preloaded, for the
sky tools' end-to-end tests (as tests/mcp/conftest.py starts them), with the emulator's sky:
--mount, --lat/--lon/--alt, --epoch and --truth (sim/README.md). The emulator's sky clock reads
--epoch when it prints its `device:` line; the moment that line arrives is the wall-clock anchor
the tools get as --at-wall, so their clock and the emulator's agree to a few milliseconds."""

from __future__ import annotations

import contextlib
import csv
import os
import socket
import subprocess
import time
from datetime import datetime
from pathlib import Path


def required(variable: str) -> str:
    value = os.environ.get(variable)
    if not value:
        raise RuntimeError(f"{variable} is not set (tests/sky/CMakeLists.txt sets it from the build tree)")
    return value


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def listening(port: int) -> bool:
    with contextlib.suppress(OSError), socket.create_connection(("127.0.0.1", port), timeout=0.2):
        return True
    return False


class Rig:
    def __init__(self, workdir: Path, variant: str, model: int, time_scale: float, epoch: str, conf: str = "",
                 mount: str = "", station=(45.0, -93.0, 250.0), start=(100.0, 30.0)):
        self.workdir, self.variant, self.model = workdir, variant, model
        self.time_scale, self.epoch, self.conf, self.mount = time_scale, epoch, conf, mount
        self.station, self.start_at = station, start
        self.port = free_port()
        self.truth = workdir / f"truth-{variant}-{self.port}.csv"
        self.sim = self.rotctld = None
        self.anchor = None
        self.sim_stderr = ""

    def start(self) -> "Rig":
        link = self.workdir / f"{self.variant}-{self.port}.tty"
        lat, lon, alt = self.station
        args = [required("BIRDCAGE_SIM"), "--variant", self.variant, "--link", str(link), "--time-scale",
                f"{self.time_scale:g}", "--az", f"{self.start_at[0]:g}", "--el", f"{self.start_at[1]:g}",
                "--lat", f"{lat:g}", "--lon", f"{lon:g}", "--alt", f"{alt:g}", "--epoch", self.epoch,
                "--truth", str(self.truth)]
        if self.mount:
            args += ["--mount", self.mount]
        self.sim_log = open(self.workdir / f"sim-{self.port}.log", "w+")
        self.sim = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=self.sim_log, text=True)
        line = self.sim.stdout.readline()
        self.anchor = time.time()  # the emulator's sky clock read --epoch just before it printed this
        if not line.startswith("device:"):
            raise RuntimeError(f"birdcage-sim said {line!r}")
        conf = f"time_scale={self.time_scale:g}" + (f",{self.conf}" if self.conf else "")
        env = dict(os.environ, LD_PRELOAD=required("BIRDCAGE_PRELOAD"))
        self.rotctld_log = open(self.workdir / f"rotctld-{self.port}.log", "w")
        self.rotctld = subprocess.Popen([os.environ.get("ROTCTLD", "/usr/bin/rotctld"), "-m", str(self.model), "-r",
                                         str(link), "-T", "127.0.0.1", "-t", str(self.port), "-C", conf],
                                        env=env, stdout=self.rotctld_log, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while not listening(self.port):
            if self.rotctld.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"rotctld did not listen (exit {self.rotctld.poll()})")
            time.sleep(0.05)
        return self

    def clock_args(self) -> list[str]:
        return ["--at", self.epoch, "--at-wall", f"{self.anchor:.6f}", "--time-scale", f"{self.time_scale:g}"]

    def close(self) -> None:
        for proc in (self.rotctld, self.sim):
            if proc is not None and proc.poll() is None:
                proc.terminate()
                try:
                    proc.wait(15)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
        if self.sim is not None:
            self.sim_log.seek(0)
            self.sim_stderr = self.sim_log.read()

    def hazards_ok(self) -> bool:
        return "hazards received: 0" in self.sim_stderr

    def truth_rows(self) -> list[dict]:
        with open(self.truth) as f:
            text = f.read()
        # The emulator may be writing its last line while we read: only whole lines count.
        rows = [r for r in csv.DictReader(text[: text.rfind("\n") + 1].splitlines()) if None not in r.values()]
        for r in rows:
            r["unix"] = datetime.fromisoformat(r["utc"].replace("Z", "+00:00")).timestamp()
            for k in ("t", "dish_az", "dish_el", "sky_az", "sky_el"):
                r[k] = float(r[k])
        return rows


@contextlib.contextmanager
def rig(workdir: Path, *args, **kwargs):
    r = Rig(workdir, *args, **kwargs)
    try:
        yield r.start()
    finally:
        r.close()
