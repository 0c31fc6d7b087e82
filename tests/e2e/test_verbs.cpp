// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end: the Hamlib verbs beyond P/p (park K, reset R, stop S, get_status s, get_info _, conf
// parameters) and the G2 completions (homing, the INT_MAX sentinel, the NVS 20 warning).
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace std::chrono_literals;
using birdcage::sim::Options;
using birdcage::sim::Variant;

namespace {

bool any_command_starting(const std::vector<std::string>& commands, const std::string& prefix) {
    return std::any_of(commands.begin(), commands.end(), [&](const std::string& c) { return c.rfind(prefix, 0) == 0; });
}

struct ParkCase {
    Variant variant;
    int model;
    double park_az, park_el;
};

}  // namespace

TEST_CASE("K parks every variant with ordinary moves, never with stow", "[e2e][verbs][park]") {
    const ParkCase cases[] = {
        {Variant::travler_hal000, 90101, 0.0, 45.0}, {Variant::travler_hal205, 90102, 0.0, 45.0},
        {Variant::travler_pro, 90103, 0.0, 45.0},    {Variant::carryout2003, 90104, 0.0, 45.0},
        {Variant::carryout_g2, 90105, 0.0, 65.0},
    };
    for (const ParkCase& c : cases) {
        DYNAMIC_SECTION(birdcage::sim::variant_name(c.variant)) {
            e2e::Rig rig(e2e::dish_options(c.variant), c.model, {"-C", "leapfrog=0"});
            REQUIRE(rig.rotctl({"K"}).exit_code == 0);
            CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), c.park_az, c.park_el); }, 30s));
            CHECK_FALSE(any_command_starting(rig.dish().received_commands(), "stow"));
            CHECK(rig.dish().hazards_received() == 0);
        }
    }
}

TEST_CASE("R: homing on the G2, RPRT -11 (not available) where the firmware has none", "[e2e][verbs][reset]") {
    SECTION("Trav'ler HAL 2.05 has no homing command") {
        e2e::Rig rig(e2e::dish_options(Variant::travler_hal205), 90102);
        e2e::RotctldConnection client(rig.port());
        CHECK(client.ask("R 1", 1) == "RPRT -11\n");
        CHECK(client.ask("p", 2).find("RPRT") == std::string::npos);  // the session survives
        CHECK(rig.dish().hazards_received() == 0);
    }
    SECTION("G2: R 1 homes (h 1, h 0) and the dish ends at its home position") {
        e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0), 90105);
        REQUIRE(rig.rotctl({"R", "1"}).exit_code == 0);
        CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 0.0, 65.0); }, 30s));
        const auto commands = rig.dish().received_commands();
        CHECK(any_command_starting(commands, "h 1"));
        CHECK(any_command_starting(commands, "h 0"));
        CHECK(rig.dish().hazards_received() == 0);
    }
    SECTION("G2: R 0 is no Hamlib reset type: refused with RPRT -1, nothing homed") {
        e2e::Rig rig(e2e::dish_options(Variant::carryout_g2, 100.0, 30.0), 90105);
        e2e::RotctldConnection client(rig.port());
        CHECK(client.ask("R 0", 1) == "RPRT -1\n");
        CHECK(client.ask("R 2", 1) == "RPRT -1\n");
        CHECK(client.ask("p", 2).find("RPRT") == std::string::npos);  // the session survives
        CHECK_FALSE(any_command_starting(rig.dish().received_commands(), "h "));
        CHECK(rig.dish().hazards_received() == 0);
    }
}

TEST_CASE("G2: while R 1 homes, p answers, s says BUSY, and a P sent meanwhile is moved to after the home",
          "[e2e][verbs][g2][homing]") {
    Options o = e2e::dish_options(Variant::carryout_g2, 100.0, 30.0);
    o.time_scale = 2.0;  // a home of several dish seconds: the client sees it run
    e2e::Rig rig(o, 90105, {"-C", "leapfrog=0", "-C", "pointing=none"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.ask("R 1", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return client.ask("s", 1).find("BUSY") != std::string::npos; }, 5s));
    // The console is held by `h`: every p during the home must still answer with a position.
    int answers_while_homing = 0;
    std::string refused;
    const bool home_ended = e2e::wait_until(
        [&] {
            const std::string position = client.ask("p", 2);
            if (position.find("RPRT") != std::string::npos)
                refused = position;
            if (answers_while_homing++ == 0) {
                CHECK(client.ask("P 150 40", 1) == "RPRT 0\n");  // taken at once, moved to after the home
            }
            return client.ask("s", 1).find("BUSY") == std::string::npos;
        },
        60s);
    REQUIRE(home_ended);
    CHECK(refused.empty());
    const auto commands = rig.dish().received_commands();
    CHECK(any_command_starting(commands, "h 1"));
    CHECK(any_command_starting(commands, "h 0"));
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0); }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("G2 with unhomed axes: moves refused with a clear error until R homes them", "[e2e][verbs][g2][homing]") {
    Options o = e2e::dish_options(Variant::carryout_g2);
    SECTION("booted unhomed") {
        o.g2_homed = false;
    }
    SECTION("boot skips homing and loses the calibration (tracker disabled, the predecessor's claim)") {
        o.already_booted = false;
        o.g2_boot_homes = false;
        o.g2_boot_calibrated = false;
    }
    e2e::Rig rig(o, 90105, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    CHECK(client.ask("P 150 40", 1) == "RPRT -9\n");  // -RIG_ERJCTED: refused, client stays connected
    CHECK(client.ask("p", 1) == "RPRT -9\n");
    const std::string info = client.ask("_", 1);
    CHECK(info.rfind("Winegard Carryout G2: axes NOT homed", 0) == 0);         // in what netrotctl shows
    CHECK(rig.rotctld_log_text().find("R 1") != std::string::npos);            // the error says how to home
    CHECK_FALSE(any_command_starting(rig.dish().received_commands(), "a 0"));  // no move sent while unhomed

    CHECK(client.ask("R 1", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until(
        [&] {
            return client.ask("s", 1).find("MOVING") == std::string::npos && e2e::settled_at(rig.dish(), 0.0, 65.0);
        },
        30s));
    REQUIRE(e2e::wait_until([&] { return client.ask("P 150 40", 1) == "RPRT 0\n"; }, 10s));
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0); }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("G2 with NVS 20 FALSE: a clear warning, and NVS is never written", "[e2e][verbs][g2][nvs]") {
    Options o = e2e::dish_options(Variant::carryout_g2);
    o.search_running = true;  // the emulator runs its search exactly when NVS 20 is FALSE
    e2e::Rig rig(o, 90105);
    e2e::RotctldConnection client(rig.port());
    // The search moves the dish while the backend is idle: that makes it read NVS 20 (once).
    CHECK(e2e::wait_until([&] { return client.ask("_", 1).find("NVS 20") != std::string::npos; }, 20s));
    CHECK(rig.rotctld_log_text().find("is FALSE") != std::string::npos);
    const auto commands = rig.dish().received_commands();
    CHECK(any_command_starting(commands, "d 20"));
    CHECK_FALSE(any_command_starting(commands, "e "));
    CHECK_FALSE(std::count(commands.begin(), commands.end(), std::string("s")));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("s reports MOVING while a leg runs and nothing at rest", "[e2e][verbs][status]") {
    Options o = e2e::dish_options(Variant::carryout_g2);
    o.time_scale = 2.0;
    e2e::Rig rig(o, 90105, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    CHECK(client.ask("s", 1).find("MOVING") == std::string::npos);
    CHECK(client.ask("P 300 40", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return client.ask("s", 1).find("MOVING") != std::string::npos; }, 5s));
    CHECK(e2e::wait_until([&] { return client.ask("s", 1).find("MOVING") == std::string::npos; }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("conf parameters: listed by rotctl -L, and they take effect", "[e2e][verbs][conf]") {
    // Stock rotctl lists the parameters, then opens the port: a missing one makes it exit at once.
    const e2e::CommandResult listed =
        e2e::run({"/usr/bin/rotctl", "-m", "90103", "-r", "/nonexistent/port", "-L"}, e2e::preload_environment());
    for (const char* name :
         {"variant", "leapfrog", "boot_timeout", "skip_init", "el_min", "el_max", "az_min", "az_max"}) {
        INFO(name);
        CHECK(listed.out.find(name) != std::string::npos);
    }
    CHECK(listed.out.find("75.00") != std::string::npos);  // the Pro's own elevation cap as the default

    SECTION("az_min/az_max clamp azimuth targets") {
        e2e::Rig rig(e2e::dish_options(Variant::carryout_g2), 90105,
                     {"-C", "leapfrog=0", "-C", "az_min=90", "-C", "az_max=270"});
        REQUIRE(rig.rotctl({"P", "300", "40"}).exit_code == 0);
        CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 270.0, 40.0); }, 30s));
    }
    SECTION("el_max narrows the elevation range") {
        e2e::Rig rig(e2e::dish_options(Variant::travler_hal000), 90101, {"-C", "leapfrog=0", "-C", "el_max=50"});
        REQUIRE(rig.rotctl({"P", "120", "80"}).exit_code == 0);
        CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, 50.0); }, 30s));
    }
    SECTION("variant=auto on a fixed model detects the real firmware") {
        e2e::Rig rig(e2e::dish_options(Variant::carryout2003), 90105, {"-C", "variant=auto", "-C", "leapfrog=0"});
        e2e::RotctldConnection client(rig.port());
        CHECK(client.ask("_", 1).find("Carryout HAL 1.00.065 (auto-detected)") != std::string::npos);
        CHECK(rig.dish().hazards_received() == 0);
    }
}

TEST_CASE("conf parameters set while rotctld runs are refused, with a log line naming -C", "[e2e][verbs][conf]") {
    // Every parameter is read at open; rotctl's `C key value` after that used to answer RPRT 0 and
    // change nothing (`C pointing none` left the G2 predictive).
    Options o = e2e::dish_options(Variant::carryout_g2);
    o.time_scale = 10.0;
    e2e::Rig rig(o, 90105, {"-C", "time_scale=10"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.ask("_", 1).find("pointing predictive") != std::string::npos);
    const std::pair<const char*, const char*> settings[] = {
        {"pointing", "none"}, {"leapfrog", "1"},         {"deadband", "0.5"},    {"deadband_share", "0"},
        {"pass_model", "1"},  {"el_min", "30"},          {"el_max", "50"},       {"az_min", "90"},
        {"az_max", "270"},    {"variant", "hal205"},     {"boot_timeout", "10"}, {"skip_init", "1"},
        {"time_scale", "1"},  {"az_mapping", "literal"}, {"start_cost", "0"},    {"az_index", "6"},
        {"el_index", "0.8"},  {"tilt_north", "1.2"},     {"tilt_east", "-0.5"}};
    for (const auto& [key, value] : settings) {
        INFO(key << " = " << value);
        CHECK(client.ask(std::string("C ") + key + " " + value, 1) == "RPRT -1\n");
        CHECK(rig.rotctld_log_text().find(std::string("-C ") + key + "=" + value) != std::string::npos);
    }
    CHECK(client.ask("_", 1).find("pointing predictive") != std::string::npos);
    // The session goes on with the settings it was opened with: el_max stays the G2's 65, not 50.
    CHECK(client.ask("P 200 60", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 60.0); }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}
