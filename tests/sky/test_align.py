# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-align's fit: on the real G2 scan of sim/data/g2-ku-skyscan (whose catalogue is look
angles at the unpublished site), and on scans generated here from a known mount with this file's
own forward model (fakerot.py's map of docs/sky.md section 1)."""

from __future__ import annotations

import math
import random
from pathlib import Path

import numpy as np
import pytest
from conftest import json_lines, run
from fakerot import mount_dish_to_sky, separation_deg

ROOT = Path(__file__).resolve().parents[2]
REAL = ROOT / "sim" / "data" / "g2-ku-skyscan"


def test_real_g2_scan(tmp_path):
    """The upstream scan is unidirectional (every column rises), so a reading's lag behind its
    label would be one elevation offset, absorbed by el_index; the serpentine lag (docs/firmware.md
    §8.7 and §12.4) is fitted only for scans whose columns alternate (test_synthetic_lag)."""
    _, out, _ = run("birdcage-align", "--from-scan", REAL / "scan_data.txt", "--catalogue",
                    REAL / "satellite_data.csv", "--json", "--plot", tmp_path / "real.png")
    result = json_lines(out)[-1]
    _, out, _ = run("birdcage-align", "--from-scan", REAL / "scan_data.txt", "--catalogue",
                    REAL / "satellite_data.csv", "--json", "--no-plot", "--index-only")
    index_only = json_lines(out)[-1]
    print("real G2 scan, four terms: " + ", ".join(f"{k} {result[k]:+.3f} ± {result['sigma'][k]:.3f}" for k in
          ("az_index", "el_index", "tilt_north", "tilt_east")))
    print(f"  residual {result['residual_rms_deg']:.3f} deg RMS over {result['n_sources']} sources; "
          f"index terms only: {index_only['residual_rms_deg']:.3f} deg over {index_only['n_sources']}")
    for s in result["sources"]:
        print(f"    {s['name'][:40]:<40} residual {s['residual_deg']:.3f}")
    assert result["event"] == "result"
    assert result["n_sources"] >= 6
    assert result["residual_rms_deg"] <= 0.5
    assert index_only["residual_rms_deg"] > result["residual_rms_deg"] + 0.2  # the tilts are needed
    for line, k in zip(result["conf_lines"], ("az_index", "el_index", "tilt_north", "tilt_east")):
        key, value = line.removeprefix("-C ").split("=")
        assert key == k and float(value) == pytest.approx(result[k], abs=0.006)
    assert (tmp_path / "real.png").stat().st_size > 10000


def geo_look(lat, lon, sat_lon):
    """Look angles of a geostationary slot, written here independently (WGS84 station, equatorial
    satellite at 42164.17 km)."""
    a, f = 6378.137, 1 / 298.257223563
    e2 = f * (2 - f)
    phi, lam = math.radians(lat), math.radians(lon)
    n = a / math.sqrt(1 - e2 * math.sin(phi) ** 2)
    st = np.array([n * math.cos(phi) * math.cos(lam), n * math.cos(phi) * math.sin(lam), n * (1 - e2) * math.sin(phi)])
    s = 42164.17 * np.array([math.cos(math.radians(sat_lon)), math.sin(math.radians(sat_lon)), 0.0])
    d = s - st
    east = np.array([-math.sin(lam), math.cos(lam), 0.0])
    north = np.array([-math.sin(phi) * math.cos(lam), -math.sin(phi) * math.sin(lam), math.cos(phi)])
    up = np.array([math.cos(phi) * math.cos(lam), math.cos(phi) * math.sin(lam), math.sin(phi)])
    return math.degrees(math.atan2(d @ east, d @ north)) % 360.0, math.degrees(math.asin(d @ up / np.linalg.norm(d)))


def catalogue(lat, lon):
    rows = []
    for line in (ROOT / "tools" / "sky" / "data" / "geostationary.csv").read_text().splitlines():
        if line.startswith("#") or line.startswith("name,"):
            continue
        name, sat_lon = line.rsplit(",", 1)
        az, el = geo_look(lat, lon, float(sat_lon))
        if el > 5:
            rows.append((name, az, el))
    return rows


def synthetic_scan(path: Path, mount, sky, lag_share=0.0, noise=2.5, seed=7):
    """A serpentine raster in dish axes; each reading taken lag_share of a step before its label."""
    rng = random.Random(seed)
    lines = ["az,el,value,time"]
    previous = None
    for i, az in enumerate(np.arange(100.0, 262.0, 2.0)):
        els = list(np.arange(14.0, 58.1, 2.0))
        if i % 2:
            els.reverse()
        for el in els:
            at = (az, el) if previous is None or previous[0] != az else (
                az, el - lag_share * (el - previous[1]))
            saz, sel = mount_dish_to_sky(mount, *at)
            value = 400.0 + 0.4 * (30.0 - el) + sum(amp * math.exp(-0.5 * (separation_deg(saz, sel, a, e) / 2.9) ** 2)
                                                    for a, e, amp in sky)
            lines.append(f"{az:.2f},{el:.2f},{value + rng.gauss(0, noise):.2f},")
            previous = (az, el)
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("lag_share", [0.0, 0.5])
def test_synthetic_scan_recovers_the_mount(tmp_path, lag_share):
    mount = (6.0, 0.8, 1.2, -0.5)
    rows = catalogue(45.0, -93.0)
    rng = random.Random(3)
    sky = [(az, el, rng.uniform(20, 150)) for _, az, el in rows if rng.random() < 0.6]
    synthetic_scan(tmp_path / "scan.csv", mount, sky, lag_share)
    (tmp_path / "cat.csv").write_bytes("".join(f"{n},{a:.2f},{e:.2f}\r\n" for n, a, e in rows).encode())
    _, out, _ = run("birdcage-align", "--from-scan", tmp_path / "scan.csv", "--catalogue", tmp_path / "cat.csv",
                    "--json", "--no-plot")
    result = json_lines(out)[-1]
    got = [result[k] for k in ("az_index", "el_index", "tilt_north", "tilt_east")]
    print(f"lag {lag_share}: recovered {got} (fitted lag {result['lag']}), residual {result['residual_rms_deg']} "
          f"over {result['n_sources']} sources, sigma {result['sigma']}")
    for want, have in zip(mount, got):
        assert have == pytest.approx(want, abs=0.1)
    assert result["lag"] == pytest.approx(lag_share, abs=0.1)
    assert result["residual_rms_deg"] <= 0.15


def sun_raster(offset_x: float, offset_y: float, amplitude: float, seed: int):
    """The Sun raster birdcage-align takes (±10 deg in sky-scaled azimuth, ±4 in elevation, 2 deg
    steps) of a 2.9 deg beam on a floor of 401 counts with 8 counts of noise per reading."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(-10.0, 10.01, 2.0), np.arange(-4.0, 4.01, 2.0))
    x, y = x.ravel(), y.ravel()
    beam = np.exp(-((x - offset_x) ** 2 + (y - offset_y) ** 2) / (2 * 2.9 ** 2))
    return x, y, 401.0 + amplitude * beam + rng.normal(0.0, 8.0, x.size)


@pytest.mark.parametrize("offset_x", [0.0, 3.0, 4.86, 7.0, 9.0])
def test_sun_raster_finds_a_beam_wide_source_anywhere_inside(offset_x):
    """The fourth e2e mount draw put the Sun 4.86 deg of sky from the raster's centre: a beam that
    wide lights most of the raster, and the old median-and-MAD test took the Sun for the spread."""
    from birdcage_sky.scanner import raster_source

    for seed in range(5):
        found = raster_source(*sun_raster(offset_x, -0.3, 200.0, seed))
        assert found is not None, f"seed {seed}"
        assert math.hypot(found[0] - offset_x, found[1] + 0.3) < 0.5, f"seed {seed}: {found}"


def test_sun_raster_without_a_source_or_with_it_beyond_the_edge_finds_none():
    from birdcage_sky.scanner import raster_source

    for seed in range(20):
        assert raster_source(*sun_raster(0.0, 0.0, 0.0, seed)) is None, f"seed {seed}: noise alone"
        assert raster_source(*sun_raster(16.0, 0.0, 200.0, seed)) is None, f"seed {seed}: beyond the edge"
