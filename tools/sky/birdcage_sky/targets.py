# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""What a dish can point at, and where it is: satellites from their TLEs through SGP4, the Sun,
the Moon and the planets through PyEphem (topocentric, apparent, pressure 0: no refraction), a
fixed J2000 RA/Dec (`radec:RA,DEC`) and a fixed direction (`azel:AZ,EL`)."""

from __future__ import annotations

import math

import ephem
import numpy as np

from . import tle as tlemod
from .geodesy import Station

PLANETS = ("mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune")
UNIX_TO_JD = 2440587.5
UNIX_TO_DUBLIN = 2440587.5 - 2415020.0  # PyEphem counts days from 1899-12-31 12:00 UT


def gmst_rad(jd_ut1: np.ndarray) -> np.ndarray:
    """Greenwich mean sidereal time (IAU 1982, the angle SGP4's TEME frame is defined against).
    UT1 is taken as UTC: |UT1-UTC| < 0.9 s moves a LEO look angle by at most a few hundredths of
    a degree."""
    tut1 = (jd_ut1 - 2451545.0) / 36525.0
    seconds = (-6.2e-6 * tut1 ** 3 + 0.093104 * tut1 ** 2 + (876600.0 * 3600 + 8640184.812866) * tut1
               + 67310.54841)
    return np.radians(seconds / 240.0) % (2 * math.pi)


class Target:
    kind = "fixed"
    name = ""
    # Seconds between samples when a pass is searched: fine enough not to miss the shortest
    # pass through the dish's window.
    search_step = 60.0

    def look(self, station: Station, t):
        """Azimuth 0..360 and elevation (degrees) at UTC t (a float or an array)."""
        raise NotImplementedError

    def look_one(self, station: Station, t: float) -> tuple[float, float]:
        az, el = self.look(station, np.array([t], dtype=float))
        return float(az[0]), float(el[0])

    def describe(self) -> str:
        return self.name


class Satellite(Target):
    kind = "satellite"
    search_step = 10.0

    def __init__(self, tle: tlemod.Tle):
        self.tle = tle
        self.name = tle.name
        # Far orbits move slowly on the sky: coarser samples lose nothing.
        period_min = 2 * math.pi / tle.satrec.no_kozai
        self.search_step = 10.0 if period_min < 200 else 60.0

    def teme_km(self, t: np.ndarray) -> np.ndarray:
        jd = t / 86400.0 + UNIX_TO_JD
        whole = np.floor(jd)
        err, r, _ = self.tle.satrec.sgp4_array(whole, jd - whole)
        r = np.array(r, dtype=float).T  # (3, N)
        r[:, np.asarray(err) != 0] = np.nan  # decayed or diverged elements
        return r

    def ecef_km(self, t: np.ndarray) -> np.ndarray:
        r = self.teme_km(t)
        g = gmst_rad(t / 86400.0 + UNIX_TO_JD)
        c, s = np.cos(g), np.sin(g)
        # TEME -> pseudo-Earth-fixed: a turn by GMST about the pole (polar motion, < 0.5", left out).
        return np.array([c * r[0] + s * r[1], -s * r[0] + c * r[1], r[2]])

    def look(self, station, t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        az, el, _ = station.look_angles(self.ecef_km(t))
        return az, el

    def describe(self) -> str:
        return f"{self.name} (NORAD {self.tle.norad})"


class EphemBody(Target):
    def __init__(self, name: str, kind: str, body: ephem.Body):
        self.name, self.kind, self.body = name, kind, body
        self.search_step = 120.0 if kind != "moon" else 60.0

    def look(self, station, t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        observer = ephem.Observer()
        observer.lat, observer.lon = math.radians(station.lat), math.radians(station.lon)
        observer.elevation = station.alt
        observer.pressure = 0  # no refraction: geometric, as the dish's axes are
        az = np.empty(t.shape)
        el = np.empty(t.shape)
        for i, ti in enumerate(t):
            observer.date = ti / 86400.0 + UNIX_TO_DUBLIN
            self.body.compute(observer)
            az[i], el[i] = math.degrees(self.body.az), math.degrees(self.body.alt)
        return az % 360.0, el


class FixedAzEl(Target):
    kind = "azel"

    def __init__(self, az: float, el: float):
        self.az, self.el = az % 360.0, el
        self.name = f"azel:{az:g},{el:g}"

    def look(self, station, t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        return np.full(t.shape, self.az), np.full(t.shape, self.el)


def _two_numbers(spec: str, what: str) -> tuple[float, float]:
    try:
        a, b = (float(x) for x in spec.split(","))
    except ValueError:
        raise LookupError(f"{what} needs two numbers in degrees, e.g. {what}:83.63,22.01") from None
    return a, b


def resolve(spec: str, tles_loader) -> Target:
    """A TARGET of the contract: sun, moon, a planet, radec:RA,DEC, azel:AZ,EL, or a satellite by
    name, unique prefix or NORAD number (tles_loader() gives the TLEs, read only when needed).
    Raises LookupError."""
    key = spec.strip().lower()
    if key == "sun":
        return EphemBody("sun", "sun", ephem.Sun())
    if key == "moon":
        return EphemBody("moon", "moon", ephem.Moon())
    if key in PLANETS:
        return EphemBody(key, "planet", getattr(ephem, key.capitalize())())
    if key.startswith("radec:"):
        ra, dec = _two_numbers(spec.split(":", 1)[1], "radec")
        if not -90 <= dec <= 90:
            raise LookupError(f"radec: declination {dec:g} is outside -90..90")
        body = ephem.FixedBody()
        body._ra, body._dec, body._epoch = math.radians(ra % 360.0), math.radians(dec), ephem.J2000
        return EphemBody(f"radec:{ra:g},{dec:g}", "radec", body)
    if key.startswith("azel:"):
        az, el = _two_numbers(spec.split(":", 1)[1], "azel")
        if not -90 <= el <= 90:
            raise LookupError(f"azel: elevation {el:g} is outside -90..90")
        return FixedAzEl(az, el)
    return Satellite(tlemod.find(tles_loader(), spec))


def no_satellites() -> list:
    return []


def solar_system() -> list[Target]:
    return [resolve(name, no_satellites) for name in ("sun", "moon", *PLANETS)]


GEO_RADIUS_KM = 42164.17


def geostationary_look(station: Station, longitude_deg):
    """Look angles of geostationary slots (degrees east) from the station: a satellite at rest on
    the equator at the geostationary radius (its station-keeping box, ~0.1 degrees, left out)."""
    lon = np.radians(np.atleast_1d(np.asarray(longitude_deg, dtype=float)))
    ecef = GEO_RADIUS_KM * np.array([np.cos(lon), np.sin(lon), np.zeros_like(lon)])
    az, el, _ = station.look_angles(ecef)
    return az, el
