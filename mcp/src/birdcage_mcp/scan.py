# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""Sky-scan helpers: the serpentine grid and the peak finder (the same rules as
tools/skyscan_plot.py, without numpy)."""

from __future__ import annotations

import statistics


def axis(first: float, last: float, step: float) -> list[float]:
    """first, first+step, ... up to last (inclusive within rounding)."""
    values = []
    n = 0
    while True:
        value = round(first + n * step, 6)
        if value > last + 1e-6:
            return values
        values.append(value)
        n += 1


def serpentine(azimuths: list[float], elevations: list[float]) -> list[tuple[float, float]]:
    """Azimuth columns ascending; elevation up in one column and down the next, so the dish never
    swings back across the whole elevation range between columns."""
    points = []
    for column, az in enumerate(azimuths):
        column_els = elevations if column % 2 == 0 else list(reversed(elevations))
        points.extend((az, el) for el in column_els)
    return points


def find_peaks(rows: list[tuple[float, float, float]], radius_deg: float = 4.0, count: int = 10):
    """Strongest local maxima above floor + max(10, 6 robust sigma), one per `radius_deg`
    neighbourhood. Returns (floor, [(value, az, el), ...]) strongest first."""
    if not rows:
        return None, []
    values = [v for _, _, v in rows]
    floor = statistics.median(values)
    spread = statistics.median(abs(v - floor) for v in values) * 1.4826
    threshold = floor + max(10.0, 6.0 * spread)
    candidates = []
    for az, el, v in rows:
        if v < threshold:
            continue
        neighbours = [w for a, e, w in rows if abs(a - az) <= radius_deg and abs(e - el) <= radius_deg]
        if v >= max(neighbours):
            candidates.append((v, az, el))
    candidates.sort(reverse=True)
    kept: list[tuple[float, float, float]] = []
    for peak in candidates:
        if all(abs(peak[1] - q[1]) > radius_deg or abs(peak[2] - q[2]) > radius_deg for q in kept):
            kept.append(peak)
    return floor, kept[:count]
