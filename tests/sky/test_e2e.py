# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The sky tools against the emulated dish behind the distribution's rotctld with the birdcage
backend preloaded, judged by the emulator's truth file (where the beam really pointed, sim/README.md)
against independent implementations: skyfield's SGP4 for the satellite, astropy for the Sun.
Every dish ends with 0 hazards counted by the emulator."""

from __future__ import annotations

import random
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pytest
from conftest import json_lines, run
from emulator import rig
from fakerot import separation_deg
from skyfield.api import EarthSatellite, load, wgs84

ROOT = Path(__file__).resolve().parents[2]
PASS_TLE = ROOT / "bench" / "passes" / "iss-45.tle"
STATION = (45.0, -93.0, 250.0)  # the bench's site
STATION_ARGS = ["--lat", "45", "--lon", "-93", "--alt", "250"]
MOUNT = (6.0, 0.8, 1.2, -0.5)
MOUNT_TEXT = "az_index=6,el_index=0.8,tilt_north=1.2,tilt_east=-0.5"


def in_sky_frame(rows, since, until):
    return [r for r in rows if since <= r["unix"] <= until]


def satellite_truth_error(rows, el_min: float) -> tuple[float, float, int]:
    """RMS and max of the beam (truth sky columns) against skyfield's SGP4 at the rows' times,
    over the rows with the satellite inside the dish's window."""
    lines = PASS_TLE.read_text().splitlines()
    ts = load.timescale(builtin=True)
    sat = EarthSatellite(lines[1], lines[2], lines[0], ts)
    top = wgs84.latlon(STATION[0], STATION[1], elevation_m=STATION[2])
    t = ts.from_datetimes([datetime.fromtimestamp(r["unix"], timezone.utc) for r in rows])
    alt, az, _ = (sat - top).at(t).altaz()
    errors = [separation_deg(r["sky_az"], r["sky_el"], a, e)
              for r, a, e in zip(rows, az.degrees, alt.degrees) if e >= el_min]
    e = np.array(errors)
    return float(np.sqrt(np.mean(e * e))), float(e.max()), len(e)


@pytest.mark.parametrize("variant,model,el_min,bound", [("g2", 90105, 18.0, 0.15), ("hal205", 90102, 15.0, 0.35)])
def test_track_replays_a_pass(tmp_path, variant, model, el_min, bound):
    """iss-45 (bench/passes) replayed at time scale 4 from 90 s before AOS: the tool's clock and the
    emulator's run from the same --epoch. pointing=none: the tool leads the targets itself."""
    with rig(tmp_path, variant, model, 4, "2024-06-01T00:01:00Z", conf="pointing=none") as r:
        _, out, err = run("birdcage-track", *STATION_ARGS, "--tle", PASS_TLE, "--port", r.port, *r.clock_args(),
                          "--json", "99045", timeout=400)
        time.sleep(0.5)
    events = json_lines(out)
    end = events[-1]
    assert [e["event"] for e in events][0] == "plan" and "wait" in [e["event"] for e in events]
    assert end["event"] == "end" and end["outcome"] == "los", err
    rows = r.truth_rows()
    rms, worst, n = satellite_truth_error(rows, el_min)
    print(f"{variant}: beam against skyfield over the pass: {rms:.3f} deg RMS, max {worst:.3f} ({n} truth rows); "
          f"the tool's own p-based figure {end['rms_error_deg']} RMS, {end['commands_sent']} targets sent, "
          f"{motor_starts(rows)} motor starts (truth file), response {end['response_s']} s")
    assert r.hazards_ok(), r.sim_stderr
    assert n > 500
    assert rms <= bound


def motor_starts(rows) -> int:
    """How often the emulated dish started moving (the truth file's `moving` column going 0 -> 1):
    the figure to set beside a client's own, e.g. real Gpredict's on the same pass."""
    moving = [r["moving"] == "1" for r in rows]
    return sum(1 for before, now in zip(moving, moving[1:]) if now and not before)


def astropy_sun(unix_times, station):
    from astropy.utils import iers

    iers.conf.auto_download = False
    iers.conf.iers_degraded_accuracy = "warn"
    import astropy.units as u
    from astropy.coordinates import AltAz, EarthLocation, get_body
    from astropy.time import Time

    loc = EarthLocation.from_geodetic(station[1] * u.deg, station[0] * u.deg, station[2] * u.m)
    t = Time(np.asarray(unix_times), format="unix", scale="utc")
    aa = get_body("sun", t, loc).transform_to(AltAz(obstime=t, location=loc, pressure=0 * u.hPa))
    return aa.az.deg, aa.alt.deg


def test_track_the_sun(tmp_path):
    """Ten minutes of the Sun at time scale 20 (G2), the beam against astropy's Sun."""
    epoch = "2026-06-21T16:00:00Z"
    with rig(tmp_path, "g2", 90105, 20, epoch, conf="pointing=none") as r:
        _, out, err = run("birdcage-track", *STATION_ARGS, "--port", r.port, *r.clock_args(), "--duration", 600,
                          "--json", "sun", timeout=200)
        time.sleep(0.5)
    end = json_lines(out)[-1]
    assert end["outcome"] == "duration", err
    rows = r.truth_rows()
    start = datetime.fromisoformat(epoch.replace("Z", "+00:00")).timestamp()
    # From the first minute on: the dish starts at az 100 el 30 and slews to the Sun first.
    rows = [x for x in rows if x["unix"] >= start + 60 and x["unix"] <= start + 600]
    az, el = astropy_sun([x["unix"] for x in rows], STATION)
    e = np.array([separation_deg(x["sky_az"], x["sky_el"], a, b) for x, a, b in zip(rows, az, el)])
    rms = float(np.sqrt(np.mean(e * e)))
    print(f"sun: beam against astropy over 9 minutes: {rms:.3f} deg RMS, max {e.max():.3f} ({len(e)} rows), "
          f"{end['commands_sent']} targets sent")
    assert r.hazards_ok(), r.sim_stderr
    assert len(e) > 100
    assert rms <= 0.1


# Mount errors the emulated G2 is set up with, each at a time of day when the Sun is inside the
# dish's window, so its cross-scan joins the arc (the arc alone leaves el_index and tilt_north
# trading against each other, docs/sky.md section 3): the docs' example with the Sun in the east,
# then three draws, one with a 15 deg azimuth error, with the Sun in the east and the
# west-south-west. Without a Sun fix the arc alone trades el_index against tilt_north. The fourth
# draw puts the Sun 4.9 deg of sky from the Sun raster's centre, where a beam as wide as the raster
# once hid it from the detection (docs/benchmarks.md, "The sky tools").
ALIGN_DRAWS = [
    pytest.param(MOUNT, "2026-06-21T14:00:00Z", id="example-sun"),
    pytest.param((-15.0, -1.5, -0.6, 0.9), "2026-06-21T15:30:00Z", id="az15"),
    pytest.param((3.5, 2.0, 0.4, 1.5), "2026-06-21T21:00:00Z", id="tilted-east"),
    pytest.param((-8.0, -0.5, -1.4, -1.0), "2026-06-21T14:30:00Z", id="sun-off-centre"),
]


def mount_text(mount) -> str:
    return ",".join(f"{k}={v}" for k, v in zip(("az_index", "el_index", "tilt_north", "tilt_east"), mount))


@pytest.mark.parametrize("mount,epoch", ALIGN_DRAWS)
def test_align_and_point(tmp_path, mount, epoch):
    """birdcage-align on the emulated G2 set up with a mount error, then a new rotctld with the
    printed -C lines: the beam on 20 random sky positions, from the truth file."""
    MOUNT_TEXT = mount_text(mount)
    with rig(tmp_path, "g2", 90105, 50, epoch, conf="pointing=none", mount=MOUNT_TEXT) as r:
        _, out, err = run("birdcage-align", *STATION_ARGS, "--port", r.port, *r.clock_args(), "--json",
                          "--plot", tmp_path / "align.png", timeout=400)
    result = json_lines(out)[-1]
    progress = [e for e in json_lines(out) if e["event"] == "progress" and e["phase"] == "scan"]
    got = [result[k] for k in ("az_index", "el_index", "tilt_north", "tilt_east")]
    print(f"align: {got} (set up with {list(mount)}), sigma {result['sigma']}, residual "
          f"{result['residual_rms_deg']} deg over {result['n_sources']} sources; {result['scan_points']} points, "
          f"{result['scan_seconds']:.0f} s of the dish's time; Sun: {result['sun']}")
    assert r.hazards_ok(), r.sim_stderr
    assert progress and progress[-1]["done"] == progress[-1]["total"]
    assert result["n_sources"] >= 6 and result["residual_rms_deg"] <= 0.3
    for want, have in zip(mount, got):
        assert have == pytest.approx(want, abs=0.3)

    conf = "pointing=none," + ",".join(line.removeprefix("-C ") for line in result["conf_lines"])
    rng = random.Random(20)
    targets = [(rng.uniform(0, 360), rng.uniform(20, 62)) for _ in range(20)]
    with rig(tmp_path, "g2", 90105, 50, epoch, conf=conf, mount=MOUNT_TEXT) as r2:
        settled = []
        for az, el in targets:
            ask(r2.port, f"P {az:.2f} {el:.2f}")
            deadline = time.monotonic() + 30
            previous = None
            while True:
                p = ask(r2.port, "p")
                if previous == p and not moving(r2.port):
                    break
                assert time.monotonic() < deadline, f"the dish did not settle for {az:.2f} {el:.2f}"
                previous = p
                time.sleep(0.05)
            time.sleep(0.4)  # the truth file is flushed every 0.25 s
            settled.append(r2.truth_rows()[-1])
    errors = np.array([separation_deg(row["sky_az"], row["sky_el"], az, el) for row, (az, el) in zip(settled, targets)])
    rms = float(np.sqrt(np.mean(errors ** 2)))
    print(f"pointing with the fitted conf: {rms:.3f} deg RMS, max {errors.max():.3f} over 20 random sky positions")
    assert r2.hazards_ok(), r2.sim_stderr
    assert rms <= 0.2


def ask(port: int, command: str) -> str:
    import socket

    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        f = s.makefile("rw")
        f.write(f"+{command}\n")
        f.flush()
        lines = []
        while not (line := f.readline().strip()).startswith("RPRT"):
            lines.append(line)
        assert line == "RPRT 0", f"{command}: {line}"
        return "\n".join(lines[1:])


def moving(port: int) -> bool:
    return "MOVING" in ask(port, "s")
