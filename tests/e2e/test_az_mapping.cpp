// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end: a north-crossing pass through the stock rotctld, fed like Gpredict (a target every
// simulated second, small steps), under every azimuth mapping the emulator offers, with the
// backend's default az_mapping=auto. Where the travel holds the pass on one branch and the mapping
// lets absolute commands reach it, the dish's true mechanical azimuth must never reverse by more
// than a few degrees. Where the mapping makes a reversal unavoidable (a wrap manager whose wrap
// point lies on the pass: it never lets the axis through that azimuth), the backend must learn it
// and take no more long ways round than the firmware forces. 0 hazards throughout.
#include "harness.hpp"

#include <birdcage_sim/motor.hpp>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>
#include <vector>

using namespace std::chrono_literals;
using birdcage::sim::AzMapping;
using birdcage::sim::Variant;

namespace {

constexpr double time_scale = 50.0;
constexpr double pass_seconds = 240.0;  // simulated
constexpr double reversal_allowed_deg = 3.0;
// The dish ends the pass at rest within this of the last target (the last legs may stop inside the
// firmware's arrival tolerance and the backend's same-angle rounding, never further).
constexpr double end_tolerance_deg = 2.0;

struct PassCase {
    const char* name;
    Variant variant;
    int model;
    double az0, span;  // display azimuth at AOS, signed azimuth span (through north)
    double el_min, el_peak;
    AzMapping mapping;
    double wrap_point;
    int forced_long_ways;  // 0: the pass is holdable under this mapping
    double end_mech;       // true mechanical azimuth expected at LOS
};

struct Flight {
    double worst_reversal = 0.0;  // against the pass direction, from the running extreme
    int long_ways = 0;            // reversals of more than 180 deg
    double end_mech = 0.0;
    double end_display_error = 0.0;
    unsigned hazards = 0;
    std::string info;
};

Flight fly(const PassCase& c) {
    birdcage::sim::Options options = e2e::dish_options(c.variant, c.az0, c.el_min, time_scale);
    options.az_mapping = c.mapping;
    options.az_wrap_point = c.wrap_point;
    e2e::Rig rig(options, c.model, {"-C", "time_scale=" + std::to_string(time_scale)});
    e2e::RotctldConnection client(rig.port());
    auto& dish = rig.dish();

    char line[64];
    const auto target = [&](double az, double el) {
        std::snprintf(line, sizeof line, "P %.2f %.2f", birdcage::sim::normalize_360(az), el);
        const std::string reply = client.ask(line, 1);
        INFO(line << " -> " << reply);
        REQUIRE(reply.find("RPRT 0") != std::string::npos);
    };
    // Before AOS Gpredict holds the AOS azimuth at the lowest elevation.
    target(c.az0, c.el_min);
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(dish, c.az0, c.el_min, 0.2); }, 60s));

    Flight flight;
    std::vector<double> track;  // true mechanical azimuth, sampled while the pass runs
    const double start = dish.sim_time();
    const auto sample = [&] { track.push_back(dish.true_mechanical_az()); };
    const int steps = static_cast<int>(pass_seconds);
    for (int i = 1; i <= steps; ++i) {
        const double f = static_cast<double>(i) / steps;
        target(c.az0 + c.span * f, c.el_min + (c.el_peak - c.el_min) * std::sin(f * 3.14159265358979));
        if (i % 5 == 0) {
            client.ask("p", 2);  // Gpredict reads the position back every cycle; a few suffice here
        }
        // Pace the client in simulated time; sample the true azimuth meanwhile.
        REQUIRE(e2e::wait_until(
            [&] {
                sample();
                return dish.sim_time() >= start + i;
            },
            10s));
    }
    // Until the dish rests at the last target: a pause between two legs is not the end (on a loaded
    // machine it lasts seconds of simulated time at this scale).
    const double end_az = c.az0 + c.span;
    REQUIRE(e2e::wait_until(
        [&] {
            sample();
            return e2e::settled_at(dish, end_az, c.el_min, end_tolerance_deg);
        },
        60s));
    sample();
    // Against the pass direction: how far back from the furthest point reached, and how many times
    // more than 180 deg (a long way round; counted once per run).
    const int direction = c.span > 0 ? 1 : -1;
    double furthest = track.front();
    double since_long_way = track.front();
    for (const double mech : track) {
        furthest = direction > 0 ? std::max(furthest, mech) : std::min(furthest, mech);
        flight.worst_reversal = std::max(flight.worst_reversal, (furthest - mech) * direction);
        since_long_way = direction > 0 ? std::max(since_long_way, mech) : std::min(since_long_way, mech);
        if ((since_long_way - mech) * direction > 180.0) {
            ++flight.long_ways;
            since_long_way = mech;
        }
    }
    flight.end_mech = dish.true_mechanical_az();
    flight.end_display_error = e2e::angle_between(dish.true_position().az, c.az0 + c.span);
    flight.hazards = dish.hazards_received();
    flight.info = client.ask("_", 1);
    const bool failing = flight.long_ways > c.forced_long_ways ||
                         (c.forced_long_ways == 0 && flight.worst_reversal > reversal_allowed_deg);
    if (failing) {
        WARN(rig.rotctld_log_text().substr(0, 200000));
    }
    return flight;
}

}  // namespace

TEST_CASE("az mapping e2e: north-crossing passes under every emulator mapping, az_mapping=auto", "[e2e][az_mapping]") {
    const PassCase cases[] = {
        // Trav'ler, the failure the tracking benchmark measured: 248 -> 43 growing, held by 248 -> 403.
        {"hal205 nearest", Variant::travler_hal205, 90102, 248, 155, 15, 60, AzMapping::nearest, 0, 0, 403},
        {"hal205 literal", Variant::travler_hal205, 90102, 248, 155, 15, 60, AzMapping::literal, 0, 0, 403},
        {"hal205 wrap manager, wrap point 95 (wrap position 455)", Variant::travler_hal205, 90102, 248, 155, 15, 60,
         AzMapping::wrap_manager, 95, 0, 403},
        // Wrap point at north: no command can take the axis through it, so the crossing is one forced
        // long way round (to 43 instead of 403).
        {"hal205 wrap manager, wrap point north", Variant::travler_hal205, 90102, 248, 155, 15, 60,
         AzMapping::wrap_manager, 0, 1, 43},
        // G2: decreasing across north, 20 -> 300 = mechanical 20 -> -60 (inside what a literal G2
        // console reaches with non-negative numbers, -336.67..23.33).
        {"g2 nearest", Variant::carryout_g2, 90105, 20, -80, 18, 50, AzMapping::nearest, 0, 0, -60},
        {"g2 literal", Variant::carryout_g2, 90105, 20, -80, 18, 50, AzMapping::literal, 0, 0, -60},
        // The wrap manager's sector is -360..0: the dish at +20 is outside it, so the first target
        // takes it 360 deg on in the pass direction (20 -> -340), and the crossing is the one forced
        // long way back.
        {"g2 wrap manager, wrap point north", Variant::carryout_g2, 90105, 20, -80, 18, 50, AzMapping::wrap_manager, 0,
         1, -60},
    };
    for (const PassCase& c : cases) {
        DYNAMIC_SECTION(c.name) {
            const Flight flight = fly(c);
            INFO("worst reversal " << flight.worst_reversal << ", long ways " << flight.long_ways << ", end "
                                   << flight.end_mech << "; get_info: " << flight.info);
            WARN(c.name << ": worst reversal " << flight.worst_reversal << " deg, long ways " << flight.long_ways
                        << ", end " << flight.end_display_error << " deg from the last target"
                        << ", end mechanical " << flight.end_mech);
            CHECK(flight.hazards == 0);
            CHECK(flight.end_display_error <= end_tolerance_deg);
            CHECK(flight.end_mech == Approx(c.end_mech).margin(3.0));
            if (c.forced_long_ways == 0) {
                CHECK(flight.worst_reversal <= reversal_allowed_deg);
                CHECK(flight.long_ways == 0);
            } else {
                CHECK(flight.long_ways <= c.forced_long_ways);
                CHECK(flight.info.find("learnt wrap_manager") != std::string::npos);
            }
        }
    }
}
