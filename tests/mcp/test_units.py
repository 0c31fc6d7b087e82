# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""The parts that need no rotctld: what the client refuses to send, the scan grid, the peak finder,
the order in which a stop reads the dish, the reading of birdcage-track's JSON lines."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from mcp.server.mcpserver.exceptions import ToolError

from birdcage_mcp.motion import wait_stopped
from birdcage_mcp.rotator import named_target
from birdcage_mcp.rotctld import Rotctld, RotctldError
from birdcage_mcp.scan import axis, find_peaks, serpentine
from birdcage_mcp.sky import Sky, SkyClock, SkyOptions, parse_time

pytestmark = pytest.mark.anyio


async def test_the_client_sends_no_raw_console_command():
    rot = Rotctld("127.0.0.1", 9)  # nothing is ever connected: the checks come first
    with pytest.raises(ValueError, match="not one this client sends"):
        await rot.ask("w", "a", "0", "0")  # rotctld's send_cmd would pass bytes to the firmware
    with pytest.raises(ValueError):
        await rot.ask("\\get_conf", "pointing")  # rotctld 4.5.4 would run it letter by letter
    with pytest.raises(RotctldError, match="not a plain word"):
        await rot.ask("P", "100\nK", "30")  # a second command smuggled into an argument
    with pytest.raises(RotctldError, match="not a plain word"):
        await rot.ask("V", "LNB 13")


def test_axis_and_serpentine():
    assert axis(158, 166, 4) == [158, 162, 166]
    assert axis(40, 41, 0.5) == [40, 40.5, 41]
    assert axis(10, 12.9, 1) == [10, 11, 12]
    assert serpentine([1, 2, 3], [10, 20]) == [(1, 10), (1, 20), (2, 20), (2, 10), (3, 10), (3, 20)]


def test_find_peaks_one_per_neighbourhood_above_the_floor():
    rows = [(az, el, 400.0 + (az + el) % 3) for az in range(100, 140, 2) for el in range(20, 40, 2)]
    values = {(a, e): v for a, e, v in rows}
    values[(120, 30)] = 560.0
    values[(122, 30)] = 540.0  # the same satellite's shoulder: no second peak
    values[(130, 24)] = 500.0
    rows = [(a, e, v) for (a, e), v in values.items()]
    floor, peaks = find_peaks(rows)
    assert 400 <= floor <= 402
    assert peaks == [(560.0, 120, 30), (500.0, 130, 24)]
    assert find_peaks([]) == (None, [])


class LegEndingOnEveryReading:
    """A dish finishing its elevation leg: each reading (flags or position) takes one step of time,
    and the leg ends at the fourth. Whichever order a caller reads in, the leg can end between its
    two readings, as it did in CI (the stop answered el 49.97 for a dish at rest at 50.00)."""

    def __init__(self) -> None:
        self.steps = 0
        self.rot = self

    def elevation(self) -> float:
        return 50.0 if self.steps >= 4 else 49.9 + 0.01 * self.steps

    async def status(self) -> list[str]:
        self.steps += 1
        return [] if self.steps >= 4 else ["BUSY", "MOVING"]

    async def position(self) -> tuple[float, float]:
        self.steps += 1
        return 100.0, self.elevation()


async def test_a_stop_answers_where_the_dish_rests_not_a_reading_taken_before_it_came_to_rest():
    dish = LegEndingOnEveryReading()
    stopped = await wait_stopped(dish, wait_s=10.0, target=(300.0, 50.0))
    assert stopped.state == "stopped"
    assert (stopped.position.azimuth, stopped.position.elevation) == (100.0, 50.0), stopped


def test_the_target_the_backend_took_is_read_on_the_sky_with_a_mount_model():
    # The controller's words are the dish's axes; with a mount model (docs/sky.md) the backend adds
    # the sky's, which is what a client compares with the target it sent.
    plain = ("Winegard Carryout G2: idle; [g2, 115200 baud, prompt MOT>]; position az 173.60 el 38.00 (read back); "
             "target az 173.60 el 38.00; el limits 18.00..65.00")
    assert named_target(plain) == (173.6, 38.0)
    mounted = plain + "; mount az_index 6.00 el_index 0.80 tilt_north 1.20 tilt_east -0.50; sky target az 180.00 el 40.00"
    assert named_target(mounted) == (180.0, 40.0)
    assert named_target("Winegard Carryout G2: idle") is None


# ---- the sky tools' reading of birdcage-track (a fake program: the machine interface's JSON) ----

FAKE_TRACK = str(Path(__file__).with_name("fixtures") / "fake-birdcage-track")


def fake_sky(**options) -> Sky:
    return Sky(SkyOptions(track_program=FAKE_TRACK, host="127.0.0.1", port=4599, **options))


async def test_a_track_is_followed_to_its_end_and_reports_its_outcome():
    sky = fake_sky()
    tracking = await sky.start_track("pass", None, False)
    samples = tracking.samples()
    await tracking.wait_started()
    assert tracking.plan is not None
    shown = [tracking.progress(event) async for event in samples]
    # Every event, in order: sky seconds since the plan's now, against the seconds from the plan to
    # its LOS (70).
    assert [s[0] for s in shown] == [5.0, 20.0, 30.0, 40.0], shown
    assert {s[1] for s in shown} == {70.0}
    assert "AOS in 5 s" in shown[0][2] and "LOS in 30 s" in shown[-1][2]
    result = tracking.result()
    assert (result.outcome, result.samples, result.rms_error_deg, result.interrupted_by) == ("los", 3, 0.12, None)
    assert result.target == "PASS" and result.last.error_deg == 0.30000000000000004
    assert sky.running is None


async def test_stop_tracking_ends_the_child_and_names_who_stopped_it(tmp_path, monkeypatch):
    monkeypatch.setenv("FAKE_TRACK_ARGS", str(tmp_path / "args.json"))
    sky = fake_sky(lat=45.0, lon=-93.0, tles=["a.tle"])
    tracking = await sky.start_track("forever", 120, True)
    await tracking.wait_started()
    with pytest.raises(ToolError, match=r"move_to refused: the dish is tracking forever .*call stop_tracking first"):
        sky.check_idle("move_to")
    await tracking.stop("stop_tracking")
    result = tracking.result()
    assert (result.outcome, result.interrupted_by) == ("interrupted", "stop_tracking"), result
    assert tracking.exit_status == 0
    sky.check_idle("move_to")  # nothing runs now
    given = json.loads((tmp_path / "args.json").read_text())
    assert given == ["--host", "127.0.0.1", "--port", "4599", "--lat", "45", "--lon", "-93", "--tle", "a.tle",
                     "--duration", "120", "--park-at-los", "--json", "forever"]


async def test_an_unknown_target_fails_in_the_programs_own_words():
    sky = fake_sky()
    tracking = await sky.start_track("nope", None, False)
    await tracking.wait_started()
    assert tracking.plan is None and not tracking.running
    assert tracking.why_failed() == "unknown target 'nope' (no satellite, body or radec:/azel: by that name)"
    assert tracking.result().outcome == "error"
    with pytest.raises(ToolError, match=r"^get_passes: birdcage-track: unknown target 'nope'"):
        await sky.query("--passes", "nope", what="get_passes")
    with pytest.raises(ToolError, match="is not a target"):
        await sky.start_track("--park-at-los", None, False)


async def test_a_missing_program_says_where_it_was_looked_for(monkeypatch):
    monkeypatch.setenv("PATH", "/nonexistent")
    with pytest.raises(ToolError, match=r"birdcage-track was not found on PATH.*--track-program PATH"):
        await Sky(SkyOptions()).query("--visible", what="get_visible_targets")


def test_the_rehearsal_clock_starts_at_its_time_and_runs_faster():
    clock = SkyClock(parse_time("2024-06-01T00:00:00Z"), 20)
    first = clock.args()
    assert first[0] == "--at" and first[1].startswith("2024-06-01T00:00:0") and first[2:] == ["--time-scale", "20"]
    assert parse_time(first[1]) >= parse_time("2024-06-01T00:00:00Z")
    assert SkyClock().args() == []
