# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Catalogues of fixed sources at a site: the geostationary table (tools/sky/data/geostationary.csv,
docs/sky.md section 2) or TLEs of geostationary satellites, turned into look angles; and the
`name,az,el` catalogues of look angles already taken at a site (no header, CRLF, as Gpredict
exports them: sim/data/g2-ku-skyscan/satellite_data.csv)."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .geodesy import Station, angular_distance

DATA_DIR = Path(__file__).resolve().parent.parent / "data"
GEOSTATIONARY_CSV = DATA_DIR / "geostationary.csv"


@dataclass
class Source:
    """A direction on the sky; co-located satellites (within a beam's fraction) are one source."""
    name: str
    az: float
    el: float
    members: list[str] = field(default_factory=list)
    longitude: float | None = None


def read_longitudes(path: Path = GEOSTATIONARY_CSV) -> list[tuple[str, float]]:
    rows = []
    with open(path, newline="") as f:
        for row in csv.reader(line for line in f if not line.lstrip().startswith("#")):
            if len(row) >= 2:
                try:
                    rows.append((row[0].strip(), float(row[1])))
                except ValueError:
                    continue  # the header
    if not rows:
        raise ValueError(f"{path}: no `name,longitude_deg` rows")
    return rows


def from_longitudes(station: Station, rows: list[tuple[str, float]]) -> list[Source]:
    from .targets import geostationary_look

    az, el = geostationary_look(station, [lon for _, lon in rows])
    return [Source(name, float(a), float(e), [name], lon) for (name, lon), a, e in zip(rows, az, el)]


def from_tles(station: Station, tles, when: float) -> list[Source]:
    """The geostationary ones among the TLEs (about one revolution a day), where they are at `when`."""
    from .targets import Satellite

    out = []
    for t in tles:
        revs_per_day = t.satrec.no_kozai * 1440 / (2 * np.pi)
        if abs(revs_per_day - 1.0027) > 0.02 or t.satrec.ecco > 0.01:
            continue
        az, el = Satellite(t).look_one(station, when)
        if not np.isnan(el):
            out.append(Source(t.name, az, el, [t.name]))
    return out


def read_look_angles(path: Path) -> list[Source]:
    """`name,az,el` rows (no header; CRLF or LF)."""
    out = []
    with open(path, newline="") as f:
        for row in csv.reader(f):
            if len(row) >= 3:
                try:
                    out.append(Source(row[0].strip(), float(row[1]), float(row[2]), [row[0].strip()]))
                except ValueError:
                    continue
    if not out:
        raise ValueError(f"{path}: no `name,az,el` rows")
    return out


def cluster(sources: list[Source], radius_deg: float = 1.0) -> list[Source]:
    """Sources closer than radius_deg merge into one at their mean direction: a dish whose beam is
    several degrees wide cannot tell them apart, and fitting them apart would only trade
    amplitudes between them."""
    groups: list[list[Source]] = []
    for s in sorted(sources, key=lambda s: s.az):
        for g in groups:
            if any(angular_distance(s.az, s.el, o.az, o.el) < radius_deg for o in g):
                g.append(s)
                break
        else:
            groups.append([s])
    out = []
    for g in groups:
        az = float(np.degrees(np.angle(np.mean(np.exp(1j * np.radians([s.az for s in g]))))) % 360.0)
        el = float(np.mean([s.el for s in g]))
        names = [m for s in g for m in s.members]
        out.append(Source(" + ".join(names), az, el, names))
    return out
