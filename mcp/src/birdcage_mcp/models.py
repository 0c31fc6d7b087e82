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
