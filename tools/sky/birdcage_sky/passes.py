# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Passes through the dish's window: AOS and LOS where the target's elevation crosses the dish's
floor el_min (not the horizon), TCA at the highest elevation, and the stretches above the dish's
cap el_max (where the tracker holds the cap and follows the azimuth)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from .clock import iso
from .geodesy import Station
from .targets import Target


@dataclass
class Pass:
    aos: float | None  # None: already in the window as far back as was searched (e.g. geostationary)
    tca: float | None
    los: float | None  # None: still in the window at the end of the search
    max_el: float
    aos_az: float | None
    tca_az: float | None
    los_az: float | None
    above_max: list[tuple[float, float]] = field(default_factory=list)

    @property
    def duration_s(self) -> float | None:
        return None if self.aos is None or self.los is None else self.los - self.aos

    def as_json(self) -> dict:
        def r(x, n=2):
            return None if x is None else round(float(x), n)
        return {"aos": iso(self.aos), "tca": iso(self.tca), "los": iso(self.los), "max_el": r(self.max_el),
                "aos_az": r(self.aos_az), "tca_az": r(self.tca_az), "los_az": r(self.los_az),
                "duration_s": r(self.duration_s, 1),
                # Extension: where the target is above the dish's cap (the tracker holds el_max there).
                "above_max_s": round(sum(b - a for a, b in self.above_max), 1),
                "above_max": [{"from": iso(a), "to": iso(b)} for a, b in self.above_max]}


def _crossings(target: Target, station: Station, ts: np.ndarray, el: np.ndarray, level: float):
    """Times where el crosses level, refined; each with +1 (rising) or -1 (setting)."""
    f = el - level
    out = []
    ok = ~np.isnan(f)
    for i in np.nonzero(ok[:-1] & ok[1:] & (np.sign(f[:-1]) != np.sign(f[1:])))[0]:
        if f[i] == 0 and i > 0 and np.sign(f[i - 1]) == np.sign(f[i + 1]):
            continue
        a, b = float(ts[i]), float(ts[i + 1])
        try:
            t = brentq(lambda x: target.look_one(station, x)[1] - level, a, b, xtol=0.01)
        except ValueError:
            t = a if f[i] == 0 else b
        out.append((t, 1 if f[i + 1] > f[i] else -1))
    return out


def find_passes(target: Target, station: Station, start: float, end: float, el_min: float, el_max: float,
                lookback: float | None = None, count: int | None = None) -> list[Pass]:
    """Passes that are in the window at some moment of [start, end], in time order. A pass under
    way at start is searched back up to lookback seconds for its AOS."""
    step = target.search_step
    if lookback is None:
        lookback = 7200.0 if step <= 10 else 86400.0
    ts = np.arange(start - lookback, end + step, step)
    az, el = target.look(station, ts)
    events = _crossings(target, station, ts, el, el_min)
    in_window_first = not np.isnan(el[0]) and el[0] >= el_min
    bounds: list[tuple[float | None, float | None]] = []
    pending_rise = None if not in_window_first else "open"
    for t, s in events:
        if s > 0:
            pending_rise = t
        elif pending_rise is not None:
            bounds.append((None if pending_rise == "open" else pending_rise, t))
            pending_rise = None
    if pending_rise is not None:
        bounds.append((None if pending_rise == "open" else pending_rise, None))

    passes = []
    for aos, los in bounds:
        if los is not None and los < start:
            continue
        if aos is not None and aos > end:
            continue
        passes.append(_describe(target, station, ts, el, aos, los, el_max, step))
        if count and len(passes) >= count:
            break
    return passes


def _describe(target, station, ts, el, aos, los, el_max, step) -> Pass:
    lo = aos if aos is not None else ts[0]
    hi = los if los is not None else ts[-1]
    inside = (ts >= lo) & (ts <= hi)
    if inside.any():
        i = int(np.nanargmax(np.where(inside, el, -np.inf)))
        a, b = max(lo, ts[i] - step), min(hi, ts[i] + step)
    else:
        a, b = lo, hi
    if b > a:
        # In seconds from a: the bounded search's tolerance is relative to the argument's size.
        best = minimize_scalar(lambda x: -target.look_one(station, a + x)[1], bounds=(0.0, b - a),
                               method="bounded", options={"xatol": 0.05})
        tca = a + float(best.x)
    else:
        tca = a
    tca_az, max_el = target.look_one(station, tca)
    if aos is None and los is None and abs(max_el - float(np.nanmax(el))) > 1e-6 and np.nanmax(el) > max_el:
        tca = None
    above = []
    if max_el > el_max:
        cross = _crossings(target, station, ts[inside], el[inside], el_max) if inside.sum() > 1 else []
        start_above = None if target.look_one(station, lo)[1] <= el_max else lo
        for t, s in cross:
            if s > 0:
                start_above = t
            elif start_above is not None:
                above.append((start_above, t))
                start_above = None
        if start_above is not None:
            above.append((start_above, hi))
    return Pass(aos=aos, tca=tca, los=los, max_el=max_el,
                aos_az=None if aos is None else target.look_one(station, aos)[0],
                tca_az=None if tca is None else tca_az,
                los_az=None if los is None else target.look_one(station, los)[0],
                above_max=above)


def current_or_next(target: Target, station: Station, now: float, horizon_s: float, el_min: float,
                    el_max: float) -> Pass | None:
    """The pass under way at now, else the next one within horizon_s."""
    passes = find_passes(target, station, now, now + horizon_s, el_min, el_max, count=1)
    return passes[0] if passes else None
