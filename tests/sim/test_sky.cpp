// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator's sky model against the real G2 scan it is built from (sim/data/g2-ku-skyscan).
#include <birdcage_sim/sky.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using birdcage::sim::LnbSupply;
using birdcage::sim::SkyModel;

TEST_CASE("sky: at 13 V the measured grid is reproduced at its points and interpolated between them", "[sim][sky]") {
    const SkyModel sky(1);
    // Lines of scan_data.txt: `174.0 43.0 562`, `110.0 18.0 409`, `202.0 40.0 545`.
    CHECK(sky.expected_rssi(174.0, 43.0, LnbSupply::odu_13v) == Approx(562.0));
    CHECK(sky.expected_rssi(110.0, 18.0, LnbSupply::odu_13v) == Approx(409.0));
    CHECK(sky.expected_rssi(202.0, 40.0, LnbSupply::odu_13v) == Approx(545.0));
    const double between = sky.expected_rssi(174.5, 43.0, LnbSupply::odu_13v);
    const double left = sky.expected_rssi(174.0, 43.0, LnbSupply::odu_13v);
    const double right = sky.expected_rssi(175.0, 43.0, LnbSupply::odu_13v);
    CHECK(between == Approx((left + right) / 2));
    CHECK(SkyModel::inside_measured_grid(174.0, 43.0));
    CHECK_FALSE(SkyModel::inside_measured_grid(100.0, 43.0));
    // A different floor shifts the measured grid with it.
    CHECK(SkyModel(1, 500.0).expected_rssi(174.0, 43.0, LnbSupply::odu_13v) == Approx(661.0));
}

TEST_CASE("sky: outside the grid the floor and the satellite belt", "[sim][sky]") {
    const SkyModel sky(1);
    // Far from the belt: the floor.
    CHECK(sky.expected_rssi(20.0, 80.0, LnbSupply::odu_13v) == Approx(401.0).margin(0.01));
    // The belt continues beyond the grid's western edge: Galaxy 13 at 237.42/25.1 has a fitted beam.
    CHECK(sky.expected_rssi(241.0, 25.1, LnbSupply::odu_13v) > 401.5);
    // The catalogue is all there, with the fit's amplitudes.
    CHECK(SkyModel::satellites().size() == 44);
}

TEST_CASE("sky: 18 V hears the other polarisation", "[sim][sky]") {
    const SkyModel sky(1);
    // The strong DIRECTV slot fades to its cross-polar leak; a slot silent at 13 V appears.
    CHECK(sky.expected_rssi(174.0, 43.0, LnbSupply::odu_13v) - sky.expected_rssi(174.0, 43.0, LnbSupply::stb_18v) > 50);
    bool some_slot_appears = false;
    for (const auto& s : SkyModel::satellites()) {
        if (s.amplitude_18v > 50 && sky.expected_rssi(s.az, s.el, LnbSupply::stb_18v) >
                                        sky.expected_rssi(s.az, s.el, LnbSupply::odu_13v) + 20) {
            some_slot_appears = true;
        }
    }
    CHECK(some_slot_appears);
}

TEST_CASE("sky: reads are deterministic by seed, and averaging n reads shrinks the noise ~1/sqrt(n)", "[sim][sky]") {
    SkyModel a(7), b(7);
    for (int i = 0; i < 50; ++i)
        CHECK(a.read(150.0, 30.0, LnbSupply::odu_13v) == b.read(150.0, 30.0, LnbSupply::odu_13v));

    SkyModel sky(3);
    const double truth = sky.expected_rssi(150.0, 30.0, LnbSupply::odu_13v);
    const auto spread = [&](int n) {
        double sum_sq = 0;
        const int trials = 400;
        for (int t = 0; t < trials; ++t) {
            double sum = 0;
            for (int i = 0; i < n; ++i)
                sum += sky.read(150.0, 30.0, LnbSupply::odu_13v);
            sum_sq += std::pow(sum / n - truth, 2);
        }
        return std::sqrt(sum_sq / trials);
    };
    const double one = spread(1), hundred = spread(100);
    CHECK(one == Approx(8.0).epsilon(0.15));
    CHECK(hundred == Approx(0.8).margin(0.3));  // 8 / sqrt(100), plus the rounding to whole counts
}
