# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""What birdcage-track and birdcage-align share on the command line: the project's conventions
(tests/cli: `Usage:` on stdout for --help, `PROGRAM VERSION` for --version, a usage error as one
stderr line `PROGRAM: ...` with exit 2), the station, the TLE sources and the clock."""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path

from .clock import Clock, parse_iso


class UsageError(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def __init__(self, *args, version: str = "", **kwargs):
        super().__init__(*args, add_help=False, formatter_class=lambda prog: argparse.RawDescriptionHelpFormatter(
            prog, max_help_position=34, width=100), **kwargs)
        self.add_argument("--help", action="help", help="this text")
        self.add_argument("--version", action="version", version=f"{self.prog} {version}",
                          help="the program's version")

    def format_help(self) -> str:
        text = super().format_help()
        return "Usage: " + text[len("usage: "):] if text.startswith("usage: ") else text

    def error(self, message: str):
        print(f"{self.prog}: {message}", file=sys.stderr)
        sys.exit(2)


def add_common(parser: argparse.ArgumentParser) -> None:
    g = parser.add_argument_group("rotctld and station")
    g.add_argument("--host", default="localhost", help="rotctld's host (default localhost)")
    g.add_argument("--port", type=int, default=4533, help="rotctld's port (default 4533)")
    g.add_argument("--lat", type=float, help="station latitude, degrees north (or env BIRDCAGE_LAT)")
    g.add_argument("--lon", type=float, help="station longitude, degrees east (or env BIRDCAGE_LON)")
    g.add_argument("--alt", type=float, help="station height above the WGS84 ellipsoid, metres (or env BIRDCAGE_ALT; default 0)")
    g = parser.add_argument_group("satellites and time")
    g.add_argument("--tle", action="append", default=[], metavar="PATH",
                   help="TLEs: a CelesTrak-style file, Gpredict .sat files or satellites.dat, or a directory of them "
                        "(repeatable; default: ~/.config/Gpredict/satdata/*.sat, the --fetch cache, "
                        "/usr/share/gpredict/data/satdata/satellites.dat)")
    g.add_argument("--fetch", action="append", default=[], metavar="GROUP",
                   help="download this CelesTrak group (e.g. amateur, weather) into ~/.cache/birdcage/tle/ first "
                        "(the only network access; never without this option)")
    g.add_argument("--at", metavar="ISO", help="run the clock from this UTC time instead of now (a replay)")
    g.add_argument("--time-scale", type=float, default=1.0, metavar="K",
                   help="the clock runs K times faster than real time (with an emulator at --time-scale K)")
    g.add_argument("--at-wall", type=float, metavar="UNIX",
                   help="the wall-clock time (Unix seconds) at which the clock reads --at (default: this program's "
                        "start); lets programs started at different moments share one clock")
    g.add_argument("--json", action="store_true", help="machine-readable output (docs/sky.md)")


def station_from(args, required: bool = True):
    from .geodesy import Station

    def pick(value, variable):
        if value is not None:
            return value
        text = os.environ.get(variable)
        if text:
            try:
                return float(text)
            except ValueError:
                raise UsageError(f"{variable}={text!r} is not a number") from None
        return None

    lat, lon = pick(args.lat, "BIRDCAGE_LAT"), pick(args.lon, "BIRDCAGE_LON")
    alt = pick(args.alt, "BIRDCAGE_ALT") or 0.0
    if lat is None or lon is None:
        if required:
            raise UsageError("--lat and --lon are required (or BIRDCAGE_LAT and BIRDCAGE_LON)")
        return None
    if not -90 <= lat <= 90:
        raise UsageError(f"--lat {lat:g} is outside -90..90")
    return Station(lat, ((lon + 180.0) % 360.0) - 180.0, alt)


def clock_from(args, started_wall: float | None) -> Clock:
    if args.time_scale <= 0:
        raise UsageError("--time-scale must be positive")
    at = None
    if args.at:
        try:
            at = parse_iso(args.at)
        except ValueError as error:
            raise UsageError(f"--at: {error}") from None
    origin = args.at_wall if args.at_wall is not None else started_wall
    return Clock(at, args.time_scale, origin)


def tle_loader(args):
    """A function that reads the TLEs once, when a satellite is first needed."""
    cache: list = []

    def load():
        from . import tle as tlemod

        if not cache:
            paths = [Path(p) for p in args.tle]
            for group in args.fetch:
                paths.append(tlemod.fetch(group))
            if not args.tle:
                paths = tlemod.default_sources() + [p for p in paths if p not in tlemod.default_sources()]
            cache.append(tlemod.load(paths))
        return cache[0]

    return load


def print_json(obj) -> None:
    print(json.dumps(obj), flush=True)
