// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Per-axis legs on a Trav'ler whose `a <id> <deg>` queues behind the motor that is moving
// (docs/firmware.md §2, §3.4) and whose motors start 4 s after each command, against the emulator's
// console in dish time (emulated_console.hpp): the same run on any machine.
//
// An elevation leg sent within the arrival tolerance ends at the first reading, but the firmware
// still runs it: the azimuth leg sent next waits out that leg's start-up delay and motion before
// its own. Read as a motor that never started, it was declared "stopped ... short of" and the
// backend lost its picture of the dish (the e2e motor-dynamics test failed on a loaded machine
// when the azimuth was also still settling into its previous leg).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "emulated_console.hpp"
#include "firmware/variants.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

constexpr double start_az = 150.0, start_el = 40.0;
constexpr double startup_delay_s = 4.0;

struct Rig {
    test::EmulatedConsole dish;
    std::vector<std::string> log;
    std::optional<Controller> controller;

    explicit Rig(const sim::Options& options) : dish(options) {
        ControllerOptions controller_options{};
        controller_options.variant = VariantId::travler_hal205;
        controller_options.leapfrog = false;
        controller_options.clock = dish.clock();
        controller_options.log = [this](LogLevel, const std::string& message) { log.push_back(message); };
        controller.emplace(dish, controller_options);
        const Status initialised = controller->initialize();
        INFO(initialised.message);
        REQUIRE(initialised);
    }

    // Services the controller every 100 ms of dish time until it has nothing left to do.
    void until_idle() {
        for (int ticks = 0; ticks < 3000; ++ticks) {
            const Status status = controller->service();
            INFO(status.message);
            REQUIRE(status);
            if (controller->idle()) {
                return;
            }
            dish.tick(100ms);
        }
        FAIL("the controller never became idle");
    }

    void until_still() {
        until_idle();
        for (int ticks = 0; ticks < 3000 && dish.console().moving(); ++ticks) {
            dish.tick(100ms);
        }
        REQUIRE_FALSE(dish.console().moving());
    }

    std::size_t count(const std::string& text) const {
        return static_cast<std::size_t>(std::count_if(
            log.begin(), log.end(), [&](const std::string& line) { return line.find(text) != std::string::npos; }));
    }

    std::size_t azimuth_commands() const {
        const auto& commands = dish.console().commands();
        return static_cast<std::size_t>(std::count_if(commands.begin(), commands.end(),
                                                      [](const std::string& c) { return c.rfind("a 0 ", 0) == 0; }));
    }
};

sim::Options late_motor() {
    sim::Options options;
    options.variant = sim::Variant::travler_hal205;
    options.start_az = start_az;
    options.start_el = start_el;
    options.motor.startup_delay = startup_delay_s;
    options.motor.accel = 3.0;
    return options;
}

}  // namespace

TEST_CASE("firmware queue: an azimuth leg queued behind an elevation leg that ended at once is not a stall",
          "[firmware_queue]") {
    Rig rig(late_motor());
    // A leg from rest teaches the start-up delay.
    REQUIRE(rig.controller->set_target({start_az + 10.0, start_el}));
    const bool wait_for_rest = GENERATE(true, false);
    INFO((wait_for_rest ? "the azimuth at rest" : "the azimuth still settling into its last leg"));
    if (wait_for_rest) {
        rig.until_still();
    } else {
        rig.until_idle();  // arrived within the tolerance: the motor is still braking
    }
    REQUIRE(rig.count(" ms after its command") == 1);
    const std::size_t before = rig.azimuth_commands();

    // Alternating order: elevation first, 0.15 deg off, inside the 0.2 deg arrival tolerance.
    REQUIRE(rig.controller->set_target({start_az + 20.0, start_el - 0.15}));
    rig.until_still();

    CHECK(rig.count("short of") == 0);
    CHECK(rig.azimuth_commands() == before + 1);  // sent once, never re-sent
    CHECK(rig.dish.console().position().az == Approx(start_az + 20.0).margin(0.05));
    CHECK(rig.dish.console().position().el == Approx(start_el - 0.15).margin(0.05));
    // Nothing after the first leg taught a start-up delay: the queued leg's start is not its own.
    CHECK(rig.count(" ms after its command") == 1);
}

TEST_CASE("firmware queue: a motor starting 2 s late teaches its delay and its travel per leg length",
          "[firmware_queue]") {
    // A draw of the dialect generator's kind: 10 deg in about 6 s, 90 deg in about 13.5 s, of which
    // 2 s are the start-up delay (sim/src/motor.cpp, Axis::move_time).
    sim::Options options = late_motor();
    options.motor.startup_delay = 2.0;
    options.motor.az_velocity = options.motor.el_velocity = 15.4;
    options.motor.accel = 2.64;
    Rig rig(options);
    const FirmwareProfile& dish = profile(VariantId::travler_hal205);
    // Before any leg: nothing learnt, the variant's curve as it is.
    CHECK(rig.controller->learnt_motor().startup_s[0] == 0.0);
    CHECK(rig.controller->learnt_motor().paces.pace(Axis::azimuth, 2.0) == 1.0);

    double az = start_az;
    for (int leg = 0; leg < 8; ++leg) {
        az += 2.0;
        REQUIRE(rig.controller->set_target({az, start_el}));
        rig.until_still();
    }
    CHECK(rig.count("short of") == 0);
    const MotorTiming learnt = rig.controller->learnt_motor();
    CHECK(learnt.startup_s[static_cast<std::size_t>(Axis::azimuth)] == Approx(2.0).margin(0.25));
    // A 2 deg leg of that motor runs 2 sqrt(2 / 2.64) = 1.74 s once under way (triangular).
    const double curve_s = std::chrono::duration<double>(estimated_move_time(dish, Axis::azimuth, 2.0)).count();
    const double travel_s = curve_s / learnt.paces.pace(Axis::azimuth, 2.0);
    CHECK(travel_s == Approx(2.0 * std::sqrt(2.0 / 2.64)).epsilon(0.2));
}
