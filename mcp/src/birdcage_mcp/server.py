# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""birdcage-mcp: an MCP server (stdio) that drives a rotator through a running rotctld.

It is a rotctld client, so it runs beside Gpredict or any other client and drives any Hamlib
rotator; the Winegard extras (signal, LNB, sky scan, the backend's own description) are offered
where the rotator answers for them. It has no raw-console tool: every command goes through rotctld
to the backend, whose session layer refuses the firmware's hazard commands.
"""

from __future__ import annotations

import argparse
import asyncio
import csv
import json
import os
import re
import tempfile
import time
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from typing import Annotated, Literal

from mcp.server.mcpserver import Context
from mcp.server.mcpserver.exceptions import ResourceError, ToolError
from mcp_types import ToolAnnotations
from pydantic import Field

from .app import BirdcageServer, tool_errors
from .models import (ConfResult, HomeResult, InfoResult, LimitsResult, LnbResult, MoveResult, ParkResult, Peak,
                     Position, ScanResult, SignalResult, StatusResult, StopResult)
from .motion import ARRIVAL_TOLERANCE_DEG, POLL_INTERVAL_S, SAME_POSITION_DEG, same_position, settle, wait_stopped
from .rotator import ENAVAIL, ENIMPL, NOT_OFFERED, Birdcage, check_in_range, named_target, named_waypoint
from .rotctld import RotctldError, RotctldRefused
from .scan import axis, find_peaks, serpentine

try:
    __version__ = version("birdcage-mcp")
except PackageNotFoundError:  # running from a source tree
    __version__ = "0"

CONF_FROM_INFO = {
    # key: (regex on the backend's `_` text, how to turn the match into the value)
    "variant": (r"\[([a-z0-9]+),", lambda m: m.group(1)),
    "pointing": (r"; pointing (\w+)", lambda m: m.group(1)),
    "leapfrog": (r"; leapfrog (on|off)", lambda m: "1" if m.group(1) == "on" else "0"),
    "el_min": (r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", lambda m: m.group(1)),
    "el_max": (r"; el limits (-?[\d.]+)\.\.(-?[\d.]+)", lambda m: m.group(2)),
    "az_mapping": (r"; azimuth mapping (\w+)", lambda m: m.group(1)),
}
ConfKey = Literal["variant", "pointing", "deadband", "deadband_share", "start_cost", "leapfrog", "time_scale",
                  "az_mapping",
                  "pass_model", "latitude", "motor", "boot_timeout", "skip_init", "el_min", "el_max", "az_min",
                  "az_max", "az_index", "el_index", "tilt_north", "tilt_east"]
Volts = Literal[13, 18]

# What each tool does to the dish, for the client (MCP tool annotations). Reading tools change
# nothing; a move is not destructive (the dish can be sent back) and repeating it changes nothing
# more; homing drives the axes to their stops and relearns where they are. None of them reaches beyond this rotator.
READS = ToolAnnotations(read_only_hint=True, open_world_hint=False)
MOVES = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
SETS = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=True, open_world_hint=False)
HOMES = ToolAnnotations(read_only_hint=False, destructive_hint=True, idempotent_hint=True, open_world_hint=False)
SCANS = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=False, open_world_hint=False)


def build_server(host: str = "localhost", port: int = 4533) -> BirdcageServer:
    bird = Birdcage(host, port)
    server = BirdcageServer(
        bird,
        "birdcage",
        version=__version__,
        instructions=(
            f"Drives a rotator (antenna mount, e.g. a Winegard dish with the birdcage backend) through rotctld at "
            f"{host}:{port}. Angles are degrees: azimuth clockwise from north, elevation above the horizon. "
            "Read get_limits before moving: a target outside them is refused. move_to waits until the dish has "
            "settled and says when another command interrupted it; stop waits until the dish is at rest. Signal, "
            "LNB and sky_scan are offered only for a rotator with a tuner (a Winegard G2 behind the birdcage backend)."
        ),
    )

    async def position_now() -> Position:
        az, el = await bird.rot.position()
        return Position(azimuth=az, elevation=el)

    @server.tool(annotations=READS)
    @tool_errors
    async def get_position() -> Position:
        """The rotator's current azimuth and elevation in degrees (rotctld `p`)."""
        return await position_now()

    @server.tool(annotations=MOVES)
    @tool_errors
    async def move_to(
        azimuth: Annotated[float, Field(description="target azimuth, degrees clockwise from north, within the "
                                                    "rotator's range (get_limits; e.g. -180..540 on a Winegard)")],
        elevation: Annotated[float, Field(description="target elevation, degrees above the horizon, within the "
                                                      "rotator's range (get_limits; e.g. 18..65 on a Carryout G2)")],
        ctx: Context,
        wait: Annotated[bool, Field(description="wait until the dish has settled (default true)")] = True,
        timeout_s: Annotated[float, Field(description="longest wait for the move, seconds", gt=0, le=900)] = 180,
    ) -> MoveResult:
        """Points the rotator at (azimuth, elevation) and, unless wait is false, waits until it has
        settled. A target outside the rotator's range is refused (the range is named); this server never
        clamps. Answers where the dish is and how the move ended: arrived; clamped (the birdcage backend
        took a nearer target, from its az_min/az_max conf); interrupted (by stop, another move_to or
        another rotctld client: it says which); or at rest short of the target."""
        await bird.check_target(azimuth, elevation)
        requested = Position(azimuth=azimuth, elevation=elevation)
        sent = (azimuth % 360.0, elevation)
        before = await bird.reported_target()
        serial = bird.claim_motion(f"move_to(azimuth={azimuth:g}, elevation={elevation:g})")
        started = time.monotonic()
        await bird.rot.ask("P", f"{azimuth:.2f}", f"{elevation:.2f}")
        goal = await bird.accepted_target(before, sent)
        notes = []
        # az_min/az_max clamp the azimuth alone (an elevation outside the range was refused above): a
        # target named with another elevation is another client's.
        clamped = goal is not None and not same_position(goal, sent) and abs(goal[1] - sent[1]) <= SAME_POSITION_DEG
        if clamped:
            notes.append(f"the backend clamped the target to az {goal[0]:.2f} el {goal[1]:.2f} (its az_min/az_max "
                         "conf, which rotctld cannot read back)")
        goal = goal if clamped else sent
        if not wait:
            return MoveResult(requested=requested, outcome="moving", position=await position_now(), settled=False,
                              at_target=False, clamped=clamped, notes=notes)
        end = await settle(bird, ctx, serial, goal[0], goal[1], timeout_s)
        position = Position(azimuth=end.azimuth, elevation=end.elevation)
        outcome = "clamped" if clamped and end.outcome == "arrived" else end.outcome
        notes += end.notes
        if end.outcome == "interrupted":
            notes.append(f"interrupted by {end.interrupted_by}; the dish was at az {end.azimuth:.2f} el "
                         f"{end.elevation:.2f}" + ("" if end.settled else " and still moving"))
        return MoveResult(
            requested=requested, outcome=outcome, position=position, settled=end.settled,
            at_target=same_position((end.azimuth, end.elevation), sent, ARRIVAL_TOLERANCE_DEG), clamped=clamped,
            interrupted_by=end.interrupted_by, seconds=round(time.monotonic() - started, 2), notes=notes)

    @server.tool(annotations=MOVES)
    @tool_errors
    async def stop(
        wait_s: Annotated[float, Field(description="longest wait for the dish to come to rest, seconds", ge=0,
                                       le=10)] = 5,
    ) -> StopResult:
        """Stops the rotator (rotctld `S`) and waits, at most wait_s, until it is at rest. A Winegard
        finishes the leg under way (the firmware has no abort for it) and drops the rest of the move.
        Answers "stopped" only when the rotator reports no motion, with where it stopped; otherwise
        "stopping", with where it is and where the leg under way ends when known. A long azimuth move
        goes in legs (the backend splits it): the answer says so when the stop ended it between them."""
        info = await bird.info_text()
        bird.claim_motion("stop")
        await bird.rot.ask("S")
        return await wait_stopped(bird, wait_s, named_target(info), named_waypoint(info))

    @server.tool(annotations=MOVES)
    @tool_errors
    async def park() -> ParkResult:
        """Sends the rotator to its park position (rotctld `K`); returns at once, the dish moves on
        (get_status says when it is at rest)."""
        bird.claim_motion("park")
        try:
            await bird.rot.ask("K")
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                raise ToolError(f"park is {NOT_OFFERED} ({error})") from None
            raise
        return ParkResult(parking=True, position=await position_now())

    @server.tool(annotations=HOMES)
    @tool_errors
    async def home() -> HomeResult:
        """Homes the rotator's axes (rotctld `R 1`; a Carryout G2 runs its homing routine, get_status
        says BUSY meanwhile). Returns at once."""
        bird.claim_motion("home")
        try:
            await bird.rot.ask("R", 1)
        except RotctldRefused as error:
            if error.code in (ENAVAIL, ENIMPL):
                raise ToolError(f"homing is {NOT_OFFERED} ({error}); only the Carryout G2 homes") from None
            raise
        return HomeResult(homing=True, status=await bird.status() or [])

    @server.tool(annotations=READS)
    @tool_errors
    async def get_status() -> StatusResult:
        """The rotator's status flags (rotctld `s`: e.g. MOVING, BUSY while homing; none at rest)
        and its position."""
        flags = await bird.status() or []
        return StatusResult(flags=flags, moving="MOVING" in flags, busy="BUSY" in flags, position=await position_now())

    async def info_result() -> InfoResult:
        caps = await bird.caps()
        levels = await bird.levels()
        offer = await bird.offer()
        return InfoResult(
            rotctld=bird.rot.address,
            model=int(caps.get("Caps dump for model", "0") or 0),
            manufacturer=caps.get("Mfg name", ""),
            model_name=caps.get("Model name", ""),
            backend_version=caps.get("Backend version", ""),
            info=await bird.info_text(),
            levels=levels,
            winegard_extras="RSSI" in levels,
            tools=server.ordered(offer),
        )

    @server.tool(annotations=READS)
    @tool_errors
    async def get_info() -> InfoResult:
        """What the rotator is: model, manufacturer, backend version, the backend's own description
        (rotctld `_`: for a Winegard dish its variant, limits, cable wrap, pointing mode, faults), its
        extension levels and the tools offered for it."""
        return await info_result()

    @server.tool(annotations=READS)
    @tool_errors
    async def get_limits() -> LimitsResult:
        """The range a target must lie in (azimuth and elevation minimum and maximum, degrees): the
        rotator's caps, narrowed by the birdcage backend's elevation limits. Targets outside are refused."""
        return LimitsResult(**await bird.limits())

    @server.tool(annotations=READS)
    @tool_errors
    async def read_signal(
        samples: Annotated[int, Field(description="reads averaged (20 ms each)", ge=1, le=100)] = 10,
    ) -> SignalResult:
        """Signal strength from a Winegard G2's tuner (ADC counts, the average of `samples` reads).
        Offered only for a rotator with a tuner."""
        await bird.require_receiver("read_signal")
        try:
            await bird.rot.ask("V", "RSSI_SAMPLES", samples)
            value = float((await bird.rot.ask("v", "RSSI", timeout=30)).lines[0])
        except RotctldRefused as error:
            if error.code == ENAVAIL:
                raise ToolError(f"read_signal is {NOT_OFFERED}: this dish has no tuner the backend can read "
                                f"(only the Carryout G2 has one) ({error})") from None
            raise
        return SignalResult(rssi=value, samples=samples, position=await position_now())

    @server.tool(annotations=SETS)
    @tool_errors
    async def set_lnb(
        volts: Annotated[Volts, Field(description="13 (vertical polarisation) or 18 (horizontal, the boot default)")],
    ) -> LnbResult:
        """Sets a Winegard G2's LNB supply: 13 V or 18 V. Offered only for a rotator with a tuner."""
        await bird.require_receiver("set_lnb")
        try:
            await bird.rot.ask("V", "LNB", volts)
            now = float((await bird.rot.ask("v", "LNB")).lines[0])
        except RotctldRefused as error:
            if error.code == ENAVAIL:
                raise ToolError(f"set_lnb is {NOT_OFFERED}: this dish has no tuner (only the Carryout G2 has one) "
                                f"({error})") from None
            raise
        return LnbResult(lnb_volts=now)

    @server.tool(annotations=READS)
    @tool_errors
    async def get_conf(
        key: Annotated[ConfKey, Field(description="a conf parameter of the birdcage backend")],
    ) -> ConfResult:
        """A conf parameter's running value, as far as rotctld can tell it. rotctld 4.5 has no command that
        reads a conf parameter back, so the value comes from the backend's own description (`_`); the
        keys it covers: variant, pointing, leapfrog, el_min, el_max, az_mapping."""
        info = await bird.info_text()
        if not info.startswith("Winegard"):
            raise ToolError(f"get_conf is {NOT_OFFERED}: it reads the birdcage backend's description, and this "
                            f"rotator is not a Winegard behind that backend (its `_`: {info or 'nothing'})")
        if key in CONF_FROM_INFO:
            pattern, convert = CONF_FROM_INFO[key]
            if match := re.search(pattern, info):
                return ConfResult(key=key, value=convert(match), source="the backend's description (`_`)")
            raise ToolError(f"the backend's description does not state {key} now: {info}")
        raise ToolError(
            f"{key} cannot be read back through rotctld 4.5 (its protocol can set a conf parameter, `C`, but not "
            f"read one); it is what rotctld was started with (`-C {key}=...`) or the model's default "
            f"(`rotctl -m <model> -L` lists the defaults). Readable here: {', '.join(CONF_FROM_INFO)}"
        )

    @server.tool(annotations=SCANS)
    @tool_errors
    async def sky_scan(
        az_min: Annotated[float, Field(description="first azimuth column, degrees")],
        az_max: Annotated[float, Field(description="last azimuth column, degrees")],
        el_min: Annotated[float, Field(description="lowest elevation, degrees")],
        el_max: Annotated[float, Field(description="highest elevation, degrees")],
        step: Annotated[float, Field(description="grid step on both axes, degrees", gt=0, le=90)],
        ctx: Context,
        samples: Annotated[int, Field(description="reads averaged per point", ge=1, le=100)] = 10,
        lnb_volts: Annotated[Volts | None, Field(description="LNB supply to set first: 13 or 18 (default: leave it)")] = None,
        csv_path: Annotated[str | None, Field(description="where to write the CSV (default: a new file in the temp directory)")] = None,
    ) -> ScanResult:
        """Scans a grid of the sky with a Winegard G2: moves through it column by column (serpentine),
        reads the signal at each point, writes `az,el,value,time` rows to a CSV as it goes and reports
        progress per point. Returns the peaks (local maxima above the floor + 6 robust sigma, one per 4
        degrees), the strongest point and the CSV's path. The same scan as the
        birdcage-skyscan program; rotctld should run with `-C pointing=none`."""
        if az_min > az_max or el_min > el_max:
            raise ToolError("az_min must not exceed az_max, nor el_min el_max")
        await bird.require_receiver("sky_scan")
        limits = await bird.limits()
        for name, value in (("az_min", az_min), ("az_max", az_max)):
            check_in_range(name, value, limits["az_min"], limits["az_max"])
        for name, value in (("el_min", el_min), ("el_max", el_max)):
            check_in_range(name, value, limits["el_min"], limits["el_max"], "the dish's range")
        plan = serpentine(axis(az_min, az_max, step), axis(el_min, el_max, step))
        if len(plan) > 20000:
            raise ToolError(f"{len(plan)} points is too many for one call (at most 20000); use a larger step")
        if "; pointing predictive" in await bird.info_text():
            raise ToolError("rotctld runs the G2 in predictive pointing, which takes a scan's stepping targets for a "
                            "slow satellite and aims ahead of them: restart rotctld with `-C pointing=none` to scan")
        try:
            await bird.rot.ask("v", "LNB")  # a dish without a tuner refuses every receiver level
        except RotctldRefused as error:
            raise ToolError(f"sky_scan is {NOT_OFFERED}: {error} (only the Carryout G2 has a tuner)") from None
        if csv_path is None:
            stamp = datetime.now(timezone.utc).strftime("%Y%m%dT%H%M%SZ")
            handle, csv_path = tempfile.mkstemp(prefix=f"birdcage-skyscan-{stamp}-", suffix=".csv")
            os.close(handle)
        csv_path = os.path.abspath(csv_path)
        try:  # before anything reaches the dish: an unwritable path is the caller's to fix
            file = open(csv_path, "w", newline="")
        except OSError as error:
            raise ToolError(f"cannot write the scan's CSV to {csv_path}: {error.strerror or error}; nothing was "
                            "moved (give a csv_path in a writable directory, or none for a temp file)") from None
        rows: list[tuple[float, float, float]] = []
        started = time.monotonic()
        with file:
            await bird.rot.ask("V", "RSSI_SAMPLES", samples)
            if lnb_volts is not None:
                await bird.rot.ask("V", "LNB", lnb_volts)
            writer = csv.writer(file, lineterminator="\n")
            writer.writerow(["az", "el", "value", "time"])
            file.flush()
            try:
                for n, (az, el) in enumerate(plan):
                    serial = bird.claim_motion("sky_scan")
                    await bird.rot.ask("P", f"{az:.2f}", f"{el:.2f}")
                    await arrive(serial, az, el, n, len(plan), csv_path)
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
        return ScanResult(
            points=len(rows),
            seconds=round(time.monotonic() - started, 1),
            csv=csv_path,
            floor=floor,
            peaks=[Peak(value=v, azimuth=a, elevation=e) for v, a, e in peaks],
            # A small grid on a satellite has too little floor for the peak threshold: say where it was strongest.
            strongest=Peak(value=strongest[2], azimuth=strongest[0], elevation=strongest[1]),
            plot=f"tools/skyscan_plot.py {csv_path} --out scan.png (from the birdcage source tree)",
        )

    async def arrive(serial: int, az: float, el: float, n: int, points: int, csv_path: str) -> None:
        """Two successive `p` within ARRIVAL_TOLERANCE_DEG of the point; a dish at rest elsewhere
        for 5 s was aimed elsewhere; another command of this server ends the scan."""
        deadline = time.monotonic() + 180
        agreeing = 0
        last = None
        still_since = time.monotonic()
        while time.monotonic() < deadline:
            if bird.motion_serial != serial:
                raise ToolError(f"the scan was interrupted by {bird.motion_by} at point {n + 1} of {points} "
                                f"(az {az:g} el {el:g}); the rows so far are in {csv_path}")
            now_az, now_el = await bird.rot.position()
            agreeing = agreeing + 1 if same_position((now_az, now_el), (az, el), ARRIVAL_TOLERANCE_DEG) else 0
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
            return (await position_now()).model_dump_json()
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
            return (await info_result()).model_dump_json()
        except RotctldError as error:
            raise ResourceError(str(error)) from None

    # ---- prompts ----

    @server.prompt(description="Check a newly connected rotator step by step before first use")
    def first_setup() -> str:
        return (
            "Help me check a rotator that rotctld has just opened, one step at a time, and stop at the first problem.\n"
            "1. get_info: which model and manufacturer; for a Winegard dish, read the backend's description "
            "(the variant and its state first: idle, moving, homing, axes NOT homed, RECOVERING, NOT ANSWERING; "
            "then faults and the pointing mode).\n"
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
