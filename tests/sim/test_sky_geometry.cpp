// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator's sky geometry: docs/sky.md §1's mount map (its examples, round trips, branches,
// the zenith), UTC text, and sanity of the look angles (their precision is checked against PyEphem
// and a second formulation by tests/sim/sky_positions.py).
#include <birdcage_sim/sky_geometry.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace birdcage::sim;

TEST_CASE("mount: the examples of docs/sky.md section 1", "[sim][mount]") {
    // A G2 whose BACK mark was turned 6 degrees east of north: reading 180 it looks at 186, and a
    // target at 180 is reached at the reading 174.
    const Mount turned{6.0, 0.0, 0.0, 0.0};
    CHECK(dish_to_sky(turned, {180.0, 45.0}).az == Approx(186.0).margin(1e-9));
    CHECK(dish_to_sky(turned, {180.0, 45.0}).el == Approx(45.0).margin(1e-9));
    CHECK(sky_to_dish(turned, {180.0, 45.0}).az == Approx(174.0).margin(1e-9));

    // tilt_north = 1: the base's north side is lower, so looking south the beam is a degree higher
    // and looking north a degree lower.
    const Mount north_low{0.0, 0.0, 1.0, 0.0};
    const AzEl south = dish_to_sky(north_low, {180.0, 30.0});
    CHECK(south.el == Approx(31.0).margin(1e-9));
    CHECK(south.az == Approx(180.0).margin(1e-9));
    CHECK(dish_to_sky(north_low, {0.0, 30.0}).el == Approx(29.0).margin(1e-9));
    // Looking east or west the tilt leans the beam sideways, not up.
    CHECK(dish_to_sky(north_low, {90.0, 0.0}).el == Approx(0.0).margin(1e-9));

    // tilt_east = 1: the east side is lower; looking east the beam is lower, west higher.
    const Mount east_low{0.0, 0.0, 0.0, 1.0};
    CHECK(dish_to_sky(east_low, {90.0, 30.0}).el == Approx(29.0).margin(1e-9));
    CHECK(dish_to_sky(east_low, {270.0, 30.0}).el == Approx(31.0).margin(1e-9));

    // el_index: the beam above the reading.
    const AzEl raised = dish_to_sky({0.0, 2.0, 0.0, 0.0}, {100.0, 20.0});
    CHECK(raised.az == Approx(100.0).margin(1e-9));
    CHECK(raised.el == Approx(22.0).margin(1e-9));
}

TEST_CASE("mount: sky -> dish inverts dish -> sky, on the cable-wrap branch it was given", "[sim][mount]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> term(-3.0, 3.0), index(-20.0, 20.0), az(-420.0, 450.0), el(-5.0, 80.0);
    double worst = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const Mount mount{index(rng), term(rng), term(rng), term(rng)};
        const AzEl dish{az(rng), el(rng)};
        const AzEl sky = dish_to_sky(mount, dish);
        const AzEl back = sky_to_dish(mount, sky);
        worst = std::max({worst, std::abs(back.az - dish.az), std::abs(back.el - dish.el)});
        // The branch: the sky azimuth stays within the tilts' reach of the reading plus az_index.
        CHECK(std::abs(sky.az - (dish.az + mount.az_index)) < 20.0);
    }
    CHECK(worst < 1e-9);
    // A Trav'ler's 400 maps to about 400 + az_index, never to 40 + az_index.
    CHECK(dish_to_sky({6.0, 0.0, 0.5, -0.5}, {400.0, 40.0}).az == Approx(406.0).margin(1.0));
    CHECK(sky_to_dish({6.0, 0.0, 0.5, -0.5}, {-100.0, 40.0}).az == Approx(-106.0).margin(1.0));
}

TEST_CASE("mount: all four terms zero is the identity, exactly, and the zenith keeps its azimuth", "[sim][mount]") {
    const Mount none;
    CHECK(none.identity());
    const AzEl dish{123.456789012345, 33.333333333333};
    CHECK(dish_to_sky(none, dish).az == dish.az);
    CHECK(dish_to_sky(none, dish).el == dish.el);
    CHECK(sky_to_dish(none, dish).az == dish.az);
    CHECK(sky_to_dish(none, dish).el == dish.el);

    const AzEl zenith = dish_to_sky({6.0, 0.0, 0.0, 0.0}, {200.0, 90.0});
    CHECK(zenith.el == Approx(90.0).margin(1e-9));
    CHECK(zenith.az == Approx(206.0).margin(1e-6));
    // With the axis tilted north by 2, the dish reading 88 toward the south sees the sky's zenith.
    const AzEl tilted = dish_to_sky({0.0, 0.0, 2.0, 0.0}, {180.0, 88.0});
    CHECK(tilted.el == Approx(90.0).margin(1e-9));
    CHECK(std::isfinite(tilted.az));
}

TEST_CASE("sky time: ISO-8601 UTC both ways", "[sim][sky]") {
    CHECK(parse_utc("2026-06-21T12:00:00Z") == Approx(1782043200.0));
    CHECK(parse_utc("2026-06-21 12:00:00") == Approx(1782043200.0));
    CHECK(parse_utc("2026-06-21T14:00:00+02:00") == Approx(1782043200.0));
    CHECK(parse_utc("2026-06-21T12:00Z") == Approx(1782043200.0));
    CHECK(parse_utc("2026-06-21") == Approx(1782043200.0 - 12 * 3600));
    CHECK(parse_utc("2026-06-21T12:00:00.250Z") == Approx(1782043200.25));
    CHECK(parse_utc("1969-12-31T23:59:59Z") == Approx(-1.0));
    CHECK(parse_utc("2024-02-29T23:59:59Z") == Approx(1709251199.0));
    for (const char* bad : {"", "2026-02-29T00:00:00Z", "2026-13-01", "2026-06-21T24:00:00Z", "2026-06-21T12:00:00Q",
                            "21.06.2026", "2026-06-21T12:00:00."}) {
        INFO(bad);
        CHECK_FALSE(parse_utc(bad));
    }
    CHECK(format_utc(1782043200.0) == "2026-06-21T12:00:00.000Z");
    CHECK(format_utc(1782043200.1234) == "2026-06-21T12:00:00.123Z");
    CHECK(format_utc(1782043259.9996) == "2026-06-21T12:01:00.000Z");
    CHECK(format_utc(-0.5) == "1969-12-31T23:59:59.500Z");
    CHECK(parse_utc(format_utc(1709251199.25)) == Approx(1709251199.25));
}

TEST_CASE("sky geometry: look angles where the answer is known", "[sim][sky]") {
    // A station under a geostationary satellite sees it at the zenith; one on its meridian due
    // south (north of the equator) or due north (south of it).
    CHECK(geostationary_direction({0.0, 10.0, 0.0}, 10.0).el == Approx(90.0).margin(1e-6));
    const AzEl boulder = geostationary_direction({40.0, -105.0, 1655.0}, -105.0);
    CHECK(boulder.az == Approx(180.0).margin(1e-9));
    // The spherical-Earth textbook value for latitude 40 is 43.7; the ellipsoid moves it < 0.2.
    CHECK(boulder.el == Approx(43.7).margin(0.2));
    CHECK(geostationary_direction({-33.9, 151.2, 0.0}, 151.2).az == Approx(0.0).margin(1e-9));
    // Beyond 81.3 degrees of longitude difference the satellite is below the horizon.
    CHECK(geostationary_direction({0.0, 0.0, 0.0}, 85.0).el < 0.0);

    // The Sun: near the zenith at an equinox noon on the equator; at a northern summer solstice
    // noon at latitude 52 it culminates near 90 - 52 + 23.44.
    const AzEl equinox = sun_direction({0.0, 0.0, 0.0}, *parse_utc("2026-03-20T12:07:00Z"));
    CHECK(equinox.el > 89.0);
    const AzEl solstice = sun_direction({52.0, 0.0, 0.0}, *parse_utc("2026-06-21T12:02:00Z"));
    CHECK(solstice.el == Approx(61.44).margin(0.05));
    CHECK(solstice.az == Approx(180.0).margin(1.0));
    // It moves west at about 15 degrees an hour of hour angle.
    const AzEl later = sun_direction({52.0, 0.0, 0.0}, *parse_utc("2026-06-21T13:02:00Z"));
    CHECK(later.az > 200.0);
    CHECK(angular_distance(solstice, later) == Approx(15.0 * std::cos(23.44 * 3.14159265 / 180)).margin(1.0));

    CHECK(angular_distance({10.0, 0.0}, {20.0, 0.0}) == Approx(10.0));
    CHECK(angular_distance({0.0, 89.0}, {180.0, 89.0}) == Approx(2.0));
}
