# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The mount model of docs/sky.md section 1: how a dish's axes sit against the sky (four terms,
degrees). The backend (`-C az_index=...`) and the emulator (`--mount`) implement the same map."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

TERMS = ("az_index", "el_index", "tilt_north", "tilt_east")


@dataclass(frozen=True)
class Mount:
    az_index: float = 0.0
    el_index: float = 0.0
    tilt_north: float = 0.0
    tilt_east: float = 0.0

    @classmethod
    def parse(cls, text: str) -> "Mount":
        """az_index=6,el_index=0.8,... (any subset; the emulator's --mount syntax)."""
        values = {}
        for item in filter(None, (p.strip() for p in text.split(","))):
            key, sep, value = item.partition("=")
            if not sep or key.strip() not in TERMS:
                raise ValueError(f"mount term {item!r}: expected one of {', '.join(TERMS)} as key=degrees")
            values[key.strip()] = float(value)
        return cls(**values)

    def as_tuple(self) -> tuple[float, float, float, float]:
        return (self.az_index, self.el_index, self.tilt_north, self.tilt_east)

    def dish_to_sky(self, az, el):
        return dish_to_sky(self.as_tuple(), az, el)

    def sky_to_dish(self, az, el):
        return sky_to_dish(self.as_tuple(), az, el)


def _vector(az, el):
    a, e = np.radians(az), np.radians(el)
    return np.cos(e) * np.sin(a), np.cos(e) * np.cos(a), np.sin(e)


def _turn_up_north(x, y, z, t):
    """R_E(t): turns up toward north."""
    c, s = np.cos(t), np.sin(t)
    return x, y * c + z * s, -y * s + z * c


def _turn_up_east(x, y, z, t):
    """R_N(t): turns up toward east."""
    c, s = np.cos(t), np.sin(t)
    return x * c + z * s, y, -x * s + z * c


def _angles(x, y, z, az_given):
    az = np.degrees(np.arctan2(x, y))
    el = np.degrees(np.arcsin(np.clip(z, -1.0, 1.0)))
    # At the zenith the azimuth is undefined: keep the one given.
    az = np.where(np.hypot(x, y) < 1e-12, az_given, az)
    return az, el


def _same_branch(az, az_reference):
    """az (any turn) moved by whole turns to lie within 180 degrees of az_reference, so a mapped
    azimuth stays on the cable-wrap branch it came from."""
    return az_reference + ((az - az_reference + 180.0) % 360.0) - 180.0


def dish_to_sky(terms, az_d, el_d):
    az_index, el_index, tilt_north, tilt_east = terms
    a = np.asarray(az_d, dtype=float) + az_index
    e = np.asarray(el_d, dtype=float) + el_index
    x, y, z = _vector(a, e)
    x, y, z = _turn_up_east(x, y, z, np.radians(tilt_east))
    x, y, z = _turn_up_north(x, y, z, np.radians(tilt_north))
    az, el = _angles(x, y, z, a)
    az = _same_branch(az, a)
    return _scalar(az, az_d), _scalar(el, el_d)


def sky_to_dish(terms, az_s, el_s):
    az_index, el_index, tilt_north, tilt_east = terms
    a = np.asarray(az_s, dtype=float)
    x, y, z = _vector(a, np.asarray(el_s, dtype=float))
    x, y, z = _turn_up_north(x, y, z, -np.radians(tilt_north))
    x, y, z = _turn_up_east(x, y, z, -np.radians(tilt_east))
    az, el = _angles(x, y, z, a)
    az = _same_branch(az, a) - az_index
    return _scalar(az, az_s), _scalar(el - el_index, el_s)


def _scalar(value, like):
    return float(value) if np.ndim(like) == 0 else value
