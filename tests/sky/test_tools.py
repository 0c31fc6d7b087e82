# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-track and birdcage-align through their command line and JSON (the contract the MCP
server and the TUI read, docs/sky.md section 5), against fakerot.py's stand-in for rotctld: fast,
and with a dish whose every command is seen."""

from __future__ import annotations

import json
import math
import signal
import subprocess
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pytest
from conftest import json_lines, program, run
from fakerot import FakeRotctld, separation_deg
from test_align import geo_look

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"
PASS_TLE = ROOT / "bench" / "passes" / "iss-45.tle"
SITE = ["--lat", "45", "--lon", "-93", "--alt", "250"]
EPOCH = datetime(2024, 6, 1, tzinfo=timezone.utc).timestamp()  # iss-45: AOS at 18 deg 00:02:33


@pytest.fixture
def fake():
    made = []

    def make(**kwargs):
        f = FakeRotctld(**kwargs)
        made.append(f)
        return f

    yield make
    for f in made:
        f.close()


def clock_args(f: FakeRotctld) -> list[str]:
    return ["--at", datetime.fromtimestamp(f.epoch, timezone.utc).isoformat(), "--at-wall", f"{f.anchor:.6f}",
            "--time-scale", f"{f.time_scale:g}"]


def test_passes_json_follow_the_dish_window(fake):
    f = fake(el_limits=(18.0, 40.0), epoch=EPOCH)
    _, out, _ = run("birdcage-track", *SITE, "--tle", PASS_TLE, "--port", f.port, *clock_args(f), "--passes",
                    "--count", "2", "--json", "99045")
    doc = json.loads(out)
    assert set(doc) >= {"target", "station", "limits", "passes"}
    assert doc["limits"]["el_min"] == 18.0 and doc["limits"]["el_max"] == 40.0  # from `_`, not dump_state's 0..90
    assert doc["station"] == {"lat": 45.0, "lon": -93.0, "alt": 250.0}
    first = doc["passes"][0]
    assert set(first) >= {"aos", "tca", "los", "max_el", "aos_az", "tca_az", "los_az", "duration_s"}
    assert first["aos"] == "2024-06-01T00:02:33Z" and first["los"] == "2024-06-01T00:06:58Z"
    assert first["max_el"] == pytest.approx(45.0, abs=0.05)
    assert first["above_max_s"] > 60 and len(first["above_max"]) == 1  # above the 40 deg cap


def test_passes_without_rotctld_use_default_limits():
    _, out, _ = run("birdcage-track", *SITE, "--tle", PASS_TLE, "--port", "1", "--at", "2024-06-01T00:00:00Z",
                    "--passes", "--count", "1", "--json", "BIRDCAGE")
    doc = json.loads(out)
    assert doc["limits_source"] == "default"
    assert (doc["limits"]["el_min"], doc["limits"]["el_max"]) == (0.0, 90.0)
    assert doc["passes"][0]["aos"] == "2024-05-31T23:59:22Z"  # the horizon, and the pass under way at --at


def test_search_and_visible():
    _, out, _ = run("birdcage-track", "--tle", DATA / "fixtures.tle", "--tle", DATA / "27607.sat", "--search", "o",
                    "--json")
    names = {s["name"]: s for s in json.loads(out)["satellites"]}
    assert set(names) == {"NOAA 19", "MOLNIYA 1-91", "SO-50", "GOES 16"}
    assert names["SO-50"]["norad"] == 27607 and names["SO-50"]["epoch"] == "2018-01-20T20:35:36Z"
    _, out, _ = run("birdcage-track", *SITE, "--tle", DATA / "fixtures.tle", "--port", "1", "--at",
                    "2018-01-21T08:56:00Z", "--visible", "--json")
    doc = json.loads(out)
    kinds = {t["name"]: t for t in doc["targets"]}
    assert "NOAA 19" in kinds and kinds["NOAA 19"]["kind"] == "satellite"  # over the site then (a pass at 08:52)
    assert all(t["el"] >= 0 and t["in_window"] for t in doc["targets"])
    assert doc["time"] == "2018-01-21T08:56:00Z"


def test_usage_and_lookup_errors():
    status, out, err = run("birdcage-track", "--passes", "sun", check_exit=2, env={"BIRDCAGE_LAT": "", "BIRDCAGE_LON": ""})
    assert out == "" and err.count("\n") == 1 and err.startswith("birdcage-track: --lat and --lon")
    status, out, err = run("birdcage-track", *SITE, "--tle", PASS_TLE, "--port", "1", "--json", "nosuchsat",
                           check_exit=1)
    end = json_lines(out)[-1]
    assert end["event"] == "end" and end["outcome"] == "error" and "nosuchsat" in end["reason"]
    assert err.startswith("birdcage-track: ") and err.count("\n") == 1
    # A target, but no rotctld to follow it with.
    status, out, err = run("birdcage-track", *SITE, "--port", "1", "--json", "sun", check_exit=1)
    assert json_lines(out)[-1]["outcome"] == "error" and "cannot reach rotctld" in err
    status, out, err = run("birdcage-align", "--from-scan", "/nonexistent", "--catalogue", "/nonexistent", "--json",
                           check_exit=1)
    assert json_lines(out)[-1]["event"] == "error"


def test_track_a_pass(fake):
    """iss-45 at time scale 20 from 60 s before AOS: plan, wait at the entry point, progress, end at
    LOS, parked; every target sent lies inside the dish's window."""
    f = fake(epoch=EPOCH + 90, time_scale=20, speed=20.0, delay=0.2, start=(100.0, 30.0))
    _, out, err = run("birdcage-track", *SITE, "--tle", PASS_TLE, "--port", f.port, *clock_args(f), "--json",
                      "--park-at-los", "BIRDCAGE ISS-45", timeout=120)
    events = json_lines(out)
    kinds = [e["event"] for e in events]
    assert kinds[0] == "plan" and kinds[-1] == "end" and "wait" in kinds and "progress" in kinds
    plan, end = events[0], events[-1]
    assert plan["aos"] == "2024-06-01T00:02:33Z" and plan["los"] == "2024-06-01T00:06:58Z"
    wait = next(e for e in events if e["event"] == "wait")
    assert set(wait) >= {"now", "seconds_to_aos", "aim"} and wait["aim"]["el"] == pytest.approx(18.0, abs=0.01)
    progress = next(e for e in events if e["event"] == "progress")
    assert set(progress) >= {"now", "target", "dish", "error_deg", "seconds_to_los"}
    assert end["outcome"] == "los" and end["parked"] is True and f.commands[-1].lstrip("+") == "K"
    print(f"fake dish, iss-45: {end['rms_error_deg']} deg RMS, max {end['max_error_deg']}, {end['commands_sent']} "
          f"targets, response learnt {end['response_s']} s (the fake's delay 0.2 s + its 20 deg/s)")
    assert end["rms_error_deg"] <= 0.15 and end["samples"] > 100
    assert 50 < end["commands_sent"] < 2000
    assert all(18.0 <= el <= 65.0 for _, _, el in f.moves[:-1])
    # The first target is sent once, before the pass, and the dish waits there.
    assert f.moves[0][0] < datetime(2024, 6, 1, 0, 2, 23, tzinfo=timezone.utc).timestamp()


def test_interrupt_stops_the_dish(fake):
    f = fake(epoch=EPOCH + 150, time_scale=10, speed=20.0, start=(314.0, 18.0))
    proc = subprocess.Popen([program("birdcage-track"), *SITE, "--tle", str(PASS_TLE), "--port", str(f.port),
                             *clock_args(f), "--json", "99045"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 30
    while not any(c.startswith("+P") for c in f.commands):
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err
    end = json_lines(out)[-1]
    assert end["outcome"] == "interrupted"
    assert f.stopped()


def test_behind_predictive_pointing_targets_go_unled(fake):
    f = fake(epoch=EPOCH + 150, time_scale=20, speed=20.0, start=(314.0, 18.0), pointing="predictive")
    _, out, _ = run("birdcage-track", *SITE, "--tle", PASS_TLE, "--port", f.port, *clock_args(f), "--json",
                    "--duration", "60", "99045", timeout=60)
    end = json_lines(out)[-1]
    assert end["outcome"] == "duration" and end["backend_leads"] is True
    from birdcage_sky import targets, tle
    from birdcage_sky.geodesy import Station

    sat = targets.Satellite(tle.load([PASS_TLE])[0])
    offsets = [separation_deg(az % 360, el, *sat.look_one(Station(45, -93, 250), t)) for t, az, el in f.moves[1:]]
    assert max(offsets) < 0.5  # where the satellite was when each was sent: no lead


def sun_low_precision(t_unix: float, lat: float, lon: float):
    """The Sun's topocentric direction to ~0.01 deg (the Astronomical Almanac's low-precision
    formulae), written here for the fake sky: independent of tools/sky and of the emulator."""
    n = t_unix / 86400.0 + 2440587.5 - 2451545.0
    L = math.radians((280.460 + 0.9856474 * n) % 360)
    g = math.radians((357.528 + 0.9856003 * n) % 360)
    lam = L + math.radians(1.915) * math.sin(g) + math.radians(0.020) * math.sin(2 * g)
    eps = math.radians(23.439 - 0.0000004 * n)
    ra = math.atan2(math.cos(eps) * math.sin(lam), math.cos(lam))
    dec = math.asin(math.sin(eps) * math.sin(lam))
    gmst = math.radians((280.46061837 + 360.98564736629 * n) % 360)
    h = gmst + math.radians(lon) - ra
    phi = math.radians(lat)
    el = math.asin(math.sin(phi) * math.sin(dec) + math.cos(phi) * math.cos(dec) * math.cos(h))
    az = math.atan2(-math.cos(dec) * math.sin(h), math.sin(dec) * math.cos(phi) - math.cos(dec) * math.sin(phi) * math.cos(h))
    return math.degrees(az) % 360.0, math.degrees(el) - 0.0024  # the solar parallax, roughly


def test_align_live_recovers_the_mount(fake, tmp_path):
    mount = (-8.0, 1.0, -0.7, 0.9)
    rng = np.random.default_rng(5)
    sources = []
    for line in (ROOT / "tools" / "sky" / "data" / "geostationary.csv").read_text().splitlines():
        if line.startswith("#") or line.startswith("name,"):
            continue
        az, el = geo_look(45.0, -93.0, float(line.rsplit(",", 1)[1]))
        if el > 10 and rng.random() < 0.5:
            sources.append((az, el, float(rng.uniform(30, 150))))
    f = fake(mount=mount, sources=sources, noise=2.0, time_scale=200, speed=200.0, delay=0.0,
             epoch=datetime(2026, 12, 1, 3, 0, tzinfo=timezone.utc).timestamp())  # night: no Sun
    _, out, err = run("birdcage-align", *SITE, "--port", f.port, *clock_args(f), "--json", "--plot",
                      tmp_path / "a.png", timeout=300)
    events = json_lines(out)
    result = events[-1]
    got = [result[k] for k in ("az_index", "el_index", "tilt_north", "tilt_east")]
    print(f"fake dish: recovered {got} of {list(mount)}; residual {result['residual_rms_deg']} over "
          f"{result['n_sources']}; {result['scan_points']} points; sun: {result['sun']}")
    assert any(e["event"] == "progress" and e["phase"] == "scan" for e in events)
    assert result["plot"] == str(tmp_path / "a.png") and (tmp_path / "a.png").exists()
    assert "V LNB 13" in [c.lstrip("+") for c in f.commands]
    # From the arc alone (the Sun down) the terms are known less well than the residuals suggest:
    # el_index and tilt_north trade against each other (the arc lies in the south, where both lift
    # the beam alike), and a dense arc with free amplitudes can slide a little along itself
    # (docs/sky.md section 3). Each term within 3 of its sigmas; the Sun, when it is up, pins them
    # (test_e2e.py's align).
    for name, want, have in zip(("az_index", "el_index", "tilt_north", "tilt_east"), mount, got):
        assert abs(have - want) <= 3 * result["sigma"][name] + 0.05, name
    assert result["residual_rms_deg"] <= 0.15
    print(f"  sigma {result['sigma']}")


def test_align_on_the_sun(fake):
    mount = (4.0, -1.5, 0.0, 0.0)
    when = datetime(2026, 6, 21, 15, 0, tzinfo=timezone.utc).timestamp()
    f = fake(mount=mount, time_scale=100, speed=200.0, delay=0.0, epoch=when, noise=1.0,
             sun=(lambda t: sun_low_precision(t, 45.0, -93.0), 150.0))
    _, out, err = run("birdcage-align", *SITE, "--port", f.port, *clock_args(f), "--json", "--sun", timeout=300)
    result = json_lines(out)[-1]
    print(f"fake dish, one Sun fix: az_index {result['az_index']}, el_index {result['el_index']} (set up "
          f"{mount[0]}, {mount[1]})")
    assert result["fitted"] == ["az_index", "el_index"]
    assert result["az_index"] == pytest.approx(mount[0], abs=0.1)
    assert result["el_index"] == pytest.approx(mount[1], abs=0.1)
