# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""The tools' results as pydantic models: each becomes the tool's output schema, so a client
knows every field's type and meaning before it calls."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, Field


class Position(BaseModel):
    azimuth: float = Field(description="degrees clockwise from north")
    elevation: float = Field(description="degrees above the horizon")


class MoveResult(BaseModel):
    requested: Position
    outcome: Literal["arrived", "clamped", "moving", "interrupted", "stopped_short"] = Field(
        description="arrived: settled at the target; clamped: settled where the backend clamped the target "
        "to (its az_min/az_max conf); moving: wait was false, the dish is on its way; "
        "interrupted: another command (stop, a new move, another rotctld client) took over; "
        "stopped_short: at rest elsewhere with no other command seen (notes say what is known)"
    )
    position: Position = Field(description="where the dish was when the tool answered")
    settled: bool = Field(description="the dish had come to rest (not MOVING) when the tool answered")
    at_target: bool
    clamped: bool = Field(False, description="the backend took another target than the one sent (az_min/az_max)")
    interrupted_by: str | None = Field(None, description="what interrupted the move, when outcome is interrupted")
    seconds: float | None = Field(None, description="from the command to the answer")
    notes: list[str] = []


class StopResult(BaseModel):
    state: Literal["stopped", "stopping"] = Field(
        description="stopped: the dish is at rest; stopping: still moving when the wait ended (a Winegard "
        "finishes the leg under way)"
    )
    position: Position = Field(description="where the dish stopped, or where it was when the wait ended")
    seconds: float = Field(description="from the stop command to the answer")
    leg_end: Position | None = Field(None, description="where the leg under way ends, when still stopping and known")
    split: bool = Field(False, description="the backend had split the move into azimuth legs and the stop ended it "
                        "at the end of the leg under way, short of its target")
    message: str


class ParkResult(BaseModel):
    parking: bool
    position: Position = Field(description="where the dish was when the park command was accepted")


class HomeResult(BaseModel):
    homing: bool
    status: list[str] = Field(description="status flags just after the command (BUSY, MOVING while homing)")


class StatusResult(BaseModel):
    flags: list[str]
    moving: bool
    busy: bool
    position: Position


class InfoResult(BaseModel):
    rotctld: str = Field(description="host:port of the rotctld this server talks to")
    model: int
    manufacturer: str
    model_name: str
    backend_version: str
    info: str = Field(description="the backend's own description (rotctld `_`)")
    levels: list[str]
    winegard_extras: bool = Field(description="the backend offers the Winegard receiver levels (RSSI, LNB)")
    tools: list[str] = Field(description="the tools offered for this rotator")


class LimitsResult(BaseModel):
    model: int
    az_min: float
    az_max: float
    el_min: float
    el_max: float
    source: str
    protocol_el_min: float | None = Field(None, description="the caps' elevation minimum, when the backend's is narrower")
    protocol_el_max: float | None = Field(None, description="the caps' elevation maximum, when the backend's is narrower")
    cable_wrap_mechanical: list[float] | None = Field(None, description="the dish's mechanical azimuth travel")


class SignalResult(BaseModel):
    rssi: float = Field(description="ADC counts")
    samples: int
    position: Position


class LnbResult(BaseModel):
    lnb_volts: float


class ConfResult(BaseModel):
    key: str
    value: str
    source: str


class Peak(BaseModel):
    value: float
    azimuth: float
    elevation: float


class ScanResult(BaseModel):
    points: int
    seconds: float
    csv: str
    floor: float | None
    peaks: list[Peak]
    strongest: Peak
    plot: str


# ---- the sky (birdcage-track / birdcage-align's JSON, docs/sky.md) ----

class Satellite(BaseModel):
    name: str
    norad: int | None = None
    epoch: str | None = Field(None, description="the TLE's epoch (ISO 8601, UTC)")
    source: str | None = Field(None, description="the file the TLE came from")


class SearchResult(BaseModel):
    satellites: list[Satellite]


class Station(BaseModel):
    lat: float = Field(description="degrees north")
    lon: float = Field(description="degrees east (west negative)")
    alt: float | None = Field(None, description="metres above sea level")


class SkyLimits(BaseModel):
    az_min: float | None = None
    az_max: float | None = None
    el_min: float
    el_max: float


class Pass(BaseModel):
    aos: str = Field(description="when the target enters the dish's elevation window (ISO 8601, UTC)")
    tca: str = Field(description="closest approach: the highest point")
    los: str = Field(description="when it leaves the dish's window")
    max_el: float
    aos_az: float
    tca_az: float
    los_az: float
    duration_s: float


class PassesResult(BaseModel):
    target: str
    station: Station
    limits: SkyLimits = Field(description="the dish's window the passes are cut to (rotctld \\dump_state)")
    limits_source: str | None = Field(None, description="'default' when rotctld could not be asked (0..90)")
    passes: list[Pass]


class NextPassResult(BaseModel):
    target: str
    station: Station
    limits: SkyLimits
    next_pass: Pass | None = Field(description="the next pass through the dish's window; None within the hours searched")
    in_progress: bool = Field(description="the target is inside the dish's window now")
    seconds_to_aos: float | None = Field(None, description="from now to the pass's AOS (0 when in progress)")
    message: str


class SkyTarget(BaseModel):
    name: str
    kind: str = Field(description="sun, moon, planet or satellite")
    az: float
    el: float
    in_window: bool = Field(description="inside the dish's elevation window (so it can be tracked now)")


class VisibleResult(BaseModel):
    time: str = Field(description="the instant the positions are for (ISO 8601, UTC)")
    targets: list[SkyTarget]


class TrackPoint(BaseModel):
    target: Position = Field(description="where the target was")
    dish: Position = Field(description="where the dish pointed (rotctld `p`)")
    error_deg: float = Field(description="angle on the sky between the two")
    seconds_to_los: float | None = None
    time: str


class TrackResult(BaseModel):
    target: str
    outcome: Literal["tracking", "waiting", "los", "duration", "interrupted", "unreachable", "error"] = Field(
        description="tracking/waiting: still under way (wait was false); los: followed until it left the dish's "
        "window; duration: followed for the duration asked; interrupted: ended early, interrupted_by says by "
        "what; unreachable: the target never enters the dish's window; error: birdcage-track failed (reason)"
    )
    reason: str = Field(description="birdcage-track's own words on how it ended (or why it has not yet)")
    interrupted_by: str | None = Field(None, description="what ended it early: stop_tracking, stop, a cancelled "
                                                         "call, or a signal from outside this server")
    aos: str | None = Field(None, description="planned entry into the dish's window")
    los: str | None = Field(None, description="planned exit from the dish's window")
    max_el: float | None = None
    rms_error_deg: float | None = Field(None, description="RMS pointing error over the samples (dish against target)")
    max_error_deg: float | None = None
    samples: int = 0
    commands_sent: int = Field(0, description="P commands sent to rotctld")
    parked: bool = False
    last: TrackPoint | None = Field(None, description="the last progress sample")
    seconds: float = Field(description="wall-clock seconds since the track started")


class StopTrackingResult(BaseModel):
    stopped: bool = Field(description="a track was running and has ended")
    track: TrackResult | None = Field(None, description="how the track ended (or the last one, when none was running)")
    position: Position | None = Field(None, description="where the dish was after the stop")
    message: str


class TrackingStatus(BaseModel):
    tracking: bool = Field(description="a track started by this server is running")
    track: TrackResult | None = Field(None, description="the running track so far, or the last one that ended")


class AlignTerms(BaseModel):
    az_index: float
    el_index: float
    tilt_north: float
    tilt_east: float


class AlignSource(BaseModel):
    name: str
    sky_az: float
    sky_el: float
    dish_az: float
    dish_el: float
    residual_deg: float


class AlignResult(AlignTerms):
    sigma: AlignTerms = Field(description="one-sigma uncertainty of each term")
    residual_rms_deg: float
    n_sources: int
    sources: list[AlignSource]
    conf_lines: list[str] = Field(description="the -C options that correct this dish (docs/sky.md); this server "
                                              "writes them nowhere")
    scan_seconds: float | None = None
    plot: str | None = None
    message: str
