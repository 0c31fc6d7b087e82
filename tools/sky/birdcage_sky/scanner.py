# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Scanning the sky through rotctld for birdcage-align: the band around the geostationary arc in
the dish's axes, and the Sun's cross-scans. Each point: `P`, wait until two successive `p` agree
with it, `v RSSI` (the birdcage backend's extension level, docs/receiver.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .clock import Clock
from .geodesy import Station
from .rotctld import Limits, Rotctld, RotctldError
from .scanio import Scan

SETTLE_TOLERANCE_DEG = 0.06
SETTLE_TIMEOUT_S = 60.0  # of the clock: the longest slew of a Trav'ler is ~16 s


class ScanError(Exception):
    pass


@dataclass
class Band:
    points: list[tuple[float, float]]  # dish axes, in the order they are visited
    az_range: tuple[float, float]
    columns: int


def arc_curve(station: Station) -> tuple[np.ndarray, np.ndarray]:
    """The geostationary arc's look angles from the station (every half degree of longitude above
    the horizon), azimuths unwrapped about the meridian the arc culminates on."""
    from .targets import geostationary_look

    lons = station.lon + np.arange(-85.0, 85.01, 0.5)
    az, el = geostationary_look(station, lons)
    keep = el > 0
    centre = 180.0 if station.lat >= 0 else 0.0
    az = centre + ((az[keep] - centre + 180.0) % 360.0) - 180.0
    order = np.argsort(az)
    return az[order], el[keep][order]


def plan_band(station: Station, limits: Limits, sources_az: list[float], az_error: float, el_error: float,
              step: float, margin: float) -> Band:
    """A serpentine over the arc in dish axes: columns of azimuth, each spanning the elevations
    the arc takes within az_error of it, widened by el_error and a beam (margin) on either side;
    up one column, down the next."""
    arc_az, arc_el = arc_curve(station)
    centre = 180.0 if station.lat >= 0 else 0.0
    src = np.array([centre + ((a - centre + 180.0) % 360.0) - 180.0 for a in sources_az])
    if len(src) == 0:
        raise ScanError("no catalogue satellite is above the dish's floor from this station")
    lo, hi = src.min() - az_error - margin, src.max() + az_error + margin
    points, columns = [], 0
    for az in np.arange(lo, hi + 1e-9, step):
        window = (arc_az >= az - az_error - margin) & (arc_az <= az + az_error + margin)
        if not window.any():
            continue
        e_lo = max(limits.el_min, arc_el[window].min() - el_error - margin)
        e_hi = min(limits.el_max, arc_el[window].max() + el_error + margin)
        if e_hi < e_lo:
            continue
        els = list(np.arange(e_lo, e_hi + 1e-9, step))
        if columns % 2:
            els.reverse()
        points += [(float(az % 360.0), float(e)) for e in els]
        columns += 1
    return Band(points, (float(lo % 360.0), float(hi % 360.0)), columns)


class Scanner:
    def __init__(self, rot: Rotctld, clock: Clock, progress=None):
        self.rot, self.clock, self.progress = rot, clock, progress
        self.stop_requested = False

    def check_rssi(self) -> None:
        try:
            names = " ".join(self.rot.ask("v", "?")).split()
        except RotctldError as error:
            raise ScanError(f"rotctld lists no levels ({error})") from None
        if "RSSI" not in names:
            raise ScanError("the rotator behind rotctld reports no RSSI level (the birdcage backend's G2 does; "
                            "docs/receiver.md); birdcage-align needs a signal to align on")
        try:
            self.rot.level("RSSI")
        except RotctldError as error:
            raise ScanError(f"`v RSSI` failed: {error} (Trav'lers and the 2003 Carryout have no tuner to read)") from None

    def settle(self, az: float, el: float) -> tuple[float, float]:
        """Waits until two successive readings agree with the target; the reading."""
        deadline = self.clock.now() + SETTLE_TIMEOUT_S
        previous = None
        while True:
            if self.stop_requested:
                raise KeyboardInterrupt
            p = self.rot.position()
            close = abs(((p[0] - az + 180) % 360) - 180) <= SETTLE_TOLERANCE_DEG and abs(p[1] - el) <= SETTLE_TOLERANCE_DEG
            if close and previous is not None and previous == p:
                return p
            if self.clock.now() > deadline:
                if previous == p:
                    raise ScanError(f"the dish rests at az {p[0]:.2f} el {p[1]:.2f}, not at the point sent "
                                    f"({az:.2f}, {el:.2f}): a backend with predictive pointing takes a scan's "
                                    f"steps for a satellite; run rotctld with -C pointing=none")
                raise ScanError(f"the dish did not reach az {az:.2f} el {el:.2f} within {SETTLE_TIMEOUT_S:g} s")
            previous = p
            self.clock.sleep(0.05)

    def read_point(self, az: float, el: float) -> tuple[float, float, float, float]:
        self.rot.move(az, el)
        p = self.settle(az, el)
        value = self.rot.level("RSSI")
        return p[0], p[1], value, self.clock.now()

    def scan(self, points: list[tuple[float, float]], phase: str = "scan") -> Scan:
        rows = []
        for i, (az, el) in enumerate(points):
            rows.append(self.read_point(az, el))
            if self.progress:
                self.progress(i + 1, len(points), phase)
        a = np.array(rows)
        return Scan(a[:, 0], a[:, 1], a[:, 2], a[:, 3])


@dataclass
class SunFix:
    time: float
    sky_az: float
    sky_el: float
    dish_az: float
    dish_el: float
    peak: float
    readings: int
    scan: Scan | None = None  # every reading taken for it, in the dish's axes


def gaussian_peak(x: np.ndarray, y: np.ndarray) -> float:
    """Where a Gaussian on a floor peaks along one line of readings."""
    from scipy.optimize import curve_fit

    i = int(np.argmax(y))
    p0 = [y[i] - np.median(y), x[i], 2.5, np.median(y)]
    try:
        popt, _ = curve_fit(lambda t, a, m, s, c: a * np.exp(-0.5 * ((t - m) / s) ** 2) + c, x, y, p0=p0,
                            maxfev=4000)
    except RuntimeError:
        return float(x[i])
    return float(popt[1]) if x.min() <= popt[1] <= x.max() else float(x[i])


# A source in a raster must stand this many times the readings' own noise above the floor.
DETECTION_SIGMAS = 6.0


def raster_source(x: np.ndarray, y: np.ndarray, value: np.ndarray, beam_sigma: float = 2.9) -> tuple[float, float] | None:
    """Where one beam-wide source sits in a raster of readings at sky offsets (x, y), or None if
    the raster shows none: a floor plus a Gaussian of the beam's width (its centre, amplitude and
    width fitted) against the floor alone. The noise is the fit's residual scatter, not the
    readings' spread: a beam as wide as the raster lights most of it, and the spread of the
    readings is then the source itself (a median-and-MAD test missed the Sun 3-5 deg from the
    raster's centre for that reason)."""
    from scipy.optimize import least_squares

    i = int(np.argmax(value))
    floor0 = float(np.percentile(value, 10))

    def model(p):
        a, mx, my, s, c = p
        return c + a * np.exp(-((x - mx) ** 2 + (y - my) ** 2) / (2.0 * s * s))

    p0 = [float(value[i]) - floor0, float(x[i]), float(y[i]), beam_sigma, floor0]
    span = max(float(np.ptp(x)), float(np.ptp(y)), 1.0)
    lower = [0.0, float(x.min()) - span, float(y.min()) - span, 0.5 * beam_sigma, -np.inf]
    upper = [np.inf, float(x.max()) + span, float(y.max()) + span, 2.0 * beam_sigma, np.inf]
    fit = least_squares(lambda p: model(p) - value, p0, bounds=(lower, upper))
    amplitude, mx, my = fit.x[0], fit.x[1], fit.x[2]
    residual = fit.fun
    dof = max(len(value) - len(p0), 1)
    noise = max(float(np.sqrt(residual @ residual / dof)), 1.0)
    # The centre inside the raster: a source beyond its edge is a slope whose centre no raster point tells.
    inside = x.min() <= mx <= x.max() and y.min() <= my <= y.max()
    if amplitude < DETECTION_SIGMAS * noise or not inside:
        return None
    return float(mx), float(my)


def sun_fix(scanner: Scanner, station: Station, limits: Limits, az_error: float, el_error: float,
            step: float = 2.0, cross_half: float = 8.0, cross_step: float = 1.0) -> SunFix:
    """One measurement of where the dish's axes put the Sun: a raster in offsets from the Sun's
    predicted position (the offsets follow the Sun as it moves), then an azimuth and an elevation
    cross-scan through the raster's peak. The offset at the peak is the mount's error there."""
    from .targets import no_satellites, resolve

    sun = resolve("sun", no_satellites)
    clock = scanner.clock

    def offset_point(daz: float, dael: float):
        t = clock.now()
        saz, sel = sun.look_one(station, t)
        el = min(max(sel + dael, limits.el_min), limits.el_max)
        return saz, sel, saz + daz / max(math.cos(math.radians(sel)), 0.2), el

    taken = []

    def read(daz, dael):
        saz, sel, az, el = offset_point(daz, dael)
        paz, pel, value, t = scanner.read_point(az % 360.0, el)
        taken.append((paz, pel, value, t))
        saz, sel = sun.look_one(station, t)
        cos_el = max(math.cos(math.radians(sel)), 0.2)
        return ((((paz - saz + 180) % 360) - 180) * cos_el, pel - sel, value, t, saz, sel)

    raster = [(a, e) for i, a in enumerate(np.arange(-az_error, az_error + 1e-9, step))
              for e in (np.arange(-el_error, el_error + 1e-9, step)[::(-1 if i % 2 else 1)])]
    rows = []
    for k, (a, e) in enumerate(raster):
        rows.append(read(a, e))
        if scanner.progress:
            scanner.progress(k + 1, len(raster), "sun raster")
    r = np.array(rows)
    found = raster_source(r[:, 0], r[:, 1], r[:, 2])
    if found is None:
        raise ScanError("no Sun in the raster: is the Sun above the dish's floor, and does this receiver see it?")
    pa, pe = found
    offsets = np.arange(-cross_half, cross_half + 1e-9, cross_step)
    az_line = [read(pa + o, pe) for o in offsets]
    el_line = [read(pa, pe + o) for o in offsets]
    az_line, el_line = np.array(az_line), np.array(el_line)
    daz = gaussian_peak(az_line[:, 0], az_line[:, 2])
    dael = gaussian_peak(el_line[:, 1], el_line[:, 2])
    t = float(el_line[len(offsets) // 2, 3])
    saz, sel = sun.look_one(station, t)
    cos_el = max(math.cos(math.radians(sel)), 0.2)
    a = np.array(taken)
    return SunFix(t, saz, sel, (saz + daz / cos_el) % 360.0, sel + dael,
                  float(max(az_line[:, 2].max(), el_line[:, 2].max())), len(taken),
                  Scan(a[:, 0], a[:, 1], a[:, 2], a[:, 3]))


def fit_fixes(fixes: list[SunFix], fit_tilts: bool) -> tuple[np.ndarray, np.ndarray, list[float]]:
    """The mount terms from pairs (sky, dish): least squares of the sky distance between each
    fix's sky position and where the mount sends its dish axes."""
    from scipy.optimize import least_squares

    from .mount import dish_to_sky

    free = [0, 1] + ([2, 3] if fit_tilts else [])
    daz = np.array([f.dish_az for f in fixes])
    dael = np.array([f.dish_el for f in fixes])
    sky = np.array([[f.sky_az, f.sky_el] for f in fixes])

    def resid(x):
        terms = np.zeros(4)
        terms[free] = x
        a, e = dish_to_sky(tuple(terms), daz, dael)
        dx = (((a - sky[:, 0] + 180) % 360) - 180) * np.cos(np.radians(sky[:, 1]))
        return np.r_[dx, e - sky[:, 1]]

    sol = least_squares(resid, np.zeros(len(free)))
    terms = np.zeros(4)
    terms[free] = sol.x
    dof = max(len(sol.fun) - len(free), 1)
    sigma = np.zeros(4)
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * max(sol.fun @ sol.fun / dof, 0.05 ** 2)
        sigma[free] = np.sqrt(np.diag(cov))
    except np.linalg.LinAlgError:
        sigma[free] = np.nan
    r = resid(sol.x).reshape(2, -1)
    return terms, sigma, list(np.hypot(r[0], r[1]))
