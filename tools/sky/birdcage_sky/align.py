# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The mount terms of docs/sky.md section 1 from a scan of known sources (docs/sky.md section 3).

A forward model of the scan: each reading is the floor (a quadratic in elevation: the ground
spills into a low beam) plus, for every source, a Gaussian beam of the distance between the
source and where the mount sends the beam at that reading's dish axes. The four mount terms and
the beam's width are fitted to every reading at once (scipy's least_squares); the floor and the
sources' amplitudes (non-negative) are solved linearly inside each step (variable projection),
so neighbours whose beams overlap share the signal instead of pulling one peak between them.
A coarse search over the index terms first finds where the catalogue pattern sits in the scan.
Each source's own position is then fitted alone, the others' beams subtracted, and its distance
from where the fitted mount puts it is the per-source residual.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares, lsq_linear
from scipy.spatial import cKDTree

from .geo import Source
from .mount import TERMS, dish_to_sky, sky_to_dish
from .scanio import Scan

BEAM_SIGMA_DEG = 2.9  # a 12-inch dish at Ku band: ~7 deg between half-power points (docs/receiver.md)
FLOOR_REFERENCE_EL = 35.0


def unit(az, el):
    a, e = np.radians(az), np.radians(el)
    return np.stack([np.cos(e) * np.sin(a), np.cos(e) * np.cos(a), np.sin(e)], axis=-1)


def separation(u, v):
    """Angles (degrees) between unit vectors u (N,3) and v (K,3): (N,K)."""
    d = np.linalg.norm(u[:, None, :] - v[None, :, :], axis=-1)
    return np.degrees(2 * np.arcsin(np.clip(d / 2, 0, 1)))


@dataclass
class Params:
    terms: np.ndarray  # az_index, el_index, tilt_north, tilt_east
    sigma: float = BEAM_SIGMA_DEG
    lag: float = 0.0  # share of the previous step a reading was taken behind its label


@dataclass
class SourceFit:
    source: Source
    amplitude: float
    dish_az: float | None = None
    dish_el: float | None = None
    sky_az: float | None = None  # where the fitted mount puts the measured peak
    sky_el: float | None = None
    residual: float | None = None
    uncertainty: float | None = None


@dataclass
class Result:
    terms: np.ndarray
    sigma_terms: np.ndarray
    beam_sigma: float
    lag: float
    floor: np.ndarray
    sources: list[SourceFit]
    rms_residual_deg: float | None
    noise: float
    fitted: list[str]
    model: np.ndarray = field(repr=False, default=None)

    def as_dict(self) -> dict:
        return {name: float(v) for name, v in zip(TERMS, self.terms)}


class BeamModel:
    """moving: sources that move during the scan (the Sun), each as (name, azimuths, elevations)
    on the sky at every reading's time; they take part in the fit and are not measured."""

    def __init__(self, scan: Scan, sources: list[Source], fit_lag: bool = False, moving=()):
        self.scan = scan
        self.sources = sources
        self.fit_lag = fit_lag
        self.source_units = unit(np.array([s.az for s in sources]), np.array([s.el for s in sources]))
        self.moving = [(name, unit(np.asarray(az), np.asarray(el))) for name, az, el in moving]
        self.prev = scan.previous_in_column()
        dz = scan.el - FLOOR_REFERENCE_EL
        self.floor_columns = np.stack([np.ones_like(dz), dz / 10, (dz / 10) ** 2], axis=1)
        self.last_coef = None

    def sample_axes(self, lag: float, idx=slice(None)):
        az, el = self.scan.az, self.scan.el
        if lag:
            p = self.prev
            az = az - lag * (az - az[p])
            el = el - lag * (el - el[p])
        return az[idx], el[idx]

    def beams(self, terms, lag, idx=slice(None)):
        az, el = self.sample_axes(lag, idx)
        sa, se = dish_to_sky(tuple(terms), az, el)
        return unit(sa, se)

    def design(self, terms, sigma, lag, idx=slice(None)):
        beams = self.beams(terms, lag, idx)
        d = separation(beams, self.source_units)
        columns = [self.floor_columns[idx], np.exp(-0.5 * (d / sigma) ** 2)]
        for _, units in self.moving:
            dm = np.degrees(2 * np.arcsin(np.clip(np.linalg.norm(beams - units[idx], axis=-1) / 2, 0, 1)))
            columns.append(np.exp(-0.5 * (dm / sigma) ** 2)[:, None])
        return np.hstack(columns)

    def solve(self, terms, sigma, lag, idx=slice(None)):
        a = self.design(terms, sigma, lag, idx)
        y = self.scan.value[idx]
        live = a.max(axis=0) > 1e-3  # sources far outside the scan: no column
        live[:3] = True
        lower = np.r_[[-np.inf] * 3, np.zeros(a.shape[1] - 3)][live]
        res = lsq_linear(a[:, live], y, bounds=(lower, np.inf), method="bvls")
        coef = np.zeros(a.shape[1])
        coef[live] = res.x
        return coef, a

    def residual(self, terms, sigma, lag, idx=slice(None)):
        coef, a = self.solve(terms, sigma, lag, idx)
        self.last_coef = coef
        return self.scan.value[idx] - a @ coef


def coarse_search(model: BeamModel, az_span: float = 20.0, el_span: float = 6.0):
    """The index offsets at which the catalogue's pattern explains the scan best (tilts 0): a
    2-degree grid over the spans, then a half-degree one around its best point."""
    idx = np.arange(0, len(model.scan), 3)

    def cost(daz, dael):
        r = model.residual(np.array([daz, dael, 0.0, 0.0]), BEAM_SIGMA_DEG, 0.0, idx)
        return float(r @ r)

    best = min((cost(a, e), a, e) for a in np.arange(-az_span, az_span + 1e-9, 2.0)
               for e in np.arange(-el_span, el_span + 1e-9, 2.0))
    _, a0, e0 = best
    best = min((cost(a, e), a, e) for a in np.arange(a0 - 1.5, a0 + 1.6, 0.5) for e in np.arange(e0 - 1.5, e0 + 1.6, 0.5))
    return best[1], best[2]


def fit(scan: Scan, sources: list[Source], *, fit_tilts: bool = True, fit_lag: bool | None = None,
        search: bool = True, start: np.ndarray | None = None, progress=None, moving=()) -> Result:
    if fit_lag is None:
        fit_lag = scan.columns_alternate()
    model = BeamModel(scan, sources, fit_lag, moving)
    if start is None:
        start = np.zeros(4)
        if search:
            if progress:
                progress("search")
            daz, dael = coarse_search(model)
            start = np.array([daz, dael, 0.0, 0.0])
    free = [0, 1] + ([2, 3] if fit_tilts else [])
    fitted = [TERMS[i] for i in free] + ["beam_sigma"] + (["lag"] if fit_lag else [])

    def unpack(x):
        terms = start.copy()
        terms[free] = x[:len(free)]
        sigma = x[len(free)]
        lag = x[len(free) + 1] if fit_lag else 0.0
        return terms, sigma, lag

    x0 = np.r_[start[free], BEAM_SIGMA_DEG, [0.0] if fit_lag else []]
    lower = np.r_[[-45.0] * len(free), 1.0, [-0.5] if fit_lag else []]
    upper = np.r_[[45.0] * len(free), 8.0, [1.5] if fit_lag else []]
    lower[0], upper[0] = -360.0, 360.0
    if progress:
        progress("fit")
    sol = least_squares(lambda x: model.residual(*unpack(x)), x0, bounds=(lower, upper), x_scale=0.5,
                        diff_step=1e-4)
    terms, sigma, lag = unpack(sol.x)
    r = model.residual(terms, sigma, lag)
    coef = model.last_coef.copy()
    n, p = len(r), len(sol.x) + int(np.count_nonzero(coef))
    chi2 = float(r @ r) / max(n - p, 1)
    noise = float(1.4826 * np.median(np.abs(r - np.median(r))))
    # Neighbouring readings share the beam, and a model that misses the beam's shape misses it
    # alike at each of them: the formal errors, which count every reading as independent, are
    # widened by the readings per beam area as far as neighbouring residuals are correlated
    # (white noise: not at all; a smooth misfit: by the square root of the readings per beam).
    per_beam = readings_per_beam(scan, sigma)
    same_column = model.prev[1:] == np.arange(len(r) - 1)
    rho = float(np.corrcoef(r[1:][same_column], r[:-1][same_column])[0, 1]) if same_column.sum() > 10 else 0.0
    widen = 1.0 + (per_beam - 1.0) * max(rho, 0.0)
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * chi2 * widen
        spread = np.sqrt(np.clip(np.diag(cov), 0, None))
    except np.linalg.LinAlgError:
        spread = np.full(len(sol.x), np.nan)
    sigma_terms = np.zeros(4)
    sigma_terms[free] = spread[:len(free)]
    source_fits = measure_sources(model, terms, sigma, lag, coef, noise)
    good = [s.residual for s in source_fits if s.residual is not None]
    rms = float(np.sqrt(np.mean(np.square(good)))) if good else None
    return Result(terms=terms, sigma_terms=sigma_terms, beam_sigma=float(sigma), lag=float(lag), floor=coef[:3],
                  sources=source_fits, rms_residual_deg=rms, noise=noise, fitted=fitted,
                  model=model.scan.value - r)


def readings_per_beam(scan: Scan, sigma: float) -> float:
    pts = np.c_[scan.az * np.cos(np.radians(scan.el)), scan.el]
    tree = cKDTree(pts)
    counts = np.array([len(c) for c in tree.query_ball_point(pts[:: max(1, len(pts) // 200)], sigma * 1.177)])
    return float(max(1.0, np.median(counts)))


def groups_of(sources: list[Source], radius_deg: float = 1.0) -> list[list[int]]:
    """Indices of sources within radius_deg of each other (chained): a beam several degrees wide
    sees each group as one peak."""
    groups: list[list[int]] = []
    for k in sorted(range(len(sources)), key=lambda k: sources[k].az):
        s = sources[k]
        for g in groups:
            if any(separation(unit(np.array([s.az]), np.array([s.el])),
                              unit(np.array([sources[j].az]), np.array([sources[j].el])))[0, 0] < radius_deg for j in g):
                g.append(k)
                break
        else:
            groups.append([k])
    return groups


def measure_sources(model: BeamModel, terms, sigma, lag, coef, noise) -> list[SourceFit]:
    """Each detected group of sources measured on its own: the other sources' beams and the floor
    subtracted, the group's beams (with their fitted amplitudes) shifted together in dish axes to
    fit the readings around it. The shift is the group's residual: how far from where the fitted
    mount puts it the sky shows it."""
    scan = model.scan
    a = model.design(terms, sigma, lag)
    amplitudes = coef[3:3 + len(model.sources)]
    strongest = amplitudes.max() if len(amplitudes) else 0.0
    beams = model.beams(terms, lag)
    az_s, el_s = model.sample_axes(lag)
    out = []
    for members in groups_of(model.sources):
        amp = amplitudes[members]
        total = float(amp.sum())
        names = [n for k in members for n in model.sources[k].members]
        weights = amp / total if total > 0 else np.full(len(members), 1 / len(members))
        # The group's direction on the sky: its members' mean, weighted by what the dish hears of each.
        mean = (unit(np.array([model.sources[k].az for k in members]),
                     np.array([model.sources[k].el for k in members])) * weights[:, None]).sum(axis=0)
        mean /= np.linalg.norm(mean)
        sky_az = float(np.degrees(np.arctan2(mean[0], mean[1])) % 360.0)
        sky_el = float(np.degrees(np.arcsin(mean[2])))
        fitk = SourceFit(Source(" + ".join(names), sky_az, sky_el, names), total)
        out.append(fitk)
        if total < max(8 * noise, 0.08 * strongest):
            continue
        pa, pe = sky_to_dish(tuple(terms), sky_az, sky_el)
        near = separation(unit(np.array([pa]), np.array([pe])), unit(az_s, el_s))[0] < 1.5 * sigma
        if near.sum() < 12 or not surrounded(az_s[near], el_s[near], pa, pe):
            continue
        own = a[:, [3 + k for k in members]] @ amp
        rest = (scan.value - a @ coef + own)[near]
        member_dish = [sky_to_dish(tuple(terms), model.sources[k].az, model.sources[k].el) for k in members]
        bsky = beams[near]

        def local(x):
            shifted = np.zeros(len(rest))
            for (ma, me), ak in zip(member_dish, amp):
                sa, se = dish_to_sky(tuple(terms), ma + x[0], me + x[1])
                d = separation(bsky, unit(np.array([sa]), np.array([se])))[:, 0]
                shifted += ak * np.exp(-0.5 * (d / sigma) ** 2)
            return rest - (x[2] * shifted + x[3])

        sol = least_squares(local, [0.0, 0.0, 1.0, 0.0], x_scale=[0.3, 0.3, 0.1, 1])
        try:
            cov = np.linalg.inv(sol.jac.T @ sol.jac) * (sol.fun @ sol.fun) / max(len(rest) - 4, 1)
            unc = float(np.sqrt(cov[0, 0] * math.cos(math.radians(pe)) ** 2 + cov[1, 1]))
        except np.linalg.LinAlgError:
            continue
        shift = math.hypot(sol.x[0] * math.cos(math.radians(pe)), sol.x[1])
        if not math.isfinite(unc) or unc > 0.5 or shift > 2 * sigma:
            continue
        da, de = pa + sol.x[0], pe + sol.x[1]
        sa, se = dish_to_sky(tuple(terms), da, de)
        fitk.dish_az, fitk.dish_el = float(da) % 360.0, float(de)
        fitk.sky_az, fitk.sky_el = float(sa) % 360.0, float(se)
        fitk.residual = float(separation(unit(np.array([sa]), np.array([se])),
                                         unit(np.array([sky_az]), np.array([sky_el])))[0, 0])
        fitk.uncertainty = unc
    return out


def surrounded(az, el, pa, pe, need: float = 2.0) -> bool:
    """Readings on every side of (pa, pe), at least `need` degrees out: a peak on the scan's edge is
    a slope, not a measured position."""
    dx = ((az - pa + 180) % 360 - 180) * math.cos(math.radians(pe))
    dy = el - pe
    return bool((dx > need).any() and (dx < -need).any() and (dy > need).any() and (dy < -need).any())


def find_peaks(scan: Scan, radius_deg: float = 4.0, count: int = 20):
    """Local maxima above the floor (median + 6 robust sigma), one per radius."""
    v = scan.value
    floor = np.median(v)
    spread = 1.4826 * np.median(np.abs(v - floor))
    threshold = floor + max(10.0, 6.0 * spread)
    pts = np.c_[scan.az * np.cos(np.radians(scan.el)), scan.el]
    tree = cKDTree(pts)
    peaks = []
    for i in np.argsort(-v):
        if v[i] < threshold:
            break
        neigh = tree.query_ball_point(pts[i], radius_deg)
        if v[i] >= v[neigh].max() and all(math.hypot(*(pts[i] - pts[j])) > radius_deg for _, j in peaks):
            peaks.append((float(v[i]), int(i)))
        if len(peaks) >= count:
            break
    return floor, [(val, float(scan.az[i]), float(scan.el[i])) for val, i in peaks]
