# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""birdcage-mcp through the MCP SDK's client session (stdio), against rotctld + the emulator."""

from __future__ import annotations

import csv
import json
import time

import anyio
import pytest

from conftest import Rig, free_port, session_for

pytestmark = pytest.mark.anyio

SKY_TOOLS = {"search_satellites", "get_passes", "get_next_pass", "get_visible_targets", "track", "stop_tracking",
             "get_tracking", "align"}
TOOLS = {"get_position", "move_to", "stop", "park", "home", "get_status", "get_info", "get_limits",
         "read_signal", "set_lnb", "get_conf", "sky_scan"} | SKY_TOOLS


async def call(session, name, arguments=None, progress=None):
    result = await session.call_tool(name, arguments or {}, progress_callback=progress)
    assert not result.is_error, f"{name}({arguments}) failed: {result.content[0].text}"
    return result.structured_content


async def call_error(session, name, arguments=None) -> str:
    result = await session.call_tool(name, arguments or {})
    assert result.is_error, f"{name}({arguments}) should have failed, returned {result.structured_content}"
    return result.content[0].text


async def wait_at_rest(session, timeout=60.0):
    """Until get_status says neither MOVING nor BUSY (homing)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        status = await call(session, "get_status")
        if not status["moving"] and not status["busy"]:
            return status
    pytest.fail(f"the dish was still moving after {timeout:g} s")


# ---- what the server offers ----

async def test_lists_tools_with_schemas_resources_and_prompts(g2):
    async with session_for(g2.port) as session:
        tools = {t.name: t for t in (await session.list_tools()).tools}
        assert set(tools) == TOOLS
        move = tools["move_to"].input_schema
        assert set(move["required"]) == {"azimuth", "elevation"}
        assert move["properties"]["azimuth"]["type"] == "number"
        assert tools["read_signal"].input_schema["properties"]["samples"]["maximum"] == 100
        assert set(tools["sky_scan"].input_schema["required"]) == {"az_min", "az_max", "el_min", "el_max", "step"}
        for tool in tools.values():
            assert tool.description, f"{tool.name} has no description"
        assert "console" not in " ".join(tools)  # no raw-console tool
        uris = {str(r.uri) for r in (await session.list_resources()).resources}
        assert uris == {"birdcage://position", "birdcage://limits", "birdcage://info"}
        prompts = {p.name for p in (await session.list_prompts()).prompts}
        assert prompts == {"first_setup", "sky_scan_guide", "tracking_guide"}
        tracking_guide = await session.get_prompt("tracking_guide", {"target": "NOAA 19"})
        assert "NOAA 19" in tracking_guide.messages[0].content.text
        assert "Gpredict is the usual tracker" in tracking_guide.messages[0].content.text
        guide = await session.get_prompt("first_setup", {})
        assert "get_limits" in guide.messages[0].content.text
        scan_guide = await session.get_prompt("sky_scan_guide", {"region": "the Clarke belt"})
        assert "the Clarke belt" in scan_guide.messages[0].content.text


# ---- every tool against an emulated Carryout G2 ----

async def test_info_limits_and_conf_of_a_g2(g2):
    async with session_for(g2.port) as session:
        info = await call(session, "get_info")
        assert info["manufacturer"] == "Winegard"
        assert info["model"] == 90105
        assert info["model_name"] == "Carryout G2"
        assert info["winegard_extras"] is True
        assert "Carryout G2" in info["info"] and "pointing none" in info["info"]
        limits = await call(session, "get_limits")
        assert (limits["el_min"], limits["el_max"]) == (18.0, 65.0)
        assert limits["model"] == 90105
        assert (await call(session, "get_conf", {"key": "pointing"}))["value"] == "none"
        assert (await call(session, "get_conf", {"key": "el_max"}))["value"] == "65.00"
        assert (await call(session, "get_conf", {"key": "variant"}))["value"] == "g2"
        text = await call_error(session, "get_conf", {"key": "time_scale"})
        assert "cannot be read back" in text and "-C time_scale=" in text
        text = await call_error(session, "get_conf", {"key": "colour"})
        assert text.startswith("get_conf: key must be 'variant', 'pointing'") and text.endswith("got 'colour'"), text


async def test_resources_read_as_json(g2):
    async with session_for(g2.port) as session:
        position = json.loads((await session.read_resource("birdcage://position")).contents[0].text)
        assert set(position) == {"azimuth", "elevation"}
        limits = json.loads((await session.read_resource("birdcage://limits")).contents[0].text)
        assert limits["el_max"] == 65.0
        info = json.loads((await session.read_resource("birdcage://info")).contents[0].text)
        assert info["manufacturer"] == "Winegard"


async def test_move_to_settles_at_the_target_with_progress(g2):
    async with session_for(g2.port) as session:
        before = await call(session, "get_position")
        target = (before["azimuth"] + 20.0) % 360.0, 40.0 if abs(before["elevation"] - 40.0) > 5 else 50.0
        progress = []

        async def on_progress(done, total, message):
            progress.append((done, total, message))

        moved = await call(session, "move_to", {"azimuth": target[0], "elevation": target[1]}, on_progress)
        assert moved["settled"] is True and moved["at_target"] is True
        assert moved["outcome"] == "arrived" and moved["notes"] == []
        assert abs(moved["position"]["azimuth"] - target[0]) <= 0.2
        assert abs(moved["position"]["elevation"] - target[1]) <= 0.2
        now = await call(session, "get_position")
        assert abs(now["azimuth"] - target[0]) <= 0.2 and abs(now["elevation"] - target[1]) <= 0.2
        assert progress, "no progress notification during a 20 degree move"
        assert all(0 < done <= total for done, total, _ in progress)
        assert [p[0] for p in progress] == sorted({p[0] for p in progress}), "progress must increase"
        status = await call(session, "get_status")
        assert status["moving"] is False and status["flags"] == []




async def test_park_and_home(g2):
    async with session_for(g2.port) as session:
        await call(session, "move_to", {"azimuth": 130.0, "elevation": 45.0})
        parking = await call(session, "park")
        assert parking["parking"] is True
        await wait_at_rest(session)
        parked = await call(session, "get_position")
        assert (round(parked["azimuth"], 1), round(parked["elevation"], 1)) != (130.0, 45.0)
        homing = await call(session, "home")
        assert homing["homing"] is True
        assert homing["status"] == ["BUSY", "MOVING"]
        await wait_at_rest(session, timeout=120)
        # A homed dish moves again.
        moved = await call(session, "move_to", {"azimuth": 160.0, "elevation": 35.0})
        assert moved["outcome"] == "arrived"


async def test_signal_and_lnb(g2):
    async with session_for(g2.port) as session:
        await call(session, "move_to", {"azimuth": 174.0, "elevation": 44.0})  # DIRECTV 9S in the emulator's sky
        assert (await call(session, "set_lnb", {"volts": 13}))["lnb_volts"] == 13.0
        on_satellite = await call(session, "read_signal", {"samples": 20})
        assert on_satellite["samples"] == 20
        await call(session, "move_to", {"azimuth": 174.0, "elevation": 60.0})
        off_satellite = await call(session, "read_signal", {"samples": 20})
        assert on_satellite["rssi"] > off_satellite["rssi"] + 50
        assert (await call(session, "set_lnb", {"volts": 18}))["lnb_volts"] == 18.0
        assert await call_error(session, "set_lnb", {"volts": 12}) == "set_lnb: volts must be 13 or 18, got 12"
        assert await call_error(session, "read_signal", {"samples": 0}) == \
            "read_signal: samples must be greater than or equal to 1, got 0"
        await call(session, "set_lnb", {"volts": 13})


async def test_sky_scan_reports_progress_and_finds_the_satellite(g2, tmp_path):
    async with session_for(g2.port) as session:
        progress = []

        async def on_progress(done, total, message):
            progress.append((done, total, message))

        out = tmp_path / "scan.csv"
        # 9 x 5 points around DIRECTV 9S (174/44 in the emulator's sky at 13 V): wide enough that
        # most points see the floor, which the peak threshold is measured from.
        grid = {"az_min": 158, "az_max": 190, "el_min": 40, "el_max": 56, "step": 4}
        result = await call(session, "sky_scan", {**grid, "samples": 5, "lnb_volts": 13, "csv_path": str(out)},
                            on_progress)
        assert result["points"] == 45
        assert result["csv"] == str(out)
        assert [p[0] for p in progress] == list(range(1, 46))
        assert all(total == 45 for _, total, _ in progress)
        assert progress[0][2].startswith("az 158.00 el 40.00 value ")
        with open(out) as file:
            rows = list(csv.DictReader(file))
        assert len(rows) == 45 and set(rows[0]) == {"az", "el", "value", "time"}
        # serpentine: up the first column, down the second
        assert [(r["az"], r["el"]) for r in rows[:6]] == [
            ("158.00", "40.00"), ("158.00", "44.00"), ("158.00", "48.00"), ("158.00", "52.00"), ("158.00", "56.00"),
            ("162.00", "56.00")]
        assert result["peaks"], f"no peak found: {rows}"
        best = result["peaks"][0]
        assert (best["azimuth"], best["elevation"]) == (174.0, 44.0)
        assert best["value"] == max(float(r["value"]) for r in rows)
        assert result["strongest"] == best
        text = await call_error(session, "sky_scan", {**grid, "el_min": 10})
        assert "el_min 10 is outside the dish's range 18..65" in text


# ---- error paths ----

async def test_rotctld_down_is_a_clear_error_and_a_restart_is_picked_up(g2):
    async with session_for(g2.port) as session:
        await call(session, "get_position")
        g2.stop_rotctld()
        try:
            for tool in ("get_position", "get_status", "get_info", "get_limits", "stop"):
                text = await call_error(session, tool)
                assert f"cannot reach rotctld at 127.0.0.1:{g2.port}" in text, text
            text = await call_error(session, "move_to", {"azimuth": 100.0, "elevation": 30.0})
            assert "is rotctld running" in text
        finally:
            g2.restart_rotctld()
        assert set(await call(session, "get_position")) == {"azimuth", "elevation"}


async def test_another_rotator_after_a_reconnect_is_announced_as_a_changed_tool_list(workdir):
    """The server declares tools.listChanged and keeps the promise: when rotctld comes back on the
    same port with another rotator (a Trav'ler, then a Carryout G2 with its tuner), the next tool
    call sends notifications/tools/list_changed; calls with the same rotator send none."""
    changed = []
    announced = anyio.Event()

    async def on_message(message):
        if getattr(message, "method", None) == "notifications/tools/list_changed":
            changed.append(message)
            announced.set()

    port = free_port()
    travler = Rig(workdir, 90102, "hal205", port=port).start()
    g2 = None
    try:
        async with session_for(port, on_message) as session:
            initialised = await session.initialize()  # the session keeps the handshake's result
            assert initialised.capabilities.tools.list_changed is True
            listed = {t.name for t in (await session.list_tools()).tools}
            assert "get_conf" in listed and not listed & {"read_signal", "set_lnb", "sky_scan"}, listed
            await call(session, "get_position")
            assert changed == []
            travler.close()
            assert "cannot reach rotctld" in await call_error(session, "get_position")
            g2 = Rig(workdir, 90105, "g2", port=port).start()
            await call(session, "get_position")
            with anyio.fail_after(10):
                await announced.wait()
            assert {t.name for t in (await session.list_tools()).tools} == TOOLS
            await call(session, "get_status")
            assert len(changed) == 1
    finally:
        travler.close()
        if g2:
            g2.close()


async def test_nothing_listening():
    port = free_port()
    async with session_for(port) as session:
        text = await call_error(session, "get_position")
        assert f"cannot reach rotctld at 127.0.0.1:{port}" in text and "connection refused" in text
        resource = None
        with pytest.raises(Exception) as raised:
            resource = await session.read_resource("birdcage://position")
        assert resource is None and "cannot reach rotctld" in str(raised.value)


async def test_a_winegard_without_tuner_answers_signal_with_no_tuner(travler):
    async with session_for(travler.port) as session:
        info = await call(session, "get_info")
        assert info["model"] == 90102 and info["winegard_extras"] is True
        for tool, args in (("read_signal", {}), ("set_lnb", {"volts": 13}),
                           ("sky_scan", {"az_min": 100, "az_max": 104, "el_min": 30, "el_max": 34, "step": 2})):
            text = await call_error(session, tool, args)
            assert "not offered by this rotator" in text and "RPRT -11" in text, text
        assert "homing is not offered by this rotator" in await call_error(session, "home")
        moved = await call(session, "move_to", {"azimuth": 104.0, "elevation": 33.0})
        assert moved["outcome"] == "arrived"


async def test_a_non_winegard_rotator_has_no_winegard_extras(dummy):
    async with session_for(dummy.port) as session:
        info = await call(session, "get_info")
        assert info["model"] == 1 and info["winegard_extras"] is False and "RSSI" not in info["levels"]
        limits = await call(session, "get_limits")
        assert (limits["az_min"], limits["az_max"], limits["el_min"], limits["el_max"]) == (-180.0, 450.0, 0.0, 90.0)
        for tool, args in (("read_signal", {"samples": 3}), ("set_lnb", {"volts": 18}), ("get_conf", {"key": "pointing"}),
                           ("sky_scan", {"az_min": 0, "az_max": 2, "el_min": 10, "el_max": 12, "step": 2})):
            text = await call_error(session, tool, args)
            assert f"{tool} is not offered by this rotator" in text, text
        started = await call(session, "move_to", {"azimuth": 10.0, "elevation": 5.0, "wait": False})
        assert started["requested"] == {"azimuth": 10.0, "elevation": 5.0}
        await call(session, "stop")
