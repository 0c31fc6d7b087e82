// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include "tracking/leapfrog.hpp"

using birdcage::apply_leapfrog;
using birdcage::AzEl;

TEST_CASE("leapfrog: thresholds per axis, in the direction of travel") {
    struct Case {
        const char* legend;
        AzEl target, current, expected;
    };
    const Case cases[] = {
        {"no lag", {180, 45}, {180, 45}, {180, 45}},
        {"lag of exactly 1 deg is not led", {181, 46}, {180, 45}, {181, 46}},
        {"lag between 1 and 2 deg leads 0.5", {181.5, 46.5}, {180, 45}, {182, 47}},
        {"lag of exactly 2 deg leads 0.5", {182, 47}, {180, 45}, {182.5, 47.5}},
        {"lag above 2 deg leads 1.0", {190, 60}, {180, 45}, {191, 61}},
        {"falling axes are led downwards", {170, 30}, {180, 45}, {169, 29}},
    };
    for (const auto& c : cases) {
        INFO(c.legend);
        const AzEl led = apply_leapfrog(c.target, c.current);
        CHECK(led.az == Approx(c.expected.az));
        CHECK(led.el == Approx(c.expected.el));
    }
}

TEST_CASE("leapfrog: elevation lag nudges elevation, not azimuth (upstream travler_rotor.py bug)") {
    // Upstream's second block compared elevations but added the lead to target_az (docs/firmware.md 12.1).
    const AzEl led = apply_leapfrog({100, 50}, {100, 40});
    CHECK(led.az == Approx(100));
    CHECK(led.el == Approx(51));
}

TEST_CASE("leapfrog: azimuth lag is taken the short way across north") {
    SECTION("359 -> 1 is +2 deg: lead 0.5 eastwards") {
        CHECK(apply_leapfrog({1, 45}, {359, 45}).az == Approx(1.5));
    }
    SECTION("359 -> 0.5 stays in [0, 360) (upstream sent a 0 -0.5)") {
        CHECK(apply_leapfrog({0.5, 45}, {359, 45}).az == Approx(1.0));
    }
    SECTION("1 -> 355 is -6 deg: lead 1 westwards") {
        CHECK(apply_leapfrog({355, 45}, {1, 45}).az == Approx(354));
    }
    SECTION("lead past north wraps") {
        CHECK(apply_leapfrog({359.8, 45}, {350, 45}).az == Approx(0.8));
    }
}
