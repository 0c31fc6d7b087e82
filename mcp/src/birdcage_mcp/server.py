# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""birdcage-mcp: an MCP server (stdio) that drives a rotator through a running rotctld.

It is a rotctld client, so it runs beside Gpredict or any other client and drives any Hamlib
rotator; the Winegard extras (signal, LNB, sky scan, the backend's own description) are offered
where the rotator answers for them. It has no raw-console tool: every command goes through rotctld
to the backend, whose session layer refuses the firmware's hazard commands. The sky (satellites,
passes, tracking, alignment) comes from birdcage-track and birdcage-align, run as child processes
(sky.py): the server computes no position itself.
"""

from __future__ import annotations

import argparse
import asyncio
import csv
import json
import os
import re
import signal
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
from .models import (AlignResult, ConfResult, HomeResult, InfoResult, LimitsResult, LnbResult, MoveResult,
                     NextPassResult, ParkResult, PassesResult, Peak, Position, ScanResult, SearchResult, SignalResult,
                     StatusResult, StopResult, StopTrackingResult, TrackingStatus, TrackResult, VisibleResult)
from .motion import ARRIVAL_TOLERANCE_DEG, POLL_INTERVAL_S, SAME_POSITION_DEG, same_position, settle, wait_stopped
from .rotator import ENAVAIL, ENIMPL, NOT_OFFERED, Birdcage, check_in_range, named_target, named_waypoint
from .rotctld import RotctldError, RotctldRefused
from .scan import axis, find_peaks, serpentine
from .sky import ALIGN, Sky, SkyClock, SkyOptions, check_target, first_line, parse_time

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
# A track moves the dish for as long as the pass lasts; calling it again starts another.
TRACKS = ToolAnnotations(read_only_hint=False, destructive_hint=False, idempotent_hint=False, open_world_hint=False)


def build_server(host: str = "localhost", port: int = 4533, sky_options: SkyOptions | None = None) -> BirdcageServer:
    bird = Birdcage(host, port)
    sky = Sky(sky_options or SkyOptions())
    sky.options.host, sky.options.port = host, port
    server = BirdcageServer(
        bird,
        sky,
        "birdcage",
        version=__version__,
        instructions=(
            f"Drives a rotator (antenna mount, e.g. a Winegard dish with the birdcage backend) through rotctld at "
            f"{host}:{port}. Angles are degrees: azimuth clockwise from north, elevation above the horizon. "
            "Read get_limits before moving: a target outside them is refused. move_to waits until the dish has "
            "settled and says when another command interrupted it; stop waits until the dish is at rest. Signal, "
            "LNB and sky_scan are offered only for a rotator with a tuner (a Winegard G2 behind the birdcage backend). "
            "Tracking without Gpredict, for a headless station: search_satellites, get_passes/get_next_pass and "
            "get_visible_targets say what can be followed; track follows a satellite, the Sun, the Moon or a planet "
            "until it leaves the dish's window (progress as it goes, the pointing error at the end); stop_tracking "
            "ends it. While a track runs, move_to, park, home and sky_scan are refused; stop ends the tracking too. "
            "The tracking_guide prompt says more."
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
        another rotctld client: it says which); or at rest short of the target. Refused while a track
        runs (stop_tracking first)."""
        sky.check_idle("move_to")
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
        goes in legs (the backend splits it): the answer says so when the stop ended it between them.
        A running track is ended first (its birdcage-track sends `S` as it ends)."""
        ended = ""
        if (running := sky.running) is not None:
            await running.stop("stop")
            ended = f"ended the tracking of {running.target} first; "
        info = await bird.info_text()
        bird.claim_motion("stop")
        await bird.rot.ask("S")
        stopped = await wait_stopped(bird, wait_s, named_target(info), named_waypoint(info))
        stopped.message = ended + stopped.message
        return stopped

    @server.tool(annotations=MOVES)
    @tool_errors
    async def park() -> ParkResult:
        """Sends the rotator to its park position (rotctld `K`); returns at once, the dish moves on
        (get_status says when it is at rest). Refused while a track runs."""
        sky.check_idle("park")
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
        says BUSY meanwhile). Returns at once. Refused while a track runs."""
        sky.check_idle("home")
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
        sky.check_idle("sky_scan")
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

    # ---- the sky: birdcage-track / birdcage-align as child processes (sky.py) ----

    def when(text: str | None) -> str:
        return text.replace("T", " ").split(".")[0].rstrip("Z") + " UTC" if text else "?"

    @server.tool(annotations=READS)
    @tool_errors
    async def search_satellites(
        text: Annotated[str, Field(description="part of a satellite's name, or its NORAD number", min_length=1)],
    ) -> SearchResult:
        """Satellites in the TLE files birdcage-track reads (Gpredict's, or those the server was started
        with) whose name contains the text, or whose NORAD number it is (birdcage-track --search)."""
        return SearchResult(**await sky.query("--search", text, what="search_satellites"))

    @server.tool(annotations=READS)
    @tool_errors
    async def get_passes(
        target: Annotated[str, Field(description="a satellite (name, unique prefix or NORAD number), sun, moon, a "
                                                 "planet, radec:RA,DEC or azel:AZ,EL")],
        hours: Annotated[float, Field(description="how far ahead to look", gt=0, le=240)] = 24,
        count: Annotated[int | None, Field(description="at most this many passes", ge=1, le=100)] = None,
    ) -> PassesResult:
        """The target's passes through the dish's window in the next hours: AOS and LOS are where it
        enters and leaves the elevation range the dish can reach (e.g. 18..65 on a Carryout G2), not the
        horizon; with the highest point and the azimuths (birdcage-track --passes)."""
        check_target(target)
        args = ["--passes", "--hours", f"{hours:g}"] + (["--count", str(count)] if count else [])
        return PassesResult(**await sky.query(*args, target, what="get_passes"))

    @server.tool(annotations=READS)
    @tool_errors
    async def get_next_pass(
        target: Annotated[str, Field(description="a satellite (name, unique prefix or NORAD number), sun, moon, a "
                                                 "planet, radec:RA,DEC or azel:AZ,EL")],
        hours: Annotated[float, Field(description="how far ahead to look", gt=0, le=240)] = 24,
    ) -> NextPassResult:
        """The target's next pass through the dish's window (or the one under way) and how long until
        it starts; says so when there is none within the hours searched."""
        check_target(target)
        answer = await sky.query("--passes", "--hours", f"{hours:g}", "--count", "1", target, what="get_next_pass")
        now = sky.options.clock.now()
        passes = answer.pop("passes", [])
        name = answer.get("target", target)
        window = answer.get("limits", {})
        if not passes:
            return NextPassResult(
                **answer, next_pass=None, in_progress=False,
                message=f"no pass of {name} through the dish's window (el {window.get('el_min', 0):g}.."
                        f"{window.get('el_max', 90):g}) in the next {hours:g} h")
        first = passes[0]
        to_aos = (parse_time(first["aos"]) - now).total_seconds()
        in_progress = to_aos <= 0 < (parse_time(first["los"]) - now).total_seconds()
        start = ("under way now" if in_progress else f"AOS {when(first['aos'])} (in {to_aos / 60:.0f} min)")
        return NextPassResult(
            **answer, next_pass=first, in_progress=in_progress, seconds_to_aos=round(max(to_aos, 0.0), 1),
            message=f"{name}: {start} at az {first['aos_az']:.1f}; highest {first['max_el']:.1f} deg at "
                    f"{when(first['tca'])} (az {first['tca_az']:.1f}); LOS {when(first['los'])} at az "
                    f"{first['los_az']:.1f}; {first['duration_s']:.0f} s in the dish's window")

    @server.tool(annotations=READS)
    @tool_errors
    async def get_visible_targets() -> VisibleResult:
        """What is above the dish's elevation floor now: the Sun, the Moon, the planets and every
        satellite in the TLE files, with azimuth, elevation and whether it is inside the dish's window
        (birdcage-track --visible)."""
        return VisibleResult(**await sky.query("--visible", what="get_visible_targets"))

    async def follow(tracking, ctx: Context) -> TrackResult:
        """Progress notifications from the track's JSON lines until it ends."""
        reported = -1.0
        try:
            async for event in tracking.samples():
                shown = tracking.progress(event)
                if shown is not None and shown[0] > reported:
                    reported = shown[0]
                    await ctx.report_progress(shown[0], shown[1], shown[2])
        except asyncio.CancelledError:
            # The client gave up on the call: the dish must not go on following what nobody watches.
            await asyncio.shield(tracking.stop("the track call, cancelled by the client"))
            raise
        return tracking.result()

    @server.tool(annotations=TRACKS)
    @tool_errors
    async def track(
        target: Annotated[str, Field(description="a satellite (name, unique prefix or NORAD number), sun, moon, a "
                                                 "planet, radec:RA,DEC or azel:AZ,EL")],
        ctx: Context,
        duration_s: Annotated[float | None, Field(description="follow for this long (seconds of the sky's clock) "
                                                              "instead of until LOS", gt=0)] = None,
        park_at_los: Annotated[bool, Field(description="park the dish when the track ends")] = False,
        wait: Annotated[bool, Field(description="wait until the track ends (default true); false: return once it "
                                                "has started, then get_tracking / stop_tracking")] = True,
    ) -> TrackResult:
        """Points the dish at the target and follows it (birdcage-track): when it is not yet in the
        dish's window, the dish waits at the point where it will enter; then it follows until LOS (or
        duration_s), with progress notifications (target, dish, pointing error, seconds to LOS). Answers
        how it ended: los or duration, with the RMS and largest pointing error measured from the dish's
        own readings; interrupted, and by what (stop_tracking, stop, a cancelled call); unreachable
        (it never enters the window). One track at a time; move_to, park, home and sky_scan are refused
        while it runs. Gpredict is the usual tracker: this is for a station without one."""
        check_target(target)
        if (running := sky.running) is not None:
            raise ToolError(f"track refused: already tracking {running.target}; call stop_tracking first")
        bird.claim_motion(f"track({target})")
        tracking = await sky.start_track(target, duration_s, park_at_los)
        await tracking.wait_started()
        if tracking.plan is None:  # it ended before planning: unknown target, no TLE, rotctld away
            raise ToolError(f"track {target}: {tracking.why_failed()}")
        if not wait:
            return tracking.result()
        return await follow(tracking, ctx)

    @server.tool(annotations=MOVES)
    @tool_errors
    async def stop_tracking() -> StopTrackingResult:
        """Ends the running track: birdcage-track gets SIGTERM, stops sending, sends the rotator `S` and
        reports how the track went. Answers where the dish is afterwards."""
        running = sky.running
        if running is None:
            last = sky.tracking.result() if sky.tracking is not None else None
            return StopTrackingResult(stopped=False, track=last, message="nothing is being tracked" + (
                f"; the last track ({last.target}) ended: {last.outcome}" if last else ""))
        await running.stop("stop_tracking")
        bird.claim_motion("stop_tracking")
        result = running.result()
        try:
            position = await position_now()
        except RotctldError:
            position = None
        where = f"; the dish is at az {position.azimuth:.2f} el {position.elevation:.2f}" if position else ""
        return StopTrackingResult(stopped=True, track=result, position=position,
                                  message=f"tracking of {result.target} ended ({result.outcome}: {result.reason})"
                                          + where)

    @server.tool(annotations=READS)
    @tool_errors
    async def get_tracking() -> TrackingStatus:
        """Whether a track runs, and how it goes: the plan (AOS, LOS, highest elevation), the last
        sample (target, dish, pointing error); or how the last track ended."""
        if sky.tracking is None:
            return TrackingStatus(tracking=False)
        return TrackingStatus(tracking=sky.running is not None, track=sky.tracking.result())

    @server.tool(annotations=SCANS)
    @tool_errors
    async def align(
        ctx: Context,
        sources: Annotated[list[str] | None, Field(description="geostationary satellites to measure (names from "
                                                               "the catalogue; default: birdcage-align's choice)")] = None,
    ) -> AlignResult:
        """Measures how the dish sits against the sky (birdcage-align: it scans known geostationary
        satellites with the G2's tuner and fits the mount model, docs/sky.md): the four terms with their
        uncertainty, the residuals per satellite and the -C lines that correct the dish. It writes
        nothing: the lines go into the rotctld service's OPTIONS by hand. Refused while a track runs;
        takes minutes (progress per point)."""
        sky.check_idle("align")
        await bird.require_receiver("align")
        args = ["--json"]
        for source in sources or []:
            check_target(source)
            args += ["--source", source]
        bird.claim_motion("align")
        process = await sky.spawn(ALIGN, args)
        result, errors = None, []
        reported = -1.0

        async def read_errors() -> None:
            async for raw in process.stderr:
                errors.append(raw.decode(errors="replace"))

        reader = asyncio.create_task(read_errors())
        try:
            async for raw in process.stdout:
                try:
                    event = json.loads(raw)
                except ValueError:
                    continue
                if event.get("event") == "progress" and event.get("done", -1) > reported:
                    reported = event["done"]
                    await ctx.report_progress(event["done"], event.get("total"), f"{event.get('phase', '')} "
                                              f"{event['done']}/{event.get('total', '?')}")
                elif event.get("event") == "result":
                    result = event
            await reader
            status = await process.wait()
        except asyncio.CancelledError:
            if process.returncode is None:
                process.send_signal(signal.SIGTERM)  # birdcage-align stops the dish as it ends
            raise
        if status != 0 or result is None:
            raise ToolError(f"align: {first_line(''.join(errors)) or f'birdcage-align exited with status {status}'}")
        result.pop("event", None)
        return AlignResult(**result, message="measured; nothing was written: add " + " ".join(
            result.get("conf_lines", [])) + " to rotctld's OPTIONS (e.g. /etc/default/birdcage-rotctld) and restart it")

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

    @server.prompt(description="Follow a satellite, the Sun or the Moon with the dish on a station without Gpredict")
    def tracking_guide(target: str = "the next good pass of a satellite I name") -> str:
        return (
            f"Help me track {target} with the dish.\n"
            "Gpredict is the usual tracker (it drives rotctld itself, docs/gpredict.md); these tools are for a "
            "headless station, or when I ask you to do it. If Gpredict's rotator control is engaged, tell me to "
            "disengage it first: two clients would fight over the dish.\n"
            "1. get_limits: the dish's elevation window (e.g. 18..65 on a Carryout G2). Passes are cut to it.\n"
            "2. Find the target: search_satellites for a satellite's name or NORAD number (ask me when several "
            "match); the Sun, the Moon and the planets go by name. get_visible_targets says what is up now.\n"
            "3. get_next_pass (or get_passes for the next hours): tell me the AOS, the highest elevation and the "
            "LOS in local words, and how long until it starts. A pass whose highest point stays below the "
            "window's floor cannot be tracked.\n"
            "4. track the target: it waits at the entry point until AOS, then follows until LOS; report its "
            "progress now and then, not every notification. With wait false it returns once started; then "
            "get_tracking says how it goes.\n"
            "5. At the end, report the outcome truthfully: the RMS and largest pointing error it measured, or "
            "that it was interrupted and by what, or why it failed. Never claim the dish followed the target "
            "when the outcome says otherwise.\n"
            "stop_tracking ends a track (the dish stops); stop does too. While a track runs, move_to, park, home "
            "and sky_scan are refused: end the track first. Never point the dish at the Sun with a receiver "
            "attached unless I ask: its heat can damage the LNB."
        )

    return server


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(
        prog="birdcage-mcp",
        description="MCP server (stdio) that drives a rotator through rotctld: position, moves, park, "
        "homing, a Winegard G2's signal, LNB and sky scan, and tracking satellites, the Sun, the Moon and the "
        "planets (with birdcage-track) for a station without Gpredict.",
    )
    parser.add_argument("--host", default="localhost", help="rotctld's host (default localhost)")
    parser.add_argument("--port", type=int, default=4533, help="rotctld's TCP port (default 4533)")
    sky = parser.add_argument_group(
        "the sky (birdcage-track and birdcage-align run as child processes; they read the station from these "
        "options or from BIRDCAGE_LAT / BIRDCAGE_LON / BIRDCAGE_ALT)")
    sky.add_argument("--track-program", default=os.environ.get("BIRDCAGE_TRACK"), metavar="PATH",
                     help="birdcage-track (default: $BIRDCAGE_TRACK, else the one on PATH)")
    sky.add_argument("--align-program", default=os.environ.get("BIRDCAGE_ALIGN"), metavar="PATH",
                     help="birdcage-align (default: $BIRDCAGE_ALIGN, else the one on PATH)")
    sky.add_argument("--lat", type=float, help="the station's latitude, degrees north")
    sky.add_argument("--lon", type=float, help="the station's longitude, degrees east (west negative)")
    sky.add_argument("--alt", type=float, help="the station's altitude, metres")
    sky.add_argument("--tle", action="append", default=[], metavar="FILE|DIR",
                     help="TLEs to read (repeatable; default: Gpredict's, as birdcage-track finds them)")
    sky.add_argument("--at", metavar="ISO-TIME",
                     help="rehearsal: the sky's clock starts at this time (UTC) when the server starts")
    sky.add_argument("--time-scale", type=float, metavar="K",
                     help="rehearsal: the sky's clock runs K times faster (as the emulator's and rotctld's "
                          "-C time_scale)")
    parser.add_argument("--version", action="version", version=f"birdcage-mcp {__version__}")
    args = parser.parse_args(argv)
    try:
        at = parse_time(args.at) if args.at else None
    except ValueError:
        parser.error(f"--at {args.at!r} is not an ISO 8601 time (e.g. 2026-12-01T12:00:00Z)")
    if args.time_scale is not None and not args.time_scale > 0:
        parser.error("--time-scale must be above 0")
    options = SkyOptions(track_program=args.track_program, align_program=args.align_program, lat=args.lat,
                         lon=args.lon, alt=args.alt, tles=args.tle, clock=SkyClock(at, args.time_scale))
    server = build_server(args.host, args.port, options)
    try:
        server.run("stdio")
    finally:
        server.sky.close()  # no track outlives the server that answers for it


if __name__ == "__main__":
    main()
