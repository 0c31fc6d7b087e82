# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The station on the WGS84 ellipsoid and topocentric look angles (geometric: no refraction)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WGS84_A_KM = 6378.137
WGS84_F = 1 / 298.257223563
WGS84_E2 = WGS84_F * (2 - WGS84_F)


@dataclass(frozen=True)
class Station:
    lat: float  # geodetic latitude, degrees north
    lon: float  # longitude, degrees east
    alt: float = 0.0  # metres above the ellipsoid

    def as_json(self) -> dict:
        return {"lat": self.lat, "lon": self.lon, "alt": self.alt}

    def ecef_km(self) -> np.ndarray:
        phi, lam = math.radians(self.lat), math.radians(self.lon)
        h = self.alt / 1000.0
        n = WGS84_A_KM / math.sqrt(1 - WGS84_E2 * math.sin(phi) ** 2)
        return np.array([(n + h) * math.cos(phi) * math.cos(lam),
                         (n + h) * math.cos(phi) * math.sin(lam),
                         (n * (1 - WGS84_E2) + h) * math.sin(phi)])

    def enu_matrix(self) -> np.ndarray:
        """Rows: the east, north and up unit vectors in Earth-fixed coordinates."""
        phi, lam = math.radians(self.lat), math.radians(self.lon)
        sp, cp, sl, cl = math.sin(phi), math.cos(phi), math.sin(lam), math.cos(lam)
        return np.array([[-sl, cl, 0.0], [-sp * cl, -sp * sl, cp], [cp * cl, cp * sl, sp]])

    def look_angles(self, ecef_km: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Azimuth (0..360), elevation (degrees) and range (km) of Earth-fixed positions
        (shape (3,) or (3, N))."""
        d = ecef_km - (self.ecef_km()[:, None] if ecef_km.ndim == 2 else self.ecef_km())
        e, n, u = self.enu_matrix() @ d
        rng = np.sqrt(e * e + n * n + u * u)
        az = np.degrees(np.arctan2(e, n)) % 360.0
        el = np.degrees(np.arcsin(np.clip(u / rng, -1, 1)))
        return az, el, rng


def angular_distance(az1, el1, az2, el2):
    """Great-circle angle between directions, degrees (arrays broadcast)."""
    az1, el1, az2, el2 = (np.radians(x) for x in (az1, el1, az2, el2))
    s = np.sin((el2 - el1) / 2) ** 2 + np.cos(el1) * np.cos(el2) * np.sin((az2 - az1) / 2) ** 2
    return np.degrees(2 * np.arcsin(np.sqrt(np.clip(s, 0, 1))))


def unwrap_near(az: float, reference: float) -> float:
    """az moved by whole turns to lie within 180 degrees of reference."""
    return reference + ((az - reference + 180.0) % 360.0) - 180.0
