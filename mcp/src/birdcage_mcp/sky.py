# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""The sky for the tools: birdcage-track and birdcage-align run as child processes with --json, and
their answers are read (the sky tools are the one implementation of the sky, docs/sky.md). This
module computes no position itself: it finds the programs, gives them the station, the rotctld and
the clock, and follows a track's JSON lines."""

from __future__ import annotations

import asyncio
import collections
import json
import logging
import os
import shutil
import signal
import time
from dataclasses import dataclass, field
from datetime import datetime, timedelta, timezone
from typing import Any

from mcp.server.mcpserver.exceptions import ToolError

from .models import Position, TrackPoint, TrackResult

logger = logging.getLogger(__name__)

TRACK = "birdcage-track"
ALIGN = "birdcage-align"
# A query (search, passes, visible) reads TLE files and asks rotctld for its limits: seconds.
QUERY_TIMEOUT_S = 120.0
# After SIGTERM birdcage-track sends `S` and prints its end event; a child that does not is killed.
STOP_TIMEOUT_S = 20.0
# A track started with wait false has no reader for its samples: keep only the latest ones.
MAX_PENDING_SAMPLES = 1000


def iso(moment: datetime) -> str:
    """UTC, milliseconds, `Z`: what birdcage-track prints and takes (--at)."""
    return moment.astimezone(timezone.utc).strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"


def parse_time(text: str) -> datetime:
    moment = datetime.fromisoformat(text.replace("Z", "+00:00"))
    return moment if moment.tzinfo else moment.replace(tzinfo=timezone.utc)


def find_program(name: str, configured: str | None) -> str | None:
    """The configured path (option or environment), else the program on PATH."""
    return configured or shutil.which(name)


class SkyClock:
    """The instant the sky is computed for. Normally the real clock; for a rehearsal against the
    emulator (--at, --time-scale), a clock that starts at `at` when the server starts and runs
    `scale` times faster, handed to every child as its own --at/--time-scale."""

    def __init__(self, at: datetime | None = None, scale: float | None = None):
        self.at = at
        self.scale = scale
        self._started = time.monotonic()

    @property
    def rehearsal(self) -> bool:
        return self.at is not None or self.scale is not None

    def now(self) -> datetime:
        if not self.rehearsal:
            return datetime.now(timezone.utc)
        start = self.at or datetime.fromtimestamp(time.time() - (time.monotonic() - self._started), timezone.utc)
        return start + timedelta(seconds=(time.monotonic() - self._started) * (self.scale or 1.0))

    def args(self) -> list[str]:
        if not self.rehearsal:
            return []
        return ["--at", iso(self.now()), "--time-scale", f"{self.scale or 1.0:g}"]


@dataclass
class SkyOptions:
    """What every child is given: the rotctld this server uses, the station, the TLEs, the clock."""

    host: str = "localhost"
    port: int = 4533
    track_program: str | None = None
    align_program: str | None = None
    lat: float | None = None
    lon: float | None = None
    alt: float | None = None
    tles: list[str] = field(default_factory=list)
    clock: SkyClock = field(default_factory=SkyClock)


def first_line(text: str) -> str:
    lines = [line.strip() for line in text.splitlines() if line.strip()]
    return lines[-1] if lines else ""


class Tracking:
    """One birdcage-track child (--json TARGET) and what its JSON lines said so far."""

    def __init__(self, target: str, process: asyncio.subprocess.Process):
        self.target = target
        self.process = process
        self.started = time.monotonic()
        self.plan: dict[str, Any] | None = None
        self.latest: dict[str, Any] | None = None  # the last wait or progress event
        self.end: dict[str, Any] | None = None
        self.stopped_by: str | None = None
        self.exit_status: int | None = None
        self.stderr_tail: collections.deque[str] = collections.deque(maxlen=20)
        self.events = 0
        self._changed = asyncio.Condition()
        # Every wait/progress event in order, for the one call that follows the track (the track
        # tool's progress); None at the end. Filled from the start, so nothing before it is missed.
        self._samples: asyncio.Queue = asyncio.Queue()
        self.finished = asyncio.Event()
        self._reader = asyncio.create_task(self._read())

    @property
    def running(self) -> bool:
        return not self.finished.is_set()

    async def _notify(self) -> None:
        async with self._changed:
            self.events += 1
            self._changed.notify_all()

    async def _read_stderr(self) -> None:
        assert self.process.stderr is not None
        async for raw in self.process.stderr:
            line = raw.decode(errors="replace").rstrip()
            if line:
                self.stderr_tail.append(line)

    async def _read(self) -> None:
        assert self.process.stdout is not None
        stderr = asyncio.create_task(self._read_stderr())
        try:
            async for raw in self.process.stdout:
                try:
                    event = json.loads(raw)
                except ValueError:
                    logger.info("birdcage-track printed a line that is not JSON: %r", raw[:200])
                    continue
                if not isinstance(event, dict):
                    continue
                kind = event.get("event")
                if kind == "plan":
                    self.plan = event
                elif kind in ("wait", "progress"):
                    self.latest = event
                    if self._samples.qsize() >= MAX_PENDING_SAMPLES:  # nobody follows (wait false)
                        self._samples.get_nowait()
                    self._samples.put_nowait(event)
                elif kind == "end":
                    self.end = event
                await self._notify()
            await stderr
            self.exit_status = await self.process.wait()
        finally:
            self.finished.set()
            self._samples.put_nowait(None)
            await self._notify()

    async def samples(self):
        """Every wait and progress event since the start, in order, until the track ends (one reader)."""
        while (event := await self._samples.get()) is not None:
            yield event

    async def wait_change(self, seen: int) -> int:
        """Until an event newer than `seen` (or the end); returns the new count."""
        async with self._changed:
            await self._changed.wait_for(lambda: self.events > seen or self.finished.is_set())
            return self.events

    async def wait_started(self) -> None:
        """Until the plan (or the child's end: an unknown target, no TLE, rotctld unreachable)."""
        seen = 0
        while self.plan is None and self.running:
            seen = await self.wait_change(seen)

    async def stop(self, by: str) -> None:
        """SIGTERM: birdcage-track stops sending, sends `S`, prints its end event and exits."""
        if self.running:
            self.stopped_by = self.stopped_by or by
            try:
                self.process.send_signal(signal.SIGTERM)
            except ProcessLookupError:
                pass
            try:
                await asyncio.wait_for(self.finished.wait(), STOP_TIMEOUT_S)
            except asyncio.TimeoutError:
                logger.warning("birdcage-track did not end %g s after SIGTERM; killing it", STOP_TIMEOUT_S)
                try:
                    self.process.kill()
                except ProcessLookupError:
                    pass
                await self.finished.wait()

    def kill_now(self) -> None:
        """At the server's exit: no track may outlive the server that answers for it."""
        if self.running and self.process.returncode is None:
            try:
                self.process.send_signal(signal.SIGTERM)
            except ProcessLookupError:
                pass

    def why_failed(self) -> str:
        """The child's own one-line message on stderr (or its end event's reason)."""
        if self.end and self.end.get("reason"):
            return str(self.end["reason"])
        if self.stderr_tail:
            return self.stderr_tail[-1]
        return f"birdcage-track exited with status {self.exit_status} and said nothing"

    def progress(self, event: dict[str, Any] | None = None) -> tuple[float, float | None, str] | None:
        """For an event (default: the latest), sky seconds since the plan, the seconds from the plan to
        its LOS, and a line to show."""
        event = event or self.latest
        if self.plan is None or event is None:
            return None
        try:
            start = parse_time(self.plan["now"])
            now = parse_time(event["now"])
        except (KeyError, ValueError, TypeError):
            return None
        elapsed = (now - start).total_seconds()
        total = None
        if self.plan.get("los"):
            try:
                total = round((parse_time(self.plan["los"]) - start).total_seconds(), 1)
            except ValueError:
                total = None
        if event.get("event") == "wait":
            aim = event.get("aim") or {}
            text = (f"waiting for {self.target}: AOS in {event.get('seconds_to_aos', 0):.0f} s, the dish waits at "
                    f"az {aim.get('az', float('nan')):.2f} el {aim.get('el', float('nan')):.2f}")
        else:
            target, dish = event.get("target") or {}, event.get("dish") or {}
            los = event.get("seconds_to_los")
            text = (f"{self.target} at az {target.get('az', float('nan')):.2f} el {target.get('el', float('nan')):.2f}, "
                    f"dish az {dish.get('az', float('nan')):.2f} el {dish.get('el', float('nan')):.2f}, "
                    f"error {event.get('error_deg', float('nan')):.2f} deg"
                    + (f", LOS in {los:.0f} s" if isinstance(los, (int, float)) else ""))
        return round(max(elapsed, 0.0), 1), total, text

    def last_point(self) -> TrackPoint | None:
        event = self.latest
        if event is None or event.get("event") != "progress":
            return None
        try:
            return TrackPoint(
                target=Position(azimuth=event["target"]["az"], elevation=event["target"]["el"]),
                dish=Position(azimuth=event["dish"]["az"], elevation=event["dish"]["el"]),
                error_deg=event["error_deg"], seconds_to_los=event.get("seconds_to_los"), time=event["now"])
        except (KeyError, TypeError):
            return None

    def result(self) -> TrackResult:
        plan = self.plan or {}
        common = dict(target=str(plan.get("target") or self.target), aos=plan.get("aos"), los=plan.get("los"),
                      max_el=plan.get("max_el"), last=self.last_point(),
                      seconds=round(time.monotonic() - self.started, 2))
        if self.running:
            waiting = self.latest is not None and self.latest.get("event") == "wait"
            shown = self.progress()
            return TrackResult(outcome="waiting" if waiting else "tracking",
                               reason=shown[2] if shown else "started; no position yet", **common)
        end = self.end
        if end is None:
            return TrackResult(outcome="error", reason=self.why_failed(), interrupted_by=self.stopped_by, **common)
        outcome = end.get("outcome", "error")
        interrupted_by = None
        if outcome == "interrupted":
            interrupted_by = self.stopped_by or "a signal from outside this server (birdcage-track got SIGINT/SIGTERM)"
        return TrackResult(
            outcome=outcome if outcome in ("los", "duration", "interrupted", "unreachable", "error") else "error",
            reason=str(end.get("reason") or ""), interrupted_by=interrupted_by,
            rms_error_deg=end.get("rms_error_deg"), max_error_deg=end.get("max_error_deg"),
            samples=int(end.get("samples") or 0), commands_sent=int(end.get("commands_sent") or 0),
            parked=bool(end.get("parked")), **common)


def check_target(target: str) -> None:
    """A target is one word for birdcage-track: never an option of its own."""
    if not target.strip() or target.startswith("-"):
        raise ToolError(f"target {target!r} is not a target: a satellite's name or NORAD number, sun, moon, a "
                        "planet, radec:RA,DEC or azel:AZ,EL")


class Sky:
    """Runs the sky programs for the tools; holds the one track this server may run at a time."""

    def __init__(self, options: SkyOptions):
        self.options = options
        self.tracking: Tracking | None = None  # the running one, or the last one

    @property
    def running(self) -> Tracking | None:
        return self.tracking if self.tracking is not None and self.tracking.running else None

    def program(self, name: str) -> str:
        configured = self.options.track_program if name == TRACK else self.options.align_program
        option = "--track-program" if name == TRACK else "--align-program"
        variable = "BIRDCAGE_TRACK" if name == TRACK else "BIRDCAGE_ALIGN"
        found = find_program(name, configured)
        if found is None:
            raise ToolError(f"{name} was not found on PATH; it comes with birdcage's sky tools (docs/sky.md). "
                            f"Install them, or start birdcage-mcp with {option} PATH (or set {variable})")
        return found

    def common(self) -> list[str]:
        o = self.options
        args = ["--host", o.host, "--port", str(o.port)]
        for flag, value in (("--lat", o.lat), ("--lon", o.lon), ("--alt", o.alt)):
            if value is not None:
                args += [flag, f"{value:g}"]
        for tle in o.tles:
            args += ["--tle", tle]
        return args + o.clock.args()

    async def spawn(self, name: str, args: list[str]) -> asyncio.subprocess.Process:
        program = self.program(name)
        try:
            return await asyncio.create_subprocess_exec(
                program, *self.common(), *args, stdin=asyncio.subprocess.DEVNULL,
                stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE)
        except OSError as error:
            raise ToolError(f"cannot run {program}: {error.strerror or error}") from None

    async def query(self, *args: str, what: str) -> dict[str, Any]:
        """`birdcage-track ARGS --json`: one JSON object on stdout; a failure is the tool's error, in
        the program's own words."""
        process = await self.spawn(TRACK, [*args, "--json"])
        try:
            out, err = await asyncio.wait_for(process.communicate(), QUERY_TIMEOUT_S)
        except asyncio.TimeoutError:
            process.kill()
            await process.wait()
            raise ToolError(f"{what}: birdcage-track did not answer within {QUERY_TIMEOUT_S:g} s") from None
        except asyncio.CancelledError:
            if process.returncode is None:
                process.kill()
            raise
        message = first_line(err.decode(errors="replace"))
        if process.returncode != 0:
            raise ToolError(f"{what}: {message or f'birdcage-track exited with status {process.returncode}'}")
        try:
            answer = json.loads(out)
        except ValueError:
            raise ToolError(f"{what}: birdcage-track's answer is not JSON: {out[:200]!r}") from None
        if not isinstance(answer, dict):
            raise ToolError(f"{what}: birdcage-track's answer is not a JSON object: {out[:200]!r}")
        return answer

    def check_idle(self, tool: str) -> None:
        """A command that moves the dish must not fight a running track: it is refused, naming it."""
        if (running := self.running) is not None:
            raise ToolError(f"{tool} refused: the dish is tracking {running.target} (track, started "
                            f"{time.monotonic() - running.started:.0f} s ago); call stop_tracking first, or stop "
                            "(which ends the tracking and stops the dish)")

    async def start_track(self, target: str, duration_s: float | None, park_at_los: bool) -> Tracking:
        check_target(target)
        args = []
        if duration_s is not None:
            args += ["--duration", f"{duration_s:g}"]
        if park_at_los:
            args.append("--park-at-los")
        process = await self.spawn(TRACK, [*args, "--json", target])
        self.tracking = Tracking(target, process)
        return self.tracking

    def close(self) -> None:
        if self.tracking is not None:
            self.tracking.kill_now()
