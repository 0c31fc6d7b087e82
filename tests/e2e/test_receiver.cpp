// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The dish as a receiver (docs/receiver.md) end to end: emulator (sky model from the real G2 scan) <- pty
// <- stock /usr/bin/rotctld + preloaded backend <- raw TCP clients speaking `v`/`V`.
//
// Stock Hamlib 4.5.4's NET rotator (`rotctl -m 2`) cannot name a backend's extension levels (it
// looks them up in its own caps and answers "Invalid parameter"), so the clients here send the
// protocol's text lines themselves, as `nc` or any program would; a direct `rotctl -m 90105`
// with the backend preloaded reads RSSI too (last test).
#include "harness.hpp"

#include <birdcage_sim/sky.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <thread>

#include <unistd.h>

using namespace std::chrono_literals;
using birdcage::sim::LnbSupply;
using birdcage::sim::SkyModel;
using birdcage::sim::Variant;

namespace {

constexpr int kG2 = 90105;
constexpr int kHal205 = 90102;
// `rssi 10` averages ten reads of 8 counts noise (sky.cpp): 2.5 counts; 4 sigma.
constexpr double kReadingTolerance = 10.0;

double reading(e2e::RotctldConnection& client, const std::string& level = "RSSI") {
    const std::string reply = client.ask("v " + level, 1);
    const auto values = e2e::numbers(reply);
    INFO("v " << level << " -> " << reply);
    REQUIRE(values.size() == 1);
    REQUIRE(reply.find("RPRT") == std::string::npos);
    return values.front();
}

void move_to(e2e::Rig& rig, e2e::RotctldConnection& client, double az, double el) {
    REQUIRE(client.ask("P " + std::to_string(az) + " " + std::to_string(el), 1).find("RPRT 0") != std::string::npos);
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), az, el); }, 60s));
    REQUIRE(e2e::wait_until([&] { return rig.dish().moving() == false; }, 10s));
}

bool sent(e2e::Rig& rig, const std::string& command) {
    const auto commands = rig.dish().received_commands();
    return std::find(commands.begin(), commands.end(), command) != commands.end();
}

// Never a streaming command, never the ADC's argument-less `scan` (docs/firmware.md §6.5).
void no_streaming_or_hazard(e2e::Rig& rig) {
    for (const std::string& command : rig.dish().received_commands()) {
        const std::string verb = command.substr(0, command.find(' '));
        CHECK(verb != "agc");
        CHECK(verb != "lnbv");
        CHECK(verb != "snr");
        CHECK(verb != "nid");
        CHECK(verb != "m");
        CHECK(command != "scan");
    }
    CHECK(rig.dish().hazards_received() == 0);
}

}  // namespace

TEST_CASE("G2: v RSSI follows where the dish points, and V LNB changes the sky it hears", "[e2e][receiver]") {
    const auto options = e2e::dish_options(Variant::carryout_g2, 174.0, 43.0);
    const SkyModel sky(0, options.rssi_floor);  // the emulator's own model, as the oracle
    e2e::Rig rig(options, kG2);
    e2e::RotctldConnection client(rig.port());

    const std::string levels = client.ask("v ?", 1);
    CHECK(levels.find("RSSI") != std::string::npos);
    CHECK(levels.find("LNB") != std::string::npos);
    // Read from the tuner's `dis` listing at open: the boot default of a freshly powered dish.
    CHECK(reading(client, "LNB") == 18.0);

    REQUIRE(client.ask("V LNB 13", 1).find("RPRT 0") != std::string::npos);
    CHECK(reading(client, "LNB") == 13.0);
    CHECK(sent(rig, "lnbdc odu"));

    // On DIRECTV's cluster (the real scan's strongest point) and off the belt.
    const double on = reading(client);
    CHECK(std::fabs(on - sky.expected_rssi(174.0, 43.0, LnbSupply::odu_13v)) <= kReadingTolerance);
    move_to(rig, client, 100.0, 60.0);
    const double off = reading(client);
    CHECK(std::fabs(off - sky.expected_rssi(100.0, 60.0, LnbSupply::odu_13v)) <= kReadingTolerance);
    CHECK(on - off > 100.0);

    // 18 V: the other polarisation; the strong satellite fades to its cross-polar leak.
    REQUIRE(client.ask("V LNB 18", 1).find("RPRT 0") != std::string::npos);
    CHECK(sent(rig, "lnbdc stb"));
    move_to(rig, client, 174.0, 43.0);
    const double on_18v = reading(client);
    CHECK(std::fabs(on_18v - sky.expected_rssi(174.0, 43.0, LnbSupply::stb_18v)) <= kReadingTolerance);
    CHECK(on - on_18v > 50.0);

    // Samples are configurable; more samples are still a reading of the same sky.
    REQUIRE(client.ask("V RSSI_SAMPLES 40", 1).find("RPRT 0") != std::string::npos);
    CHECK(reading(client, "RSSI_SAMPLES") == 40.0);
    CHECK(std::fabs(reading(client) - sky.expected_rssi(174.0, 43.0, LnbSupply::stb_18v)) <= kReadingTolerance);
    CHECK(sent(rig, "rssi 40"));
    CHECK(client.ask("V RSSI_SAMPLES 0", 1).find("RPRT -1") != std::string::npos);
    CHECK(client.ask("V LNB 5", 1).find("RPRT -1") != std::string::npos);

    // Back in the motor menu with the position model intact.
    const auto p = client.get_position();
    REQUIRE(p.ok);
    CHECK(e2e::angle_between(p.az, 174.0) <= 0.1);
    CHECK(std::fabs(p.el - 43.0) <= 0.1);
    move_to(rig, client, 150.0, 30.0);
    no_streaming_or_hazard(rig);
}

// rotctld restarted while the dish stayed powered at 13 V: the backend must not report the boot
// default. What it reports is the tuner's own listing (DVB `dis`, the real console's `LNB Polarity
// ODU:13V` row) or unknown; setting it makes it known; a reboot of the dish makes 18 V true again.
TEST_CASE("G2: the LNB supply after open is the dish's or unknown and never an assumed 18 V", "[e2e][receiver]") {
    const auto options = e2e::dish_options(Variant::carryout_g2, 174.0, 43.0);
    e2e::Rig rig(options, kG2, {}, [](birdcage::sim::Emulator& dish) {
        e2e::type_into(dish, {"dvb", "lnbdc odu", "q"});
    });
    e2e::RotctldConnection client(rig.port());
    CHECK(sent(rig, "dis"));                // asked, one-shot
    CHECK(reading(client, "LNB") == 13.0);  // the dish's own supply, not the boot default
    REQUIRE(client.ask("V LNB 18", 1).find("RPRT 0") != std::string::npos);
    CHECK(reading(client, "LNB") == 18.0);
    REQUIRE(client.ask("V LNB 13", 1).find("RPRT 0") != std::string::npos);
    CHECK(reading(client, "LNB") == 13.0);
    rig.dish().power_cycle();
    REQUIRE(e2e::wait_until([&] { return client.ask("_", 1).find("recovered 1") != std::string::npos; }, 60s));
    CHECK(reading(client, "LNB") == 18.0);  // the boot default again (`Enabled LNB ODU 18V`)
    no_streaming_or_hazard(rig);
}

// A tuner whose listing has no LNB row the backend can read (the reconstructed console's `dis`):
// unknown, never the boot default assumed.
TEST_CASE("G2: an LNB supply the tuner does not list is unknown after open", "[e2e][receiver]") {
    auto options = e2e::dish_options(Variant::carryout_g2, 174.0, 43.0);
    options.g2_console = birdcage::sim::G2Console::reconstructed;
    options.unlisted_commands = true;
    e2e::Rig rig(options, kG2, {}, [](birdcage::sim::Emulator& dish) {
        e2e::type_into(dish, {"dvb", "lnbdc odu", "q"});
    });
    e2e::RotctldConnection client(rig.port());
    CHECK(sent(rig, "dis"));
    const std::string after_open = client.ask("v LNB", 1);
    INFO(after_open);
    CHECK(after_open.find("RPRT -11") != std::string::npos);
    REQUIRE(client.ask("V LNB 13", 1).find("RPRT 0") != std::string::npos);
    CHECK(reading(client, "LNB") == 13.0);
    no_streaming_or_hazard(rig);
}

TEST_CASE("Trav'ler: the receiver levels answer not available", "[e2e][receiver]") {
    e2e::Rig rig(e2e::dish_options(Variant::travler_hal205, 100.0, 30.0), kHal205);
    e2e::RotctldConnection client(rig.port());
    CHECK(client.ask("v RSSI", 1).find("RPRT -11") != std::string::npos);  // -RIG_ENAVAIL
    CHECK(client.ask("v LNB", 1).find("RPRT -11") != std::string::npos);
    CHECK(client.ask("V LNB 13", 1).find("RPRT -11") != std::string::npos);
    const auto p = client.get_position();
    CHECK(p.ok);
    for (const std::string& command : rig.dish().received_commands()) {
        CHECK(command.find("dvb") == std::string::npos);
        CHECK(command.find("rssi") == std::string::npos);
    }
}

TEST_CASE("G2: a reading asked during a move waits for it, loses nothing of it, and p answers", "[e2e][receiver]") {
    // Slower time so the azimuth leg (120 -> 200) is still running when the reading is asked.
    const auto options = e2e::dish_options(Variant::carryout_g2, 120.0, 30.0, 10.0);
    e2e::Rig rig(options, kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection mover(rig.port());
    e2e::RotctldConnection watcher(rig.port());

    REQUIRE(mover.ask("P 200 40", 1).find("RPRT 0") != std::string::npos);
    REQUIRE(e2e::wait_until([&] { return rig.dish().moving(); }, 10s));

    // rotctld runs one client's command at a time: the watcher's `p` is answered once the reading
    // is done, from the position model, never with an error.
    std::vector<e2e::RotctldConnection::Position> seen;
    std::thread watch([&] {
        for (int i = 0; i < 5; ++i) {
            seen.push_back(watcher.get_position(20s));
        }
    });
    const double value = reading(mover);
    watch.join();
    CHECK(value > 0.0);
    for (const auto& p : seen) {
        CHECK(p.ok);
        CHECK(p.el >= 30.0 - 0.1);
        CHECK(p.el <= 40.0 + 0.1);
    }
    // The move survived the trip to DVB> and back.
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 40.0); }, 60s));
    const auto commands = rig.dish().received_commands();
    // The reading's trip (the open's LNB read went to DVB> before any leg).
    const auto dvb =
        std::find_if(commands.begin(), commands.end(), [](const std::string& c) { return c.rfind("rssi ", 0) == 0; });
    REQUIRE(dvb != commands.end());
    // The worker entered the tuner menu only with no leg in flight: both legs (the controller
    // sends the next one as the previous arrives) were sent before it.
    const auto is_leg = [](const std::string& c) { return c.rfind("a 0 ", 0) == 0 || c.rfind("a 1 ", 0) == 0; };
    CHECK(std::count_if(commands.begin(), dvb, is_leg) >= 2);
    no_streaming_or_hazard(rig);
}

TEST_CASE("G2: stock rotctl with the backend preloaded reads RSSI directly from the dish", "[e2e][receiver]") {
    birdcage::sim::Emulator dish(e2e::dish_options(Variant::carryout_g2, 174.0, 43.0));
    const e2e::HazardWatch no_hazards(dish);
    const auto result = e2e::run({"/usr/bin/rotctl", "-m", std::to_string(kG2), "-r", dish.device_path(), "v", "RSSI"},
                                 e2e::preload_environment());
    INFO(result.out << result.err);
    REQUIRE(result.exit_code == 0);
    const auto values = e2e::numbers(result.out);
    REQUIRE(values.size() == 1);
    // The boot default 18 V: the cross-polar leak of the strong cluster at 174/43.
    const SkyModel sky(0, 401.0);
    CHECK(std::fabs(values.front() - sky.expected_rssi(174.0, 43.0, LnbSupply::stb_18v)) <= kReadingTolerance);
}

namespace {

struct ScanRow {
    double az, el, value;
};

std::vector<ScanRow> read_csv(const std::string& path) {
    std::ifstream in(path);
    std::vector<ScanRow> rows;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
        ScanRow r{};
        if (std::sscanf(line.c_str(), "%lf,%lf,%lf", &r.az, &r.el, &r.value) == 3)
            rows.push_back(r);
    }
    return rows;
}

// The strongest direction of the model inside a box, on a fine lattice.
std::pair<double, double> model_peak(const SkyModel& sky, double az0, double az1, double el0, double el1) {
    std::pair<double, double> best{az0, el0};
    double best_value = -1;
    for (double az = az0; az <= az1; az += 0.25) {
        for (double el = el0; el <= el1; el += 0.25) {
            const double v = sky.expected_rssi(az, el, LnbSupply::odu_13v);
            if (v > best_value) {
                best_value = v;
                best = {az, el};
            }
        }
    }
    return best;
}

std::string scan_path(const char* what) {
    return "/tmp/birdcage-e2e-skyscan-" + std::string(what) + "-" + std::to_string(::getpid()) + ".csv";
}

}  // namespace

TEST_CASE("birdcage-skyscan on the emulator finds its satellites within one grid step", "[e2e][receiver][skyscan]") {
    const auto options = e2e::dish_options(Variant::carryout_g2, 166.0, 37.0, 100.0);
    const SkyModel sky(0, options.rssi_floor);
    e2e::Rig rig(options, kG2, {"-C", "pointing=none"});
    const std::string csv = scan_path("peaks");
    const double sim_started = rig.dish().sim_time();
    const auto result = e2e::run({BIRDCAGE_SKYSCAN_PATH, "--port", std::to_string(rig.port()), "--az", "166:206:2",
                                  "--el", "35:49:2", "--lnb", "13", "--out", csv},
                                 {}, 300s);
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    const double sim_seconds = rig.dish().sim_time() - sim_started;
    const auto rows = read_csv(csv);
    REQUIRE(rows.size() == 21u * 8u);
    // Two satellite clusters in the box: DIRECTV's (~174/43) and ECHOSTAR 14's (~201/41).
    for (const auto& [az0, az1] : {std::pair{166.0, 186.0}, std::pair{190.0, 206.0}}) {
        const auto expected = model_peak(sky, az0, az1, 35.0, 49.0);
        const auto best = *std::max_element(rows.begin(), rows.end(), [&](const ScanRow& a, const ScanRow& b) {
            const bool a_in = a.az >= az0 && a.az <= az1, b_in = b.az >= az0 && b.az <= az1;
            return a_in != b_in ? b_in : a.value < b.value;
        });
        INFO("model peak " << expected.first << "/" << expected.second << ", scan peak " << best.az << "/" << best.el);
        CHECK(std::fabs(best.az - expected.first) <= 2.0);
        CHECK(std::fabs(best.el - expected.second) <= 2.0);
        CHECK(best.value > options.rssi_floor + 100.0);
    }
    WARN("skyscan of 168 points: " << sim_seconds << " s of dish time (= real speed)");
    no_streaming_or_hazard(rig);
    std::remove(csv.c_str());
}

TEST_CASE("birdcage-skyscan resumes after a kill without losing or repeating a point", "[e2e][receiver][skyscan]") {
    e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 120.0, 30.0, 100.0), kG2, {"-C", "pointing=none"});
    const std::string csv = scan_path("resume");
    const std::vector<std::string> scan = {BIRDCAGE_SKYSCAN_PATH,
                                           "--port",
                                           std::to_string(rig.port()),
                                           "--az",
                                           "120:130:2",
                                           "--el",
                                           "30:40:2",
                                           "--out",
                                           csv};
    {
        e2e::Child first(scan, {}, scan_path("resume-log"));
        REQUIRE(e2e::wait_until([&] { return read_csv(csv).size() >= 10; }, 120s));
    }  // SIGTERM mid-scan
    const std::size_t before = read_csv(csv).size();
    CHECK(before < 36u);
    std::vector<std::string> again = scan;
    again.push_back("--resume");
    const auto result = e2e::run(again, {}, 300s);
    INFO(result.err);
    REQUIRE(result.exit_code == 0);
    CHECK(result.err.find(std::to_string(before) + " of 36 points already") != std::string::npos);
    const auto rows = read_csv(csv);
    CHECK(rows.size() == 36u);
    std::set<std::pair<long, long>> points;
    for (const auto& r : rows)
        points.insert({std::lround(r.az * 100), std::lround(r.el * 100)});
    CHECK(points.size() == 36u);
    for (double az = 120; az <= 130; az += 2)
        for (double el = 30; el <= 40; el += 2)
            CHECK(points.count({std::lround(az * 100), std::lround(el * 100)}) == 1);
    std::remove(csv.c_str());
    std::remove(scan_path("resume-log").c_str());
}
