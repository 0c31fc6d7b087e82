// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The TUI's model (RotctldClient, Station) against the stock rotctld with the backend preloaded and
// the emulated dish: what the screens show comes from these answers.
#include "scan_launcher.hpp"
#include "sky_tracker.hpp"
#include "station.hpp"

#include "harness.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

using namespace std::chrono_literals;
namespace tui = birdcage::tui;
using birdcage::sim::Variant;

namespace {

bool contains(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

TEST_CASE("the client reads a G2's position, status, info, caps and levels through rotctld") {
    e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0, 20.0), 90105, {"-C", "time_scale=20"});
    birdcage::rotctl::Client client("127.0.0.1", rig.port());
    std::string why;
    REQUIRE(client.connect(&why));

    double az = 0, el = 0;
    REQUIRE(client.get_position(az, el) == 0);
    CHECK(az == Approx(100.0).margin(0.05));
    CHECK(el == Approx(30.0).margin(0.05));

    tui::RotatorCaps caps;
    REQUIRE(client.get_caps(caps) == 0);
    CHECK(caps.model.find("G2") != std::string::npos);
    CHECK(caps.can_reset);
    CHECK(caps.can_park);

    std::vector<std::string> levels;
    REQUIRE(client.ext_levels(levels) == 0);
    CHECK(contains(levels, "RSSI"));
    CHECK(contains(levels, "LNB"));
    double rssi = -1;
    CHECK(client.get_level("RSSI", rssi) == 0);
    CHECK(rssi >= 0.0);
    CHECK(client.set_level("LNB", 13) == 0);
    double lnb = 0;
    REQUIRE(client.get_level("LNB", lnb) == 0);
    CHECK(lnb == 13.0);

    REQUIRE(caps.levels.size() == 3);
    CHECK(caps.levels[2].name == "LNB");
    CHECK(caps.levels[2].range == "13..18/5");

    std::string info;
    CHECK(client.get_info(info) == 0);
    CHECK(info.find("[g2,") != std::string::npos);  // the variant in force

    std::string flags = "?";
    CHECK(client.get_status(flags) == 0);
    CHECK(flags.empty());  // at rest
    CHECK(tui::squeeze_flags(flags) == "idle");
    CHECK(tui::squeeze_flags("BUSY MOVING BUSY MOVING ") == "BUSY MOVING");
    tui::Limits limits;
    REQUIRE(client.get_limits(limits) == 0);
    CHECK(limits.max_el > limits.min_el);
    CHECK_FALSE(client.peer_closed());
}

TEST_CASE("a Trav'ler lists the levels but has no RSSI, and the station says so") {
    e2e::Rig rig(e2e::dish_options(Variant::travler_hal205, 100.0, 30.0, 20.0), 90102, {"-C", "time_scale=20"});
    birdcage::rotctl::Client client("127.0.0.1", rig.port());
    std::string why;
    REQUIRE(client.connect(&why));
    double rssi = 0;
    CHECK(client.get_level("RSSI", rssi) != 0);
    std::string info;
    CHECK(client.get_info(info) == 0);
    CHECK(info.find("[hal205,") != std::string::npos);
    tui::RotatorCaps caps;
    CHECK(client.get_caps(caps) == 0);
    CHECK(caps.model.find("Trav") != std::string::npos);
    CHECK_FALSE(caps.can_reset);  // it has no homing: the info screen must not offer home(R)
    client.disconnect();

    // The signal screen: the levels are listed (the models share them), the reading says why not.
    tui::Station station("127.0.0.1", rig.port());
    station.watch_signal(true);
    REQUIRE(e2e::wait_until([&] { return !station.snapshot().signal_error.empty(); }, 20s));
    const tui::Snapshot s = station.snapshot();
    CHECK(contains(s.levels, "RSSI"));
    CHECK_FALSE(s.rssi);
    CHECK(s.signal_error == "Feature not available");
}

TEST_CASE("the station moves the dish, and notices rotctld going away") {
    auto rig = std::make_unique<e2e::Rig>(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0, 20.0), 90105,
                                          std::vector<std::string>{"-C", "time_scale=20"});
    tui::Station station("127.0.0.1", rig->port());
    REQUIRE(e2e::wait_until([&] { return station.snapshot().link == tui::LinkState::connected; }, 30s));
    REQUIRE(e2e::wait_until([&] { return station.snapshot().position.has_value(); }, 10s));
    const tui::Snapshot first = station.snapshot();
    CHECK(first.caps.can_reset);
    CHECK(first.info.find("[g2,") != std::string::npos);
    CHECK(contains(first.levels, "RSSI"));

    station.submit({tui::Command::Kind::move, 200.0, 35.0, {}});
    const bool arrived = e2e::wait_until(
        [&] {
            const auto p = station.snapshot().position;
            return p && std::abs(p->first - 200.0) < 0.1 && std::abs(p->second - 35.0) < 0.1;
        },
        60s);
    CHECK(arrived);
    CHECK(e2e::settled_at(rig->dish(), 200.0, 35.0, 0.2));
    const tui::Snapshot moved = station.snapshot();
    REQUIRE(moved.target);
    CHECK(moved.target->first == 200.0);
    CHECK(moved.last_result == "P 200.00 35.00: ok");
    station.watch_signal(true);
    REQUIRE(e2e::wait_until([&] { return station.snapshot().rssi && station.snapshot().lnb; }, 20s));

    rig.reset();  // rotctld exits
    CHECK(e2e::wait_until([&] { return station.snapshot().link == tui::LinkState::reconnecting; }, 10s));
    const tui::Snapshot gone = station.snapshot();
    CHECK_FALSE(gone.position);  // not shown as if current
    // Nothing of the dead link stays on any screen: no RSSI, LNB or trend, no last "ok".
    CHECK_FALSE(gone.rssi);
    CHECK_FALSE(gone.lnb);
    CHECK(gone.rssi_trend.empty());
    CHECK(gone.last_result.empty());
    // Typed while rotctld is away: not queued for later.
    station.submit({tui::Command::Kind::move, 10.0, 10.0, {}});
    CHECK(e2e::wait_until([&] { return station.snapshot().last_result.find("not sent") != std::string::npos; }, 10s));
    CHECK(station.snapshot().link_detail.find("retrying in") != std::string::npos);
}

TEST_CASE("a jog starts from where the dish is now, not from a target another client has replaced") {
    // A jog from this client's old target: after `g 174 44` here and Gpredict's `P 120 30`, one
    // right-arrow sent P 175 44, a 55 deg swing (docs/tui.md, "Keys").
    e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0, 20.0), 90105, {"-C", "time_scale=20"});
    tui::Station station("127.0.0.1", rig.port());
    REQUIRE(e2e::wait_until([&] { return station.snapshot().link == tui::LinkState::connected; }, 30s));
    station.submit({tui::Command::Kind::move, 174.0, 44.0, {}});
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 174.0, 44.0, 0.2); }, 60s));

    e2e::RotctldConnection other(rig.port());  // another client moves the dish
    REQUIRE(other.ask("P 120 30", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, 30.0, 0.2); }, 60s));
    // The user presses the key once the screen shows the dish there: on a loaded machine the
    // backend's reading can trail the emulator's settled dish by a poll (el 30.64 under ASan).
    REQUIRE(e2e::wait_until(
        [&] {
            const auto at = station.snapshot().position;
            return at && std::fabs(at->first - 120.0) <= 0.2 && std::fabs(at->second - 30.0) <= 0.2;
        },
        30s));

    station.submit({tui::Command::Kind::jog, 1.0, 0.0, {}});
    REQUIRE(e2e::wait_until(
        [&] {
            return station.snapshot().last_result.rfind("P ", 0) == 0 &&
                   station.snapshot().last_result.find("121.") != std::string::npos;
        },
        10s));
    const auto target = station.snapshot().target;
    REQUIRE(target);
    CHECK(target->first == Approx(121.0).margin(0.2));
    CHECK(target->second == Approx(30.0).margin(0.2));
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 121.0, 30.0, 0.3); }, 60s));
}

TEST_CASE("a target outside the rotator's range is refused with the range named, never clamped") {
    tui::Limits limits{-180, 540, 0, 90};
    CHECK(tui::out_of_range(limits, 999, 40) == "az 999.00 is outside -180.00..540.00");
    CHECK(tui::out_of_range(limits, 200, 95) == "el 95.00 is outside 0.00..90.00");
    CHECK(tui::out_of_range(limits, 540, 90).empty());

    e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0, 20.0), 90105, {"-C", "time_scale=20"});
    tui::Station station("127.0.0.1", rig.port());
    REQUIRE(e2e::wait_until([&] { return station.snapshot().link == tui::LinkState::connected; }, 30s));
    station.submit({tui::Command::Kind::move, 999.0, 40.0, {}});
    REQUIRE(e2e::wait_until([&] { return !station.snapshot().last_result.empty(); }, 10s));
    const tui::Snapshot s = station.snapshot();
    CHECK(s.last_result.find("P 999.00 40.00: refused, az 999.00 is outside ") == 0);
    CHECK_FALSE(s.target);
    // Nothing went to rotctld: the dish stays where it was.
    CHECK(e2e::settled_at(rig.dish(), 100.0, 30.0, 0.2));
    CHECK_FALSE(rig.dish().moving());
}

TEST_CASE("the scan launcher runs birdcage-skyscan through rotctld and follows its progress") {
    e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 180.0, 40.0, 20.0), 90105,
                 {"-C", "time_scale=20", "-C", "pointing=none"});
    char dir_template[] = "/tmp/birdcage-tui-scan.XXXXXX";
    REQUIRE(mkdtemp(dir_template) != nullptr);
    const std::string csv = std::string(dir_template) + "/scan.csv";
    tui::ScanLauncher scan;
    std::string why;
    REQUIRE(scan.start(BIRDCAGE_SKYSCAN_PATH,
                       {"--host", "127.0.0.1", "--port", std::to_string(rig.port()), "--az", "178:182:2", "--el",
                        "40:42:2", "--samples", "2", "--out", csv},
                       &why));
    CHECK(scan.running());
    const bool ended = e2e::wait_until(
        [&] {
            scan.pump();
            return !scan.running();
        },
        120s);
    REQUIRE(ended);
    CHECK(scan.exit_status == 0);
    CHECK(scan.total == 6);
    CHECK(scan.done == 6);
    CHECK(scan.progress.find("done, 6 points") != std::string::npos);
    std::ifstream in(csv);
    int rows = 0;
    for (std::string line; std::getline(in, line);) {
        rows += line.find(',') != std::string::npos && line.find("az") != 0 ? 1 : 0;
    }
    CHECK(rows == 6);
    std::remove(csv.c_str());
    rmdir(dir_template);
}

TEST_CASE("the scan launcher reports a program that cannot run and one that fails") {
    tui::ScanLauncher scan;
    std::string why;
    CHECK_FALSE(scan.start("/nonexistent/birdcage-skyscan", {}, &why));
    CHECK(why.find("cannot run") != std::string::npos);
    REQUIRE(scan.start("/bin/sh", {"-c", "printf 'birdcage-skyscan: cannot connect to rotctld\\n' >&2; exit 1"}, &why));
    REQUIRE(e2e::wait_until(
        [&] {
            scan.pump();
            return !scan.running();
        },
        10s));
    CHECK(scan.exit_status == 1);
    CHECK(scan.progress == "birdcage-skyscan: cannot connect to rotctld");
    CHECK(scan.outcome() == "failed with status 1");
}

TEST_CASE("a scan ended with x says it was stopped, not that it failed with status 143") {
    tui::ScanLauncher scan;
    std::string why;
    REQUIRE(scan.start("/bin/sh", {"-c", "exec sleep 60"}, &why));
    CHECK(scan.outcome() == "running, x stops it");
    scan.cancel();
    REQUIRE(e2e::wait_until(
        [&] {
            scan.pump();
            return !scan.running();
        },
        10s));
    CHECK(scan.exit_status == 143);
    CHECK(scan.outcome() == "scan stopped");
}

// ---- the sky screen's reading of birdcage-track (docs/sky.md's machine interface) ----------------

TEST_CASE("the JSON reader takes the machine interface's shapes and refuses what is not JSON") {
    const auto visible = tui::parse_json(
        R"({"time":"2024-06-01T00:00:00Z","targets":[{"name":"sun","kind":"sun","az":280.5,"el":20.1,"in_window":true},)"
        R"({"name":"ISS \"Z\" \u00e9","kind":"satellite","az":-1.5e1,"el":19,"in_window":false},)"
        R"({"name":"moon","kind":"moon","az":100,"el":40,"in_window":true}]})");
    REQUIRE(visible);
    const auto targets = tui::visible_targets(*visible);
    REQUIRE(targets.size() == 3);
    // In the window first, then the highest.
    CHECK(targets[0].name == "moon");
    CHECK(targets[1].name == "sun");
    CHECK(targets[2].name == "ISS \"Z\" \xc3\xa9");
    CHECK(targets[2].az == -15.0);
    CHECK_FALSE(targets[2].in_window);
    std::string why;
    CHECK_FALSE(tui::parse_json(R"({"a":1,})", &why));
    CHECK(why.find("member name") != std::string::npos);
    CHECK_FALSE(tui::parse_json("{\"a\":1} trailing"));
    CHECK_FALSE(tui::parse_json("[1, nul]"));
    CHECK(tui::parse_iso_time("2024-06-01T00:03:41Z") == Approx(1717200221.0));
    CHECK(tui::parse_iso_time("2024-06-01T00:03:41.250Z") == Approx(1717200221.25));
    CHECK_FALSE(tui::parse_iso_time("yesterday"));
    CHECK(tui::iso_time(1717200221.25) == "2024-06-01T00:03:41.250Z");
}

TEST_CASE("a track is followed event by event, and a stop ends it as interrupted") {
    // A stand-in speaking the JSON lines; the tmux test drives the real program.
    const std::string script = BIRDCAGE_TUI_FIXTURES "/track-events.sh";
    tui::Tracker tracker;
    std::string why;
    REQUIRE(tracker.start("/bin/sh", {script}, "iss", &why));
    CHECK(tracker.phase == "starting");
    REQUIRE(e2e::wait_until(
        [&] {
            tracker.pump();
            return tracker.phase == "tracking";
        },
        10s));
    CHECK(tracker.target == "ISS (ZARYA)");
    CHECK(tracker.los == "2024-06-01T00:08:06Z");
    CHECK(tracker.aim == std::make_pair(313.75, 18.0));
    CHECK(tracker.dish_position == std::make_pair(313.9, 19.4));
    CHECK(tracker.error_deg == Approx(0.12));
    CHECK(tracker.seconds_to_los == Approx(256));
    tracker.cancel();
    REQUIRE(e2e::wait_until(
        [&] {
            tracker.pump();
            return !tracker.running();
        },
        10s));
    CHECK(tracker.phase == "interrupted");
    CHECK(tracker.stopped);
    CHECK(tracker.samples == 7);
    CHECK(tracker.rms_error_deg == Approx(0.2));
    CHECK(tracker.reason == "stopped; sent S");
}

TEST_CASE("a track that cannot start says why in the program's own words") {
    tui::Tracker tracker;
    std::string why;
    CHECK_FALSE(tracker.start("/nonexistent/birdcage-track", {}, "iss", &why));
    CHECK(why.find("cannot run") != std::string::npos);
    REQUIRE(tracker.start(
        "/bin/sh", {"-c", "echo \"birdcage-track: unknown target '$2'\" >&2; exit 1", "birdcage-track"}, "nope", &why));
    REQUIRE(e2e::wait_until(
        [&] {
            tracker.pump();
            return !tracker.running();
        },
        10s));
    CHECK(tracker.phase == "error");
    CHECK(tracker.reason == "birdcage-track: unknown target 'nope'");
    tui::SkyQuery query;
    REQUIRE(query.start("/bin/sh", {"-c", "echo 'birdcage-track: no TLE names ZZZ' >&2; exit 1"}, &why));
    REQUIRE(e2e::wait_until([&] { return query.pump(); }, 10s));
    CHECK_FALSE(query.answer);
    CHECK(query.error == "birdcage-track: no TLE names ZZZ");
}
