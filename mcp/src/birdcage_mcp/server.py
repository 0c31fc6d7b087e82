# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""birdcage-mcp: an MCP server (stdio) that drives a rotator through a running rotctld.

It is a rotctld client, so it runs beside Gpredict or any other client and drives any Hamlib
rotator; the Winegard extras (signal, LNB, sky scan, the backend's own description) are used where
the birdcage backend offers them. It has no raw-console tool: every command goes through rotctld
to the backend, whose session layer refuses the firmware's hazard commands.
"""

from __future__ import annotations

import argparse
import asyncio
import csv
import functools
import json
import math
import os
import re
import tempfile
import time
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from typing import Annotated, Any

from mcp.server.mcpserver import Context, MCPServer
from mcp.server.mcpserver.exceptions import ResourceError, ToolError
from pydantic import Field

from .rotctld import Rotctld, RotctldError, RotctldRefused
from .scan import axis, find_peaks, serpentine

try:
    __version__ = version("birdcage-mcp")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0"

NOT_OFFERED = "not offered by this rotator"
ENAVAIL = -11
ENIMPL = -4
# Two readings this close are the same position (rotctld prints two decimals).
SAME_POSITION_DEG = 0.011
# A reading this close to where the dish was sent counts as arrived (the skyscan tool's default).
ARRIVAL_TOLERANCE_DEG = 0.2
POLL_INTERVAL_S = 0.05
# A rotator that has not moved for this long and reports no motion has stopped short of the target.
STILL_FOR_S = 1.5

CONF_FROM_INFO = {
    # key: (regex on the backend's `_` text, how to turn the match into the value)
    "variant": (r"\[([a-z0-9]+),", lambda m: m.group(1)),
    "pointing": (r"; pointing (\w+)", lambda m: m.group(1)),
    "leapfrog": (r"; leapfrog (on|off)", lambda m: "1" if m.group(1) == "on" else "0"),
    "el_min": (r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", lambda m: m.group(1)),
    "el_max": (r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", lambda m: m.group(2)),
    "az_mapping": (r"; azimuth mapping (\w+)", lambda m: m.group(1)),
}
WINEGARD_CONF_KEYS = [
    "variant", "pointing", "deadband", "deadband_share", "leapfrog", "time_scale", "az_mapping",
    "pass_model", "latitude", "boot_timeout", "skip_init", "el_min", "el_max", "az_min", "az_max",
]


def azimuth_difference(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 360.0))


class Birdcage:
    """What the tools share: the rotctld connection and what was learned about the rotator."""

    def __init__(self, host: str, port: int):
        self.rot = Rotctld(host, port)

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

    async def require_receiver(self, what: str) -> None:
        """Signal and LNB exist only as the birdcage backend's extension levels."""
        if "RSSI" not in await self.levels():
            raise ToolError(
                f"{what} is {NOT_OFFERED}: rotctld lists no RSSI/LNB levels (`v ?`); they come with the "
                "birdcage backend's Winegard models (a Carryout G2 has the tuner)"
            )

    async def limits(self) -> dict[str, Any]:
        state = await self.rot.ask("\\dump_state")
        limits: dict[str, Any] = {
            "model": int(state.value("Rotor Model")),
            "az_min": float(state.value("Minimum Azimuth")),
            "az_max": float(state.value("Maximum Azimuth")),
            "el_min": float(state.value("Minimum Elevation")),
            "el_max": float(state.value("Maximum Elevation")),
            "source": "rotctld's range check (dump_state)",
        }
        info = await self.info_text()
        if match := re.search(r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", info):
            # The backend clamps targets to the variant's (or el_min/el_max's) range, which is
            # narrower than the wide range its caps give rotctld's own check.
            limits["protocol_el_min"], limits["protocol_el_max"] = limits["el_min"], limits["el_max"]
            limits["el_min"], limits["el_max"] = float(match.group(1)), float(match.group(2))
            limits["source"] = "the birdcage backend's elevation limits (`_`); azimuth: rotctld's range check"
        if match := re.search(r"cable wrap (-?[\d.]+)\.\.(-?[\d.]+)", info):
            limits["cable_wrap_mechanical"] = [float(match.group(1)), float(match.group(2))]
        return limits

    async def status(self) -> list[str]:
        try:
            reply = await self.rot.ask("s")
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                return []
            raise
        # Hamlib 4.5.4's rotctld prints each flag twice ("BUSY MOVING BUSY MOVING").
        return list(dict.fromkeys(reply.value("Status flags").split()))


def tool_errors(function):
    """Turns a rotctld failure into the tool's error text."""

    @functools.wraps(function)
    async def wrapper(*args, **kwargs):
        try:
            return await function(*args, **kwargs)
        except RotctldError as error:
            raise ToolError(str(error)) from None

    return wrapper


def build_server(host: str = "localhost", port: int = 4533) -> MCPServer:
    bird = Birdcage(host, port)
    server = MCPServer(
        "birdcage",
        version=__version__,
        instructions=(
            f"Drives a rotator (antenna mount, e.g. a Winegard dish with the birdcage backend) through rotctld at "
            f"{host}:{port}. Angles are degrees: azimuth clockwise from north, elevation above the horizon. "
            "Read get_limits before moving; move_to waits until the dish has settled and says when a target was "
            "clamped. Signal, LNB and sky_scan need a Winegard G2 behind the birdcage backend."
        ),
    )

    async def position_dict() -> dict[str, float]:
        az, el = await bird.rot.position()
        return {"azimuth": az, "elevation": el}

    @server.tool()
    @tool_errors
    async def get_position() -> dict[str, float]:
        """The rotator's current azimuth and elevation in degrees (rotctld `p`)."""
        return await position_dict()

    @server.tool()
    @tool_errors
    async def move_to(
        azimuth: Annotated[float, Field(description="target azimuth, degrees clockwise from north (0..360)")],
        elevation: Annotated[float, Field(description="target elevation, degrees above the horizon")],
        ctx: Context,
        wait: Annotated[bool, Field(description="wait until the dish has settled (default true)")] = True,
        timeout_s: Annotated[float, Field(description="longest wait for the move, seconds", gt=0, le=900)] = 180,
    ) -> dict[str, Any]:
        """Points the rotator at (azimuth, elevation) and, unless wait is false, waits until it has
        settled. Reports where it ended up and whether the target was clamped to the rotator's limits."""
        limits = await bird.limits()
        notes = []
        predictive = "; pointing predictive" in await bird.info_text()
        expected_el = min(max(elevation, limits["el_min"]), limits["el_max"])
        if expected_el != elevation:
            notes.append(f"elevation {elevation:g} is outside {limits['el_min']:g}..{limits['el_max']:g}: "
                         f"clamped to {expected_el:g}")
        try:
            await bird.rot.ask("P", f"{azimuth:.2f}", f"{elevation:.2f}")
        except RotctldRefused as error:
            raise ToolError(
                f"the rotator refused az {azimuth:g} el {elevation:g} ({error}); rotctld accepts azimuth "
                f"{limits.get('az_min'):g}..{limits.get('az_max'):g} and elevation "
                f"{limits.get('protocol_el_min', limits['el_min']):g}..{limits.get('protocol_el_max', limits['el_max']):g}"
            ) from None
        result: dict[str, Any] = {"requested": {"azimuth": azimuth, "elevation": elevation}}
        clamped = bool(notes)
        if not wait:
            result.update(settled=False, position=await position_dict(), clamped=clamped, notes=notes)
            return result
        started = time.monotonic()
        az, el = await settle(ctx, azimuth % 360.0, expected_el, timeout_s)
        result["seconds"] = round(time.monotonic() - started, 2)
        result["position"] = {"azimuth": az, "elevation": el}
        result["settled"] = True
        at_target = (azimuth_difference(az, azimuth % 360.0) <= ARRIVAL_TOLERANCE_DEG
                     and abs(el - expected_el) <= ARRIVAL_TOLERANCE_DEG)
        if not at_target:
            if predictive:
                notes.append(f"the rotator rests at az {az:.2f} el {el:.2f}, not at the target: the backend's "
                             "predictive pointing (made for following a pass) took the targets for a moving "
                             "satellite and aimed ahead; for separate moves run rotctld with -C pointing=none")
            else:
                clamped = True
                notes.append(f"the rotator stopped at az {az:.2f} el {el:.2f}, not at the target: clamped to its "
                             "limits (e.g. the backend's az_min/az_max) or stopped")
        result["at_target"] = at_target
        result["clamped"] = clamped
        result["notes"] = notes
        return result

    async def settle(ctx: Context, az_target: float, el_target: float, timeout_s: float) -> tuple[float, float]:
        """Polls `p` until two successive readings agree with the target, or the rotator has been still
        and not MOVING for STILL_FOR_S (stopped short: clamped or stopped). Sends progress meanwhile."""
        deadline = time.monotonic() + timeout_s
        last: tuple[float, float] | None = None
        agreeing = 0
        still_since = time.monotonic()
        start: tuple[float, float] | None = None
        reported = 0.0  # progress notifications must increase
        while time.monotonic() < deadline:
            az, el = await bird.rot.position()
            start = start or (az, el)
            near = azimuth_difference(az, az_target) <= ARRIVAL_TOLERANCE_DEG and abs(el - el_target) <= ARRIVAL_TOLERANCE_DEG
            agreeing = agreeing + 1 if near else 0
            # p can read the target while the backend still reports MOVING (a leg finishing, e.g. the
            # elevation one after the azimuth one): settled means both agree.
            if agreeing >= 2 and "MOVING" not in await bird.status():
                return az, el
            if last is None or azimuth_difference(az, last[0]) > SAME_POSITION_DEG or abs(el - last[1]) > SAME_POSITION_DEG:
                still_since = time.monotonic()
                if last is not None:
                    # Degrees travelled on both axes together: the G2 moves one axis after the other.
                    total = azimuth_difference(start[0], az_target) + abs(start[1] - el_target)
                    done = round(total - azimuth_difference(az, az_target) - abs(el - el_target), 2)
                    if done > reported:
                        reported = done
                        await ctx.report_progress(done, round(total, 2), f"az {az:.2f} el {el:.2f}")
            elif time.monotonic() - still_since >= STILL_FOR_S and "MOVING" not in await bird.status():
                return az, el
            last = (az, el)
            await asyncio.sleep(POLL_INTERVAL_S)
        raise ToolError(f"the rotator did not settle within {timeout_s:g} s (last at az {last[0]:.2f} el {last[1]:.2f})"
                        if last else f"no position within {timeout_s:g} s")

    @server.tool()
    @tool_errors
    async def stop() -> dict[str, Any]:
        """Stops the rotator (rotctld `S`). On a Winegard dish a leg already under way finishes; the
        rest of the move is dropped."""
        await bird.rot.ask("S")
        return {"stopped": True, "position": await position_dict()}

    @server.tool()
    @tool_errors
    async def park() -> dict[str, Any]:
        """Sends the rotator to its park position (rotctld `K`); returns at once, the dish moves on."""
        try:
            await bird.rot.ask("K")
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                raise ToolError(f"park is {NOT_OFFERED} ({error})") from None
            raise
        return {"parking": True, "position": await position_dict()}

    @server.tool()
    @tool_errors
    async def home() -> dict[str, Any]:
        """Homes the rotator's axes (rotctld `R 1`; a Carryout G2 runs its homing routine, get_status
        says BUSY meanwhile). Returns at once."""
        try:
            await bird.rot.ask("R", 1)
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                raise ToolError(f"homing is {NOT_OFFERED} ({error}); only the Carryout G2 homes") from None
            raise
        return {"homing": True, "status": await bird.status()}

    @server.tool()
    @tool_errors
    async def get_status() -> dict[str, Any]:
        """The rotator's status flags (rotctld `s`: e.g. MOVING, BUSY while homing; none at rest)
        and its position."""
        flags = await bird.status()
        return {"flags": flags, "moving": "MOVING" in flags, "busy": "BUSY" in flags, "position": await position_dict()}

    async def info_dict() -> dict[str, Any]:
        caps = await bird.caps()
        levels = await bird.levels()
        return {
            "rotctld": bird.rot.address,
            "model": int(caps.get("Caps dump for model", "0") or 0),
            "manufacturer": caps.get("Mfg name", ""),
            "model_name": caps.get("Model name", ""),
            "backend_version": caps.get("Backend version", ""),
            "info": await bird.info_text(),
            "levels": levels,
            "winegard_extras": "RSSI" in levels,
        }

    @server.tool()
    @tool_errors
    async def get_info() -> dict[str, Any]:
        """What the rotator is: model, manufacturer, backend version, the backend's own description
        (rotctld `_`: for a Winegard dish its variant, limits, cable wrap, pointing mode, faults) and
        its extension levels."""
        return await info_dict()

    @server.tool()
    @tool_errors
    async def get_limits() -> dict[str, Any]:
        """The range targets are held to: azimuth and elevation minimum and maximum in degrees."""
        return await bird.limits()

    @server.tool()
    @tool_errors
    async def read_signal(
        samples: Annotated[int, Field(description="reads averaged (20 ms each)", ge=1, le=100)] = 10,
    ) -> dict[str, Any]:
        """Signal strength from a Winegard G2's tuner (ADC counts, the average of `samples` reads).
        Not offered by other rotators."""
        await bird.require_receiver("read_signal")
        try:
            await bird.rot.ask("V", "RSSI_SAMPLES", samples)
            value = float((await bird.rot.ask("v", "RSSI", timeout=30)).lines[0])
        except RotctldRefused as error:
            if error.code == ENAVAIL:
                raise ToolError(f"read_signal is {NOT_OFFERED}: this dish has no tuner the backend can read "
                                f"(only the Carryout G2 has one) ({error})") from None
            raise
        return {"rssi": value, "samples": samples, "position": await position_dict()}

    @server.tool()
    @tool_errors
    async def set_lnb(
        volts: Annotated[int, Field(description="13 (vertical polarisation) or 18 (horizontal, the boot default)")],
    ) -> dict[str, Any]:
        """Sets a Winegard G2's LNB supply: 13 V or 18 V. Not offered by other rotators."""
        if volts not in (13, 18):
            raise ToolError(f"volts must be 13 or 18, not {volts}")
        await bird.require_receiver("set_lnb")
        try:
            await bird.rot.ask("V", "LNB", volts)
            now = float((await bird.rot.ask("v", "LNB")).lines[0])
        except RotctldRefused as error:
            if error.code == ENAVAIL:
                raise ToolError(f"set_lnb is {NOT_OFFERED}: this dish has no tuner (only the Carryout G2 has one) "
                                f"({error})") from None
            raise
        return {"lnb_volts": now}

    @server.tool()
    @tool_errors
    async def get_conf(
        key: Annotated[str, Field(description="a conf parameter of the birdcage backend, e.g. pointing, el_min, variant")],
    ) -> dict[str, Any]:
        """A conf parameter's running value, as far as rotctld can tell it. rotctld 4.5 has no command that
        reads a conf parameter back, so the value comes from the backend's own description (`_`); the
        keys it covers: variant, pointing, leapfrog, el_min, el_max, az_mapping."""
        if not re.fullmatch(r"[a-z_]+", key):
            raise ToolError(f"{key!r} is not a conf parameter name")
        info = await bird.info_text()
        if not info.startswith("Winegard"):
            raise ToolError(f"get_conf is {NOT_OFFERED}: it reads the birdcage backend's description, and this "
                            f"rotator is not a Winegard behind that backend (its `_`: {info or 'nothing'})")
        if key in CONF_FROM_INFO:
            pattern, convert = CONF_FROM_INFO[key]
            if match := re.search(pattern, info):
                return {"key": key, "value": convert(match), "source": "the backend's description (`_`)"}
            raise ToolError(f"the backend's description does not state {key} now: {info}")
        if key in WINEGARD_CONF_KEYS:
            raise ToolError(
                f"{key} cannot be read back through rotctld 4.5 (its protocol can set a conf parameter, `C`, but not "
                f"read one); it is what rotctld was started with (`-C {key}=...`) or the model's default "
                f"(`rotctl -m <model> -L` lists the defaults). Readable here: {', '.join(CONF_FROM_INFO)}"
            )
        raise ToolError(f"unknown conf parameter {key!r}; the birdcage backend's are: {', '.join(WINEGARD_CONF_KEYS)}")

    @server.tool()
    @tool_errors
    async def sky_scan(
        az_min: Annotated[float, Field(description="first azimuth column, degrees")],
        az_max: Annotated[float, Field(description="last azimuth column, degrees")],
        el_min: Annotated[float, Field(description="lowest elevation, degrees")],
        el_max: Annotated[float, Field(description="highest elevation, degrees")],
        step: Annotated[float, Field(description="grid step on both axes, degrees", gt=0, le=90)],
        ctx: Context,
        samples: Annotated[int, Field(description="reads averaged per point", ge=1, le=100)] = 10,
        lnb_volts: Annotated[int | None, Field(description="LNB supply to set first: 13 or 18 (default: leave it)")] = None,
        csv_path: Annotated[str | None, Field(description="where to write the CSV (default: a new file in the temp directory)")] = None,
    ) -> dict[str, Any]:
        """Scans a grid of the sky with a Winegard G2: moves through it column by column (serpentine),
        reads the signal at each point, writes `az,el,value,time` rows to a CSV as it goes and reports
        progress per point. Returns the peaks (local maxima above the floor + 6 robust sigma, one per 4
        degrees), the strongest point and the CSV's path. The same scan as the
        birdcage-skyscan program; rotctld should run with `-C pointing=none`."""
        if az_min > az_max or el_min > el_max:
            raise ToolError("az_min must not exceed az_max, nor el_min el_max")
        if lnb_volts not in (None, 13, 18):
            raise ToolError(f"lnb_volts must be 13 or 18, not {lnb_volts}")
        plan = serpentine(axis(az_min, az_max, step), axis(el_min, el_max, step))
        if len(plan) > 20000:
            raise ToolError(f"{len(plan)} points is too many for one call (at most 20000); use a larger step")
        await bird.require_receiver("sky_scan")
        info = await bird.info_text()
        if "; pointing predictive" in info:
            raise ToolError("rotctld runs the G2 in predictive pointing, which takes a scan's stepping targets for a "
                            "slow satellite and aims ahead of them: restart rotctld with `-C pointing=none` to scan")
        limits = await bird.limits()
        if el_min < limits["el_min"] or el_max > limits["el_max"]:
            raise ToolError(f"elevations {el_min:g}..{el_max:g} leave the dish's range "
                            f"{limits['el_min']:g}..{limits['el_max']:g}")
        try:
            await bird.rot.ask("v", "LNB")  # a dish without a tuner refuses every receiver level
            await bird.rot.ask("V", "RSSI_SAMPLES", samples)
            if lnb_volts is not None:
                await bird.rot.ask("V", "LNB", lnb_volts)
        except RotctldRefused as error:
            raise ToolError(f"sky_scan is {NOT_OFFERED}: {error} (only the Carryout G2 has a tuner)") from None
        if csv_path is None:
            stamp = datetime.now(timezone.utc).strftime("%Y%m%dT%H%M%SZ")
            handle, csv_path = tempfile.mkstemp(prefix=f"birdcage-skyscan-{stamp}-", suffix=".csv")
            os.close(handle)
        csv_path = os.path.abspath(csv_path)
        rows: list[tuple[float, float, float]] = []
        started = time.monotonic()
        try:
            with open(csv_path, "w", newline="") as file:
                writer = csv.writer(file, lineterminator="\n")
                writer.writerow(["az", "el", "value", "time"])
                file.flush()
                for n, (az, el) in enumerate(plan):
                    await bird.rot.ask("P", f"{az:.2f}", f"{el:.2f}")
                    await arrive(az, el)
                    value = float((await bird.rot.ask("v", "RSSI", timeout=30)).lines[0])
                    rows.append((az, el, value))
                    writer.writerow([f"{az:.2f}", f"{el:.2f}", f"{value:g}",
                                     datetime.now(timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")])
                    file.flush()
                    await ctx.report_progress(n + 1, len(plan), f"az {az:.2f} el {el:.2f} value {value:g}")
        except (asyncio.CancelledError, Exception):
            # Whatever ended the scan early, the dish should not keep going to the last point.
            try:
                await asyncio.shield(bird.rot.ask("S"))
            except Exception:
                pass
            raise
        floor, peaks = find_peaks(rows)
        strongest = max(rows, key=lambda row: row[2])
        return {
            "points": len(rows),
            "seconds": round(time.monotonic() - started, 1),
            "csv": csv_path,
            "floor": floor,
            "peaks": [{"value": v, "azimuth": a, "elevation": e} for v, a, e in peaks],
            # A small grid on a satellite has too little floor for the peak threshold: say where it was strongest.
            "strongest": {"value": strongest[2], "azimuth": strongest[0], "elevation": strongest[1]},
            "plot": f"tools/skyscan_plot.py {csv_path} --out scan.png (from the birdcage source tree)",
        }

    async def arrive(az: float, el: float) -> None:
        """Two successive `p` within ARRIVAL_TOLERANCE_DEG of the point; a dish at rest elsewhere
        for 5 s was aimed elsewhere."""
        deadline = time.monotonic() + 180
        agreeing = 0
        last = None
        still_since = time.monotonic()
        while time.monotonic() < deadline:
            now_az, now_el = await bird.rot.position()
            near = azimuth_difference(now_az, az) <= ARRIVAL_TOLERANCE_DEG and abs(now_el - el) <= ARRIVAL_TOLERANCE_DEG
            agreeing = agreeing + 1 if near else 0
            if agreeing >= 2:
                return
            if (now_az, now_el) != last:
                last, still_since = (now_az, now_el), time.monotonic()
            elif time.monotonic() - still_since > 5:
                raise ToolError(f"the dish rests at az {now_az:.2f} el {now_el:.2f} instead of {az:g} {el:g}")
            await asyncio.sleep(POLL_INTERVAL_S)
        raise ToolError(f"the dish did not reach az {az:g} el {el:g} within 180 s")

    # ---- resources ----

    @server.resource("birdcage://position", mime_type="application/json",
                     description="The rotator's azimuth and elevation now")
    async def position_resource() -> str:
        try:
            return json.dumps(await position_dict())
        except RotctldError as error:
            raise ResourceError(str(error)) from None

    @server.resource("birdcage://limits", mime_type="application/json",
                     description="The range targets are held to")
    async def limits_resource() -> str:
        try:
            return json.dumps(await bird.limits())
        except RotctldError as error:
            raise ResourceError(str(error)) from None

    @server.resource("birdcage://info", mime_type="application/json",
                     description="Model, backend version, the backend's description and extension levels")
    async def info_resource() -> str:
        try:
            return json.dumps(await info_dict())
        except RotctldError as error:
            raise ResourceError(str(error)) from None

    # ---- prompts ----

    @server.prompt(description="Check a newly connected rotator step by step before first use")
    def first_setup() -> str:
        return (
            "Help me check a rotator that rotctld has just opened, one step at a time, and stop at the first problem.\n"
            "1. get_info: which model and manufacturer; for a Winegard dish, read the backend's description "
            "(variant, 'initialised', whether the axes are homed, faults, the pointing mode).\n"
            "2. get_limits: the azimuth and elevation range. Tell me if it does not fit the mount I describe.\n"
            "3. get_status and get_position: the dish should be at rest. If the description says the axes are "
            "not homed, a Carryout G2 needs home (then wait until get_status no longer says BUSY).\n"
            "4. A small test move: move_to a point 5 degrees from the current position, inside the limits, and "
            "report how long it took and where it settled. Then stop, and park only if I ask.\n"
            "5. If get_info lists the RSSI level (a Carryout G2): read_signal with 10 samples, and tell me whether "
            "the LNB is at 13 or 18 V is worth changing for the satellites I want.\n"
            "Never send anything but these tools: there is no raw console, and the dish must not be driven past "
            "its limits."
        )

    @server.prompt(description="Plan and run a sky scan with a Winegard G2 and read its peaks")
    def sky_scan_guide(region: str = "the geostationary arc visible from here") -> str:
        return (
            f"Plan a sky scan of {region} with the dish.\n"
            "1. get_info: the rotator must list the RSSI level (a Carryout G2 behind the birdcage backend), and its "
            "description must say 'pointing none'; otherwise tell me to restart rotctld with -C pointing=none.\n"
            "2. get_limits: keep el_min/el_max inside the dish's elevation range.\n"
            "3. Start coarse: a 4 degree step over the region (each point takes about 0.4 s at real speed plus the "
            "move), show me the number of points and the expected time before starting.\n"
            "4. sky_scan with lnb_volts 13 (vertical; the polarisation most Ku-band TV satellites use for the "
            "strong transponders) and samples 10; report its progress.\n"
            "5. Read the peaks: each is a candidate satellite; compare their azimuth/elevation with the "
            "geostationary arc for my latitude. Then offer a finer scan (1-2 degrees) around the strongest peak.\n"
            "6. Give me the CSV path and the plot command the result names."
        )

    return server


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="birdcage-mcp",
        description="MCP server (stdio) that drives a rotator through rotctld: position, moves, park, "
        "homing, and a Winegard G2's signal, LNB and sky scan.",
    )
    parser.add_argument("--host", default="localhost", help="rotctld's host (default localhost)")
    parser.add_argument("--port", type=int, default=4533, help="rotctld's TCP port (default 4533)")
    parser.add_argument("--version", action="version", version=f"birdcage-mcp {__version__}")
    args = parser.parse_args(argv)
    build_server(args.host, args.port).run("stdio")


if __name__ == "__main__":
    main()
