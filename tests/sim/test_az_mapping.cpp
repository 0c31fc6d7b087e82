// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator's azimuth-target mapping switch (Options::az_mapping, §14 G2.4): where one `a 0 <deg>`
// puts the mechanical azimuth under each reading, on the Trav'ler (0..455) and the G2
// (-423.33..+23.33), and which way the dish turns to get there.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/motor.hpp"
#include "pty_client.hpp"

using namespace birdcage::sim;
using namespace birdcage::sim::testing;

namespace {

struct Move {
    double end;              // true mechanical azimuth at rest
    double lowest, highest;  // mechanical azimuth range swept on the way
};

// Starts a dish at mechanical `start` (a display azimuth mapped as Options::start_az is), opens its
// motor menu and sends `a 0 <value>` for each value, one after the other at rest.
std::vector<Move> moves(Variant variant, AzMapping mapping, double start, const std::vector<std::string>& values,
                        double wrap_point = 0.0, OutOfRange out_of_range = OutOfRange::clamp) {
    Options options;
    options.variant = variant;
    options.time_scale = 200.0;
    options.start_az = start;
    options.az_mapping = mapping;
    options.az_wrap_point = wrap_point;
    options.out_of_range = out_of_range;
    Emulator dish(options);
    PtyClient client(dish.device_path());
    const bool g2 = variant == Variant::carryout_g2;
    const std::string prompt = g2 ? "MOT>" : "MOTOR>";
    client.command(g2 ? "mot" : "motor", prompt);
    std::vector<Move> result;
    for (const auto& value : values) {
        const double before = dish.sim_time();
        client.command("a 0 " + value, prompt);
        REQUIRE(wait_for([&] { return !dish.moving(); }));
        Move move{dish.true_mechanical_az(), dish.true_mechanical_az(), dish.true_mechanical_az()};
        // history() holds displayed azimuths: unwrap them sample by sample (each < 180 apart).
        double mech = result.empty() ? dish.true_mechanical_az() : result.back().end;
        bool first = true;
        for (const Sample& sample : dish.history()) {
            if (sample.t < before)
                continue;
            if (first) {
                mech = mech + std::remainder(sample.az - mech, 360.0);
                first = false;
            } else {
                mech += std::remainder(sample.az - normalize_360(mech), 360.0);
            }
            move.lowest = std::min(move.lowest, mech);
            move.highest = std::max(move.highest, mech);
        }
        result.push_back(move);
    }
    CHECK(dish.hazards_received() == 0);
    return result;
}

}  // namespace

TEST_CASE("az mapping: the helpers place the wrap manager's sector", "[emulator][az_mapping]") {
    // Trav'ler 0..455: wrap point north -> 0..360; at 95 (wrap position 455, §3.4) -> 95..455.
    CHECK(wrap_sector_start(0.0, 0.0, 455.0) == Approx(0.0));
    CHECK(wrap_sector_start(95.0, 0.0, 455.0) == Approx(95.0));
    CHECK(wrap_sector_start(200.0, 0.0, 455.0) == Approx(200.0));  // 255 deg of 200..560 vs 200 of -160..200
    // G2 -423.33..23.33: wrap point north -> -360..0.
    CHECK(wrap_sector_start(0.0, -423.33, 23.33) == Approx(-360.0));
    CHECK(wrap_manager_target(43.0, 0.0, 300.0, 0.0, 455.0) == Approx(43.0));
    CHECK(wrap_manager_target(403.0, 0.0, 300.0, 0.0, 455.0) == Approx(43.0));
    CHECK(wrap_manager_target(0.0, 0.0, 350.0, 0.0, 455.0) == Approx(360.0));  // on the point: nearer end
    CHECK(wrap_manager_target(10.0, 0.0, -5.0, -423.33, 23.33) == Approx(-350.0));
}

TEST_CASE("az mapping nearest (default): the branch nearest the dish, in-travel values beyond 360 literally",
          "[emulator][az_mapping]") {
    CHECK(Options{}.az_mapping == AzMapping::nearest);
    const auto travler = moves(Variant::travler_hal205, AzMapping::nearest, 350.0, {"10", "403", "100", "30"});
    CHECK(travler[0].end == Approx(370.0).margin(0.01));  // 10 from 350: across north, clockwise
    CHECK(travler[0].lowest >= 349.9);
    CHECK(travler[1].end == Approx(403.0).margin(0.01));
    CHECK(travler[2].end == Approx(100.0).margin(0.01));  // 460 is beyond the travel
    CHECK(travler[3].end == Approx(30.0).margin(0.01));
    // G2 at 300 = -60: 30 -> -330 (the +30 branch is beyond the travel); 340 -> -380, not -20.
    const auto g2 = moves(Variant::carryout_g2, AzMapping::nearest, 300.0, {"30", "340"});
    CHECK(g2[0].end == Approx(-330.0).margin(0.01));
    CHECK(g2[1].end == Approx(-380.0).margin(0.01));
}

TEST_CASE("az mapping literal: the number is the mechanical angle, G2 numbers name one fixed branch",
          "[emulator][az_mapping]") {
    // From 350, 10 is mechanical 10: 340 deg anticlockwise (the wrap limit never reached).
    const auto travler = moves(Variant::travler_hal205, AzMapping::literal, 350.0, {"10", "403", "500"});
    CHECK(travler[0].end == Approx(10.0).margin(0.01));
    CHECK(travler[0].highest <= 350.1);
    CHECK(travler[1].end == Approx(403.0).margin(0.01));
    CHECK(travler[2].end == Approx(455.0).margin(0.01));  // out of range: clamped (the default)
    const auto rejected = moves(Variant::travler_hal205, AzMapping::literal, 100.0, {"500"}, 0.0, OutOfRange::reject);
    CHECK(rejected[0].end == Approx(100.0).margin(0.01));
    // G2: 10 is +10, 340 is -20, 30 is -330 - whichever branch the dish is on.
    const auto g2 = moves(Variant::carryout_g2, AzMapping::literal, 300.0, {"10", "340", "30", "340"});
    CHECK(g2[0].end == Approx(10.0).margin(0.01));
    CHECK(g2[1].end == Approx(-20.0).margin(0.01));
    CHECK(g2[2].end == Approx(-330.0).margin(0.01));
    CHECK(g2[3].end == Approx(-20.0).margin(0.01));  // not -380, although it is nearer
}

TEST_CASE("az mapping wrap_manager: never through the wrap point, the long way round instead",
          "[emulator][az_mapping]") {
    // Wrap point north (default): 350 -> 10 goes 340 deg anticlockwise; 403 is 43 - reverses at north.
    const auto travler = moves(Variant::travler_hal205, AzMapping::wrap_manager, 350.0, {"10", "403", "355"});
    CHECK(travler[0].end == Approx(10.0).margin(0.01));
    CHECK(travler[0].highest <= 350.1);
    CHECK(travler[1].end == Approx(43.0).margin(0.01));
    CHECK(travler[2].end == Approx(355.0).margin(0.01));
    CHECK(travler[2].highest <= 355.1);
    // Wrap point at 95 (wrap position 455): a north crossing stays on its branch, 95 is never crossed.
    const auto at95 = moves(Variant::travler_hal205, AzMapping::wrap_manager, 350.0, {"10", "90", "100"}, 95.0);
    CHECK(at95[0].end == Approx(370.0).margin(0.01));
    CHECK(at95[1].end == Approx(450.0).margin(0.01));
    CHECK(at95[2].end == Approx(100.0).margin(0.01));
    CHECK(at95[2].highest <= 450.1);
    // G2, wrap point north: the sector is -360..0; 10 from -5 is -350, the long way.
    const auto g2 = moves(Variant::carryout_g2, AzMapping::wrap_manager, 355.0, {"10", "350"});
    CHECK(g2[0].end == Approx(-350.0).margin(0.01));
    CHECK(g2[1].end == Approx(-10.0).margin(0.01));
    CHECK(g2[1].highest <= -9.9);
}
