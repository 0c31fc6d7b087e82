# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""UTC instants as floats (seconds since 1970-01-01T00:00:00Z, leap seconds not counted, like
time_t), ISO-8601 text, and the scaled clock of --at/--time-scale."""

from __future__ import annotations

import re
import time
from datetime import datetime, timezone

_ISO = re.compile(
    r"^(\d{4})-(\d{2})-(\d{2})(?:[T ](\d{2}):(\d{2})(?::(\d{2})(\.\d+)?)?)?\s*(Z|[+-]\d{2}:?\d{2})?$", re.I)


def parse_iso(text: str) -> float:
    """YYYY-MM-DD[THH:MM[:SS[.fff]]][Z|+HH:MM]; no zone means UTC. Raises ValueError."""
    m = _ISO.match(text.strip())
    if not m:
        raise ValueError(f"not an ISO-8601 time: {text!r} (e.g. 2026-12-01T18:30:00Z)")
    year, month, day, hour, minute, second = (int(g) if g else 0 for g in m.groups()[:6])
    fraction = float(m.group(7)) if m.group(7) else 0.0
    stamp = datetime(year, month, day, hour, minute, second, tzinfo=timezone.utc).timestamp() + fraction
    zone = m.group(8)
    if zone and zone.upper() != "Z":
        sign = -1 if zone[0] == "-" else 1
        digits = zone[1:].replace(":", "")
        stamp -= sign * (int(digits[:2]) * 3600 + int(digits[2:]) * 60)
    return stamp


def iso(t: float | None, decimals: int = 0) -> str | None:
    """2026-12-01T18:30:00Z (decimals > 0 adds fractional seconds)."""
    if t is None:
        return None
    if decimals <= 0:
        t = round(t)
    text = datetime.fromtimestamp(t, timezone.utc).strftime("%Y-%m-%dT%H:%M:%S")
    if decimals > 0:
        frac = t - int(t // 1)
        text += f"{frac:.{decimals}f}"[1:]
    return text + "Z"


class Clock:
    """The tools' notion of now. Without --at it is the system clock. With --at ISO it reads ISO
    at its origin (the program's start, or the wall-clock moment --at-wall names) and runs
    time_scale times faster than real time from there, so a replay keeps pace with an emulator
    started with --time-scale K and --epoch ISO. Sleeping is in the clock's seconds."""

    def __init__(self, at: float | None = None, time_scale: float = 1.0, origin_wall: float | None = None):
        if time_scale <= 0:
            raise ValueError("the time scale must be positive")
        self.time_scale = time_scale
        wall, mono = time.time(), time.monotonic()
        origin_wall = wall if origin_wall is None else origin_wall
        # Monotonic underneath: the system clock may be stepped while a pass runs.
        self._mono_origin = mono - (wall - origin_wall)
        self._sky_origin = at if at is not None else origin_wall

    def now(self) -> float:
        return self._sky_origin + (time.monotonic() - self._mono_origin) * self.time_scale

    def real_seconds(self, sky_seconds: float) -> float:
        return sky_seconds / self.time_scale

    def sleep(self, sky_seconds: float) -> None:
        if sky_seconds > 0:
            time.sleep(sky_seconds / self.time_scale)

    def sleep_until(self, t: float, real_cap: float | None = None) -> None:
        """Sleeps until the clock reads t (at most real_cap real seconds)."""
        real = (t - self.now()) / self.time_scale
        if real_cap is not None:
            real = min(real, real_cap)
        if real > 0:
            time.sleep(real)
