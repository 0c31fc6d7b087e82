# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""What the server answers against what the rotator does (asked directly from rotctld, beside the
server): stop, interrupted moves, refused targets, failure reasons; and what it offers: the tool
list per rotator, annotations and output schemas."""

from __future__ import annotations

import re
import time

import anyio
import pytest

from conftest import Rig, rig, session_for
from test_server import TOOLS, call, call_error

pytestmark = pytest.mark.anyio

RECEIVER = {"read_signal", "set_lnb", "sky_scan", "align"}


def rest(rig: Rig, timeout: float = 30.0) -> tuple[float, float]:
    """Where the dish comes to rest, read from rotctld directly: no MOVING and two equal readings."""
    deadline = time.monotonic() + timeout
    last = None
    while time.monotonic() < deadline:
        now = rig.position()
        if not rig.moving() and now == last:
            return now
        last = now
        time.sleep(0.1)
    pytest.fail(f"the dish did not come to rest within {timeout:g} s")


def near(a: tuple[float, float], b: tuple[float, float], tolerance: float = 0.2) -> bool:
    return abs((a[0] - b[0] + 180) % 360 - 180) <= tolerance and abs(a[1] - b[1]) <= tolerance


async def start_long_leg(session, rig: Rig) -> None:
    """From az 100 to az 300 at el 30: one azimuth leg of 200 degrees through north (the cable wrap),
    about 3 s at real speed."""
    await call(session, "move_to", {"azimuth": 100.0, "elevation": 30.0})
    started = await call(session, "move_to", {"azimuth": 300.0, "elevation": 30.0, "wait": False})
    assert started["outcome"] == "moving"
    assert rig.moving()


async def test_stop_answers_stopped_only_at_rest_and_where_the_dish_is(g2_real):
    async with session_for(g2_real.port) as session:
        await start_long_leg(session, g2_real)
        stopped = await call(session, "stop")
        assert stopped["state"] == "stopped", stopped
        answered = (stopped["position"]["azimuth"], stopped["position"]["elevation"])
        # The rotator's own account, after the answer: at rest, where the answer says; the leg under
        # way finished (the firmware cannot abort it).
        assert not g2_real.moving()
        assert near(rest(g2_real), answered, 0.02), (rest(g2_real), stopped)
        assert near(answered, (300.0, 30.0)), stopped
        assert "finished the leg under way" in stopped["message"]


async def test_stop_that_cannot_wait_says_still_stopping_and_where_the_leg_ends(g2_real):
    async with session_for(g2_real.port) as session:
        await start_long_leg(session, g2_real)
        stopping = await call(session, "stop", {"wait_s": 0})
        assert stopping["state"] == "stopping", stopping
        assert stopping["leg_end"] == {"azimuth": 300.0, "elevation": 30.0}, stopping
        assert "still stopping" in stopping["message"] and "ends at az 300.00 el 30.00" in stopping["message"]
        assert g2_real.moving()
        assert near(rest(g2_real), (300.0, 30.0))


async def start_split_move(session, rig: Rig) -> None:
    """From az 150 to az 330 at el 30: 180 degrees either way round, which the backend turns in two
    legs, by 240 (docs/mcp.md, "Long azimuth moves"); returns once the first leg is under way."""
    await call(session, "move_to", {"azimuth": 150.0, "elevation": 30.0})
    started = await call(session, "move_to", {"azimuth": 330.0, "elevation": 30.0, "wait": False})
    assert started["outcome"] == "moving"
    with anyio.fail_after(10):
        while not rig.moving():
            await anyio.sleep(0.02)


async def test_stop_during_a_split_move_says_it_was_split_and_rests_at_the_waypoint(g2_real):
    async with session_for(g2_real.port) as session:
        await start_split_move(session, g2_real)
        stopped = await call(session, "stop")
        assert stopped["state"] == "stopped" and stopped["split"] is True, stopped
        assert near((stopped["position"]["azimuth"], stopped["position"]["elevation"]), (240.0, 30.0)), stopped
        assert near(rest(g2_real), (240.0, 30.0))
        assert "the move to az 330.00 el 30.00 was split" in stopped["message"], stopped
        # The waypoint is half-way from where the dish read when the leg was planned (e.g. 240.04).
        named = re.search(r"the end of the leg under way, az (\d+\.\d\d)", stopped["message"])
        assert named and abs(float(named.group(1)) - 240.0) <= 0.2, stopped
        # Not split: a move that goes in one leg.
        await call(session, "move_to", {"azimuth": 200.0, "elevation": 30.0, "wait": False})
        plain = await call(session, "stop")
        assert plain["split"] is False and "split" not in plain["message"], plain


async def test_stop_that_cannot_wait_during_a_split_move_names_the_waypoint_as_the_leg_end(g2_real):
    async with session_for(g2_real.port) as session:
        await start_split_move(session, g2_real)
        stopping = await call(session, "stop", {"wait_s": 0})
        assert stopping["state"] == "stopping" and stopping["split"] is True, stopping
        leg_end = stopping["leg_end"]
        assert near((leg_end["azimuth"], leg_end["elevation"]), (240.0, 30.0)), stopping
        assert "short of the move's target az 330.00 (the move was split" in stopping["message"], stopping
        assert near(rest(g2_real), (240.0, 30.0))


async def concurrently(session, first: tuple[str, dict], then: tuple[str, dict], rig: Rig) -> tuple[dict, dict]:
    """Calls `first`, and `then` once the dish is seen moving; returns both answers."""
    answers: dict[str, dict] = {}

    async def run(key: str, name: str, arguments: dict) -> None:
        answers[key] = await call(session, name, arguments)

    async with anyio.create_task_group() as group:
        group.start_soon(run, "first", *first)
        with anyio.fail_after(10):
            while not rig.moving():
                await anyio.sleep(0.02)
        group.start_soon(run, "then", *then)
    return answers["first"], answers["then"]


async def test_move_to_interrupted_by_stop_says_interrupted(g2_real):
    async with session_for(g2_real.port) as session:
        await call(session, "move_to", {"azimuth": 100.0, "elevation": 30.0})
        moved, stopped = await concurrently(session, ("move_to", {"azimuth": 300.0, "elevation": 50.0}),
                                            ("stop", {}), g2_real)
        assert moved["outcome"] == "interrupted" and moved["interrupted_by"] == "stop", moved
        assert moved["clamped"] is False and moved["at_target"] is False
        assert "interrupted by stop" in moved["notes"][0]
        assert stopped["state"] == "stopped"
        assert near(rest(g2_real), (stopped["position"]["azimuth"], stopped["position"]["elevation"]), 0.02)


async def test_move_to_interrupted_by_another_move_to_says_by_which(g2_real):
    async with session_for(g2_real.port) as session:
        await call(session, "move_to", {"azimuth": 100.0, "elevation": 30.0})
        first, second = await concurrently(session, ("move_to", {"azimuth": 300.0, "elevation": 50.0}),
                                           ("move_to", {"azimuth": 120.0, "elevation": 40.0}), g2_real)
        assert first["outcome"] == "interrupted", first
        assert first["interrupted_by"] == "move_to(azimuth=120, elevation=40)"
        assert second["outcome"] == "arrived", second
        assert near(rest(g2_real), (120.0, 40.0))


async def test_move_to_interrupted_by_another_client_says_so(g2_real):
    g2 = g2_real
    async with session_for(g2.port) as session:
        await call(session, "move_to", {"azimuth": 100.0, "elevation": 30.0})
        answers = {}

        async def move() -> None:
            answers["move"] = await call(session, "move_to", {"azimuth": 300.0, "elevation": 50.0})

        async with anyio.create_task_group() as group:
            group.start_soon(move)
            with anyio.fail_after(10):
                while not g2.moving():
                    await anyio.sleep(0.01)
            await anyio.sleep(0.3)
            g2.ask("P 150.00 40.00")  # as Gpredict would, while the dish turns
        moved = answers["move"]
        assert moved["outcome"] == "interrupted", moved
        assert moved["interrupted_by"] == "another rotctld client's target az 150.00 el 40.00"
        assert near((moved["position"]["azimuth"], moved["position"]["elevation"]), (150.0, 40.0))


async def test_targets_outside_the_range_are_refused_with_the_limits_named(g2):
    async with session_for(g2.port) as session:
        before = g2.position()
        cases = {
            (541.0, 40.0): "move_to: azimuth 541 is outside this rotator's range -180..540; nothing was sent",
            (150.0, 80.0): "move_to: elevation 80 is outside this rotator's range 18..65; nothing was sent",
            (150.0, 10.0): "move_to: elevation 10 is outside this rotator's range 18..65; nothing was sent",
            (1e308, 40.0): "move_to: azimuth 1e+308 is outside this rotator's range -180..540; nothing was sent",
        }
        for (az, el), expected in cases.items():
            text = await call_error(session, "move_to", {"azimuth": az, "elevation": el})
            assert text.removeprefix("Error executing tool ") == expected
        assert g2.position() == before and not g2.moving()
        text = await call_error(session, "move_to", {"azimuth": "north", "elevation": 40.0})
        assert text == "move_to: azimuth must be a number, got 'north'"
        text = await call_error(session, "move_to", {"elevation": 40.0})
        assert text == "move_to: azimuth is required"


async def test_a_target_the_backend_clamps_says_clamped_and_where(workdir):
    # az_min/az_max (backend conf) clamp azimuth targets; rotctld cannot read them back, but the
    # backend's description names the target it took.
    with rig(workdir, 90105, "g2", "pointing=none,az_min=90,az_max=270") as g2:
        async with session_for(g2.port) as session:
            moved = await call(session, "move_to", {"azimuth": 300.0, "elevation": 30.0})
            assert moved["outcome"] == "clamped" and moved["clamped"] is True and moved["at_target"] is False, moved
            assert moved["notes"] == ["the backend clamped the target to az 270.00 el 30.00 (its az_min/az_max conf, "
                                      "which rotctld cannot read back)"]
            assert near(rest(g2), (270.0, 30.0))
            moved = await call(session, "move_to", {"azimuth": 200.0, "elevation": 40.0})
            assert moved["outcome"] == "arrived" and moved["clamped"] is False, moved


async def test_the_dummy_rotators_range_comes_from_its_caps(dummy):
    async with session_for(dummy.port) as session:
        text = await call_error(session, "move_to", {"azimuth": 540.0, "elevation": 10.0})
        assert "azimuth 540 is outside this rotator's range -180..450" in text


async def test_an_unwritable_csv_path_says_why_and_moves_nothing(g2, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a directory\n")
    async with session_for(g2.port) as session:
        before = g2.position()
        text = await call_error(session, "sky_scan", {"az_min": 170, "az_max": 174, "el_min": 40, "el_max": 44,
                                                      "step": 4, "csv_path": str(blocker / "scan.csv")})
        assert f"cannot write the scan's CSV to {blocker / 'scan.csv'}: Not a directory" in text, text
        assert g2.position() == before


async def test_tools_carry_annotations_and_output_schemas(g2):
    async with session_for(g2.port) as session:
        tools = {t.name: t for t in (await session.list_tools()).tools}
        reading = {"get_position", "get_status", "get_info", "get_limits", "read_signal", "get_conf",
                   "search_satellites", "get_passes", "get_next_pass", "get_visible_targets", "get_tracking"}
        for name, tool in tools.items():
            assert tool.annotations is not None, name
            assert tool.annotations.read_only_hint is (name in reading), name
            assert tool.annotations.open_world_hint is False, name
            assert tool.output_schema and tool.output_schema["type"] == "object", name
        assert tools["home"].annotations.destructive_hint is True
        assert tools["move_to"].annotations.destructive_hint is False
        assert tools["move_to"].annotations.idempotent_hint is True
        assert tools["sky_scan"].annotations.idempotent_hint is False
        assert tools["track"].annotations.idempotent_hint is False
        assert tools["track"].annotations.destructive_hint is False
        assert set(tools["track"].output_schema["properties"]) >= {"outcome", "interrupted_by", "rms_error_deg"}
        assert set(tools["move_to"].output_schema["properties"]) >= {"outcome", "position", "interrupted_by"}
        assert tools["set_lnb"].input_schema["properties"]["volts"]["enum"] == [13, 18]
        assert "pointing" in tools["get_conf"].input_schema["properties"]["key"]["enum"]


async def test_tools_offered_follow_the_rotator(g2, travler, dummy, workdir):
    async with session_for(g2.port) as session:
        assert {t.name for t in (await session.list_tools()).tools} == TOOLS
    async with session_for(travler.port) as session:
        # No tuner, and no homing: the backend's caps for a Trav'ler say "Can Reset: N".
        assert {t.name for t in (await session.list_tools()).tools} == TOOLS - RECEIVER - {"home"}
        assert set((await call(session, "get_info"))["tools"]) == TOOLS - RECEIVER - {"home"}
    async with session_for(dummy.port) as session:
        assert {t.name for t in (await session.list_tools()).tools} == TOOLS - RECEIVER - {"get_conf"}


async def test_the_tool_list_is_checked_again_on_reconnect(workdir):
    g2 = Rig(workdir, 90105, "g2", "pointing=none").start()
    try:
        async with session_for(g2.port) as session:
            assert RECEIVER <= {t.name for t in (await session.list_tools()).tools}
            g2.close()  # another rotator behind the same port
            dummy = Rig(workdir, 1, None, port=g2.port).start()
            try:
                await call(session, "get_position")
                assert not RECEIVER & {t.name for t in (await session.list_tools()).tools}
            finally:
                dummy.close()
    finally:
        g2.close()
