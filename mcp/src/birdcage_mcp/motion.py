# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""Waiting for the dish: a move until it settles or something else takes over, a stop until the
dish is at rest. Both answer only what rotctld reported, never what was hoped for."""

from __future__ import annotations

import asyncio
import math
import time
from dataclasses import dataclass, field

from mcp.server.mcpserver import Context
from mcp.server.mcpserver.exceptions import ToolError

from .models import Position, StopResult
from .rotator import Birdcage

# Two readings this close are the same position (rotctld prints two decimals).
SAME_POSITION_DEG = 0.011
# A reading this close to where the dish was sent counts as arrived (the skyscan tool's default).
ARRIVAL_TOLERANCE_DEG = 0.2
POLL_INTERVAL_S = 0.05
# A rotator that has not moved for this long and reports no motion has come to rest short of the target.
STILL_FOR_S = 1.5
# A rotator without status flags counts as stopped once its position has not changed for this long.
STOP_STILL_FOR_S = 0.5


def azimuth_difference(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 360.0))


def same_position(a: tuple[float, float], b: tuple[float, float], tolerance: float = SAME_POSITION_DEG) -> bool:
    return azimuth_difference(a[0], b[0]) <= tolerance and abs(a[1] - b[1]) <= tolerance


def in_motion(flags: list[str] | None) -> bool:
    return flags is not None and ("MOVING" in flags or "BUSY" in flags)


@dataclass
class Settled:
    azimuth: float
    elevation: float
    outcome: str
    settled: bool
    interrupted_by: str | None = None
    notes: list[str] = field(default_factory=list)


async def settle(bird: Birdcage, ctx: Context, serial: int, az_target: float, el_target: float,
                 timeout_s: float) -> Settled:
    """Polls `p` until two successive readings agree with the target and the rotator is not MOVING;
    returns at once when another command of this server took over, and says what happened when the
    dish came to rest elsewhere. Sends progress meanwhile."""
    deadline = time.monotonic() + timeout_s
    target = (az_target, el_target)
    last: tuple[float, float] | None = None
    start: tuple[float, float] | None = None
    agreeing = 0
    still_since = time.monotonic()
    reported = 0.0  # progress notifications must increase
    while time.monotonic() < deadline:
        if bird.motion_serial != serial:
            # Flags before position: a position read after "not moving" is where the dish rests.
            at_rest = not in_motion(await bird.status())
            az, el = await bird.rot.position()
            return Settled(az, el, "interrupted", at_rest, bird.motion_by)
        az, el = await bird.rot.position()
        start = start or (az, el)
        agreeing = agreeing + 1 if same_position((az, el), target, ARRIVAL_TOLERANCE_DEG) else 0
        # p can read the target while the backend still reports MOVING (a leg finishing, e.g. the
        # elevation one after the azimuth one): settled means both agree.
        if agreeing >= 2 and not in_motion(await bird.status()):
            # Where it rests, read after the flags said so (the readings above may precede the leg's end).
            az, el = await bird.rot.position()
            return Settled(az, el, "arrived", True)
        if last is None or not same_position((az, el), last):
            still_since = time.monotonic()
            if last is not None:
                # Degrees travelled on both axes together: the G2 moves one axis after the other.
                total = azimuth_difference(start[0], az_target) + abs(start[1] - el_target)
                done = round(total - azimuth_difference(az, az_target) - abs(el - el_target), 2)
                if done > reported:
                    reported = done
                    await ctx.report_progress(done, round(total, 2), f"az {az:.2f} el {el:.2f}")
        elif time.monotonic() - still_since >= STILL_FOR_S and not in_motion(await bird.status()):
            return await at_rest_elsewhere(bird, az, el, target)
        last = (az, el)
        await asyncio.sleep(POLL_INTERVAL_S)
    where = f" (last at az {last[0]:.2f} el {last[1]:.2f})" if last else ""
    raise ToolError(f"the rotator did not settle within {timeout_s:g} s{where}; it may still be moving (get_status)")


async def at_rest_elsewhere(bird: Birdcage, az: float, el: float, target: tuple[float, float]) -> Settled:
    """The dish rests short of the target and this server sent nothing since: the birdcage backend's
    description says whether another rotctld client stopped or redirected it."""
    here = f"az {az:.2f} el {el:.2f}"
    info = await bird.info_text()
    if "; pointing predictive" in info:
        return Settled(az, el, "stopped_short", True, notes=[
            f"the rotator rests at {here}, not at the target: the backend's predictive pointing (made for "
            "following a pass) took the targets for a moving satellite and aimed ahead; for separate moves run "
            "rotctld with -C pointing=none"])
    if info.startswith("Winegard"):
        named = await bird.reported_target()
        if named is None:
            return Settled(az, el, "interrupted", True,
                           "a stop from another rotctld client (the backend no longer names a target)")
        if not same_position(named, target, ARRIVAL_TOLERANCE_DEG):
            return Settled(az, el, "interrupted", True,
                           f"another rotctld client's target az {named[0]:.2f} el {named[1]:.2f}")
        return Settled(az, el, "stopped_short", True, notes=[
            f"the rotator came to rest at {here} and still names this target: it could not reach it "
            "(see get_info for faults and the cable wrap)"])
    return Settled(az, el, "stopped_short", True, notes=[
        f"the rotator came to rest at {here}, not at the target; it does not say why (another rotctld "
        "client may have stopped or moved it)"])


# Why a stop can land short of a move's target on the azimuth axis (docs/mcp.md, "Long azimuth moves").
SPLIT_WHY = ("the backend turns the azimuth in legs shorter than 180° so that the firmware cannot take the other "
             "way round")


async def wait_stopped(bird: Birdcage, wait_s: float, target: tuple[float, float] | None,
                       waypoint: float | None = None) -> StopResult:
    """After `S`: polls until the rotator reports no motion (or, without status flags, its position
    holds), at most wait_s. `target` is what the backend named before the stop: with the axis seen
    moving it tells where the leg under way ends; `waypoint`, named with it when the backend split
    the move, is where the azimuth leg under way ends instead."""
    started = time.monotonic()
    first: tuple[float, float] | None = None
    previous: tuple[float, float] | None = None
    still_since = started
    while True:
        # Flags before position: the leg under way may end between the two readings, and a position
        # read before the flags said "not moving" can be short of where the dish comes to rest.
        flags = await bird.status()
        az, el = await bird.rot.position()
        now = (az, el)
        first = first or now
        if flags is not None:
            at_rest = not in_motion(flags)
        else:
            if previous is None or not same_position(previous, now):
                still_since = time.monotonic()
            at_rest = time.monotonic() - still_since >= STOP_STILL_FOR_S
        seconds = round(time.monotonic() - started, 2)
        if at_rest:
            travelled = azimuth_difference(first[0], az) + abs(first[1] - el)
            after = (f" (it finished the leg under way: {travelled:.1f}° after the stop was sent)"
                     if travelled > ARRIVAL_TOLERANCE_DEG else "")
            # Split: it rests where the leg under way ended, short of the target (not when the last leg
            # had started before the stop).
            split = (waypoint is not None and target is not None
                     and azimuth_difference(az, waypoint) <= ARRIVAL_TOLERANCE_DEG
                     and azimuth_difference(az, target[0]) > ARRIVAL_TOLERANCE_DEG)
            if split:
                after += (f"; the move to az {target[0]:.2f} el {target[1]:.2f} was split ({SPLIT_WHY}): the stop "
                          f"ended it at the end of the leg under way, az {waypoint:.2f}")
            return StopResult(state="stopped", position=Position(azimuth=az, elevation=el), seconds=seconds,
                              split=split, message=f"stopped: the dish is at rest at az {az:.2f} el {el:.2f}{after}")
        if previous is not None and time.monotonic() - started >= wait_s:  # two readings: which axis moves
            leg_end = None
            split = False
            if target is not None and previous is not None:
                az_moving = azimuth_difference(previous[0], az) > SAME_POSITION_DEG
                el_moving = abs(previous[1] - el) > SAME_POSITION_DEG
                split = az_moving and waypoint is not None
                if az_moving or el_moving:
                    leg_end = Position(azimuth=(waypoint if split else target[0]) if az_moving else az,
                                       elevation=target[1] if el_moving else el)
            ends = (f"; the leg under way ends at az {leg_end.azimuth:.2f} el {leg_end.elevation:.2f}" if leg_end
                    else "; where the leg under way ends is not known")
            if split:
                ends += f", short of the move's target az {target[0]:.2f} (the move was split: {SPLIT_WHY})"
            return StopResult(
                state="stopping", position=Position(azimuth=az, elevation=el), seconds=seconds, leg_end=leg_end,
                split=split,
                message=f"still stopping after {seconds:g} s: the dish is at az {az:.2f} el {el:.2f} and still "
                f"moving (a Winegard finishes the leg under way; the rest of the move is dropped){ends}; "
                "get_status says when it is at rest")
        previous = now
        await asyncio.sleep(POLL_INTERVAL_S)
