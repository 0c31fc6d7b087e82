# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""What the tools know about the rotator behind rotctld: its caps and ranges, its extras, which
tools it supports, and which command of this server last set it moving."""

from __future__ import annotations

import asyncio
import math
import re
import time
from typing import Any

from mcp.server.mcpserver.exceptions import ToolError

from .rotctld import Rotctld, RotctldError, RotctldRefused

NOT_OFFERED = "not offered by this rotator"
# How long the backend's description may take to name a target just sent.
ACCEPT_WAIT_S = 0.5
ENAVAIL = -11
ENIMPL = -4

# Tools every rotator gets; the others depend on what it answers (Birdcage.offer).
# The sky tools run birdcage-track, a rotctld client like this server: any rotator can track.
SKY_TOOLS = ("search_satellites", "get_passes", "get_next_pass", "get_visible_targets", "track", "stop_tracking",
             "get_tracking")
CORE_TOOLS = ("get_position", "move_to", "get_status", "get_info", "get_limits", *SKY_TOOLS)
# birdcage-align measures the geostationary satellites with the tuner.
RECEIVER_TOOLS = ("read_signal", "set_lnb", "sky_scan", "align")
# In the order the server registers them.
ALL_TOOLS = ("get_position", "move_to", "stop", "park", "home", "get_status", "get_info", "get_limits", "read_signal",
             "set_lnb", "get_conf", "sky_scan", *SKY_TOOLS, "align")


def number_text(value: float) -> str:
    """A number as a person reads it: 1e308 stays short, not 309 digits."""
    return f"{value:.6g}"


def check_in_range(name: str, value: float, low: float, high: float, what: str = "this rotator's range") -> None:
    if not math.isfinite(value) or not low <= value <= high:
        raise ToolError(f"{name} {number_text(value)} is outside {what} {low:g}..{high:g}; nothing was sent")


def named_target(info: str) -> tuple[float, float] | None:
    # With a mount model (docs/sky.md) the controller's target is on the dish's axes and the sky's follows it.
    for pattern in (r"; sky target az (-?[\d.]+) el (-?[\d.]+)", r"; target az (-?[\d.]+) el (-?[\d.]+)"):
        if match := re.search(pattern, info):
            return float(match.group(1)), float(match.group(2))
    return None


def named_waypoint(info: str) -> float | None:
    """The azimuth where the leg under way ends when the backend split the move (a stop lands there)."""
    if match := re.search(r"; azimuth by waypoints: the leg under way ends at az (-?[\d.]+)", info):
        return float(match.group(1))
    return None


class Birdcage:
    """What the tools share: the rotctld connection and what was learned about the rotator."""

    def __init__(self, host: str, port: int):
        self.rot = Rotctld(host, port)
        # Every motion command this server sends takes a new serial; a wait that sees the serial
        # change knows which command took over (a stop, another move) without guessing.
        self.motion_serial = 0
        self.motion_by = ""
        self._offer: tuple[int, frozenset[str]] | None = None  # (connection it was learned on, tools)

    def claim_motion(self, what: str) -> int:
        self.motion_serial += 1
        self.motion_by = what
        return self.motion_serial

    # ---- what the rotator is ----

    async def levels(self) -> list[str]:
        try:
            return await self.rot.levels()
        except RotctldRefused:
            return []

    async def caps(self) -> dict[str, str]:
        reply = await self.rot.ask("1")
        return {k: v for k, v in reply.pairs}

    async def info_text(self) -> str:
        try:
            return (await self.rot.ask("_")).value("Info")
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                return ""
            raise

    async def reported_target(self) -> tuple[float, float] | None:
        """The target the birdcage backend is working towards (`_` names it until a stop clears it)."""
        return named_target(await self.info_text())

    async def accepted_target(self, before: tuple[float, float] | None,
                              sent: tuple[float, float]) -> tuple[float, float] | None:
        """The target the backend took from a `P` just sent: the one `_` names once it no longer names
        the one before (the description follows the backend's worker within a cycle or two). It differs
        from `sent` when the backend clamped it (its az_min/az_max conf). None: no birdcage backend."""
        deadline = time.monotonic() + ACCEPT_WAIT_S
        while True:
            info = await self.info_text()
            if not info.startswith("Winegard"):
                return None
            named = named_target(info)
            if named is not None and (named != before or
                                      (abs(math.remainder(named[0] - sent[0], 360.0)) < 0.01 and abs(named[1] - sent[1]) < 0.01)):
                return named
            if time.monotonic() >= deadline:
                return named
            await asyncio.sleep(0.02)

    async def has_tuner(self) -> bool | None:
        """True/False from what rotctld answers; None when it cannot tell now (dish busy, rotctld away)."""
        if "LNB" not in await self.levels():
            return False
        try:
            await self.rot.ask("v", "LNB", timeout=5)
            return True
        except RotctldRefused as error:
            return False if error.code in (ENAVAIL, ENIMPL) else None

    async def offer(self) -> frozenset[str] | None:
        """The tools this rotator supports, learned once per rotctld connection (a reconnect may find
        another rotator behind the same port); None when rotctld cannot be asked."""
        try:
            caps = await self.caps()  # rotctld answers it alone; a dead connection is replaced here
            if self._offer is not None and self._offer[0] == self.rot.connections:
                return self._offer[1]
            tools = set(CORE_TOOLS)
            for tool, cap in (("stop", "Can Stop"), ("park", "Can Park"), ("home", "Can Reset")):
                if caps.get(cap) == "Y":
                    tools.add(tool)
            if (await self.info_text()).startswith("Winegard"):
                tools.add("get_conf")
            tuner = await self.has_tuner()
            if tuner is not False:
                tools.update(RECEIVER_TOOLS)
        except RotctldError:
            return None
        offer = frozenset(tools)
        if tuner is not None:  # unsure: ask again next time
            self._offer = (self.rot.connections, offer)
        return offer

    async def require_receiver(self, what: str) -> None:
        """Signal and LNB exist only as the birdcage backend's extension levels."""
        if "RSSI" not in await self.levels():
            raise ToolError(
                f"{what} is {NOT_OFFERED}: rotctld lists no RSSI/LNB levels (`v ?`); they come with the "
                "birdcage backend's Winegard models (a Carryout G2 has the tuner)"
            )

    async def limits(self) -> dict[str, Any]:
        """The range a target must lie in: the caps' (`1`), narrowed by the backend's elevation limits (`_`)."""
        caps = await self.caps()
        try:
            limits: dict[str, Any] = {
                "model": int(caps.get("Caps dump for model", "0") or 0),
                "az_min": float(caps["Min Azimuth"]),
                "az_max": float(caps["Max Azimuth"]),
                "el_min": float(caps["Min Elevation"]),
                "el_max": float(caps["Max Elevation"]),
                "source": "the rotator's caps (dump_caps)",
            }
        except (KeyError, ValueError):
            raise RotctldError(f"rotctld's caps name no azimuth/elevation range (got: {', '.join(caps) or 'nothing'})") from None
        info = await self.info_text()
        if match := re.search(r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", info):
            limits["protocol_el_min"], limits["protocol_el_max"] = limits["el_min"], limits["el_max"]
            limits["el_min"], limits["el_max"] = float(match.group(1)), float(match.group(2))
            limits["source"] = "the birdcage backend's elevation limits (`_`); azimuth: the rotator's caps (dump_caps)"
        if match := re.search(r"cable wrap (-?[\d.]+)\.\.(-?[\d.]+)", info):
            limits["cable_wrap_mechanical"] = [float(match.group(1)), float(match.group(2))]
        return limits

    async def check_target(self, azimuth: float, elevation: float) -> dict[str, Any]:
        """Refuses a target outside the rotator's range, naming the range; never clamps."""
        limits = await self.limits()
        check_in_range("azimuth", azimuth, limits["az_min"], limits["az_max"])
        check_in_range("elevation", elevation, limits["el_min"], limits["el_max"])
        return limits

    async def status(self) -> list[str] | None:
        """The status flags; None when the rotator cannot report them."""
        try:
            reply = await self.rot.ask("s")
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                return None
            raise
        # Hamlib 4.5.4's rotctld prints each flag twice ("BUSY MOVING BUSY MOVING").
        return list(dict.fromkeys(reply.value("Status flags").split()))
