// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The controller's cable-wrap handling against the emulator (the test oracle, written from the
// docs/firmware.md and not from src/): north-crossing passes on the emulated G2 and Trav'ler, with
// the azimuth reported displayed and mechanical; the dish's true mechanical azimuth must never
// unwind during the pass and never leave the travel less the margins.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "birdcage_sim/emulator.hpp"
#include "console/fd_transport.hpp"
#include "dish/controller.hpp"
#include "tracking/wrap.hpp"

using namespace std::chrono_literals;
namespace sim = birdcage::sim;

namespace {

constexpr double time_scale = 50.0;    // simulated seconds per real second
constexpr auto target_deadline = 60s;  // a failure bound, not a timing assertion

struct Case {
    const char* name;
    sim::Variant sim_variant;
    birdcage::VariantId variant;
    double start_az, start_el;   // display azimuth the emulated dish starts at
    double span;                 // signed azimuth span of the pass (through north)
    double rate;                 // the rate hint passed with each target (deg/s)
    double expected_start_mech;  // where the pass must start (mechanical)
};

struct Run {
    std::vector<double> settled;  // true mechanical azimuth after each target
    std::vector<double> samples;  // true mechanical azimuth while following targets 1..n
    unsigned hazards = 0;
    std::vector<std::string> az_commands;
};

Run fly(const Case& c, sim::AzReport report, int targets) {
    sim::Options options;
    options.variant = c.sim_variant;
    options.time_scale = time_scale;
    options.start_az = c.start_az;
    options.start_el = c.start_el;
    options.az_report = report;
    sim::Emulator dish(options);

    auto opened = birdcage::FdTransport::open(dish.device_path(), birdcage::profile(c.variant).baud);
    REQUIRE(opened);
    birdcage::ControllerOptions controller_options;
    controller_options.variant = c.variant;
    controller_options.leapfrog = false;
    controller_options.boot_timeout = 20s;
    birdcage::Controller controller(*opened.value, controller_options);
    const birdcage::Status initialised = controller.initialize();
    INFO(initialised.message);
    REQUIRE(initialised);

    Run run;
    const double el_min = controller.el_min();
    for (int i = 0; i <= targets; ++i) {
        const double f = static_cast<double>(i) / targets;
        const double az = birdcage::normalize_azimuth(c.start_az + c.span * f);
        const double el = el_min + 40.0 * std::sin(f * 3.14159265358979);
        REQUIRE(controller.set_target({az, el}, c.rate));
        const auto deadline = std::chrono::steady_clock::now() + target_deadline;
        while (!controller.idle() || dish.moving()) {
            REQUIRE(std::chrono::steady_clock::now() < deadline);
            const birdcage::Status status = controller.service();
            INFO(status.message);
            REQUIRE((status || status.code == birdcage::Errc::timeout));
            if (i > 0) {
                run.samples.push_back(dish.true_mechanical_az());
            }
            std::this_thread::sleep_for(2ms);
        }
        run.settled.push_back(dish.true_mechanical_az());
        const auto estimate = controller.mechanical_azimuth();
        REQUIRE(estimate);
        CHECK(*estimate == Approx(dish.true_mechanical_az()).margin(0.3));
    }
    run.hazards = dish.hazards_received();
    for (const auto& command : dish.received_commands()) {
        if (command.rfind("a 0 ", 0) == 0) {
            run.az_commands.push_back(command);
        }
    }
    return run;
}

}  // namespace

TEST_CASE("wrap on the emulator: north-crossing passes never unwind mid-pass", "[wrap][emulator]") {
    const Case cases[] = {
        // G2 at 300 = -60 after homing: only 81 deg left clockwise, so the pass starts on -420.
        {"G2 clockwise 300 -> 60", sim::Variant::carryout_g2, birdcage::VariantId::carryout_g2, 300, 18, 120, 0.5,
         -420},
        // 60 is only -300 on the G2; anticlockwise to 300 = -420 fits by continuity.
        {"G2 anticlockwise 60 -> 300", sim::Variant::carryout_g2, birdcage::VariantId::carryout_g2, 60, 18, -120, -0.5,
         -300},
        // Trav'ler at 60: 58 deg left anticlockwise, so the pass starts on 420.
        {"Trav'ler anticlockwise 60 -> 300", sim::Variant::travler_hal205, birdcage::VariantId::travler_hal205, 60, 15,
         -120, -0.5, 420},
        // Trav'ler clockwise 300 -> 60 = 420, by continuity, also without a rate hint.
        {"Trav'ler clockwise 300 -> 60, no rate hint", sim::Variant::travler_hal205,
         birdcage::VariantId::travler_hal205, 300, 15, 120, 0.0, 300},
    };
    for (const Case& c : cases) {
        for (const sim::AzReport report : {sim::AzReport::displayed, sim::AzReport::mechanical}) {
            DYNAMIC_SECTION(c.name << (report == sim::AzReport::displayed ? ", az displayed" : ", az mechanical")) {
                constexpr int targets = 12;  // 10-deg steps
                const Run run = fly(c, report, targets);
                const double step = std::fabs(c.span) / targets;
                REQUIRE(run.settled.size() == targets + 1);
                CHECK(run.settled.front() == Approx(c.expected_start_mech).margin(0.2));
                CHECK(run.settled.back() == Approx(c.expected_start_mech + c.span).margin(0.2));
                // Target by target the dish turns one step the way the satellite goes ...
                for (std::size_t i = 1; i < run.settled.size(); ++i) {
                    INFO("target " << i);
                    CHECK((run.settled[i] - run.settled[i - 1]) * (c.span > 0 ? 1 : -1) == Approx(step).margin(0.2));
                }
                // ... and in between it never leaves the pass's own stretch of azimuth (an unwind
                // would take it 360 deg away).
                const double low = std::min(run.settled.front(), run.settled.back());
                const double high = std::max(run.settled.front(), run.settled.back());
                for (double mech : run.samples) {
                    REQUIRE(mech >= low - 0.5);
                    REQUIRE(mech <= high + 0.5);
                }
                // Never closer than the margin to a limit; absolute numbers the console has (0..360
                // on the G2, where '-' is a relative move; the travel's own angles on the Trav'ler);
                // no hazard.
                const auto& row = birdcage::profile(c.variant);
                const auto usable = birdcage::wrap::usable_window({row.az_min, row.az_max});
                CHECK(low >= usable.min - 0.1);
                CHECK(high <= usable.max + 0.1);
                for (const auto& command : run.az_commands) {
                    const double value = std::stod(command.substr(4));
                    CHECK(value >= 0.0);
                    CHECK(value < (row.az_min < 0.0 ? 360.0 : usable.max + 0.01));
                }
                CHECK(run.hazards == 0);
            }
        }
    }
}
