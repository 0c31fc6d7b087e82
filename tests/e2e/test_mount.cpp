// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end: the mount model's conf (docs/sky.md §1). The emulated dish has no mount of its own:
// its axes are what the backend must send for a target on the sky, and `p` must answer the sky.
// The dish axes expected are computed here from docs/sky.md, apart from the core's code.
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

using namespace std::chrono_literals;
using birdcage::sim::Variant;

namespace {

constexpr double az_index = 6.0, el_index = 0.8, tilt_north = 1.2, tilt_east = -0.5;
const std::vector<std::string> mount_conf = {"-C", "az_index=6",     "-C", "el_index=0.8",
                                             "-C", "tilt_north=1.2", "-C", "tilt_east=-0.5"};

double rad(double deg) {
    return deg * M_PI / 180.0;
}

double deg(double rad) {
    return rad * 180.0 / M_PI;
}

struct DishAxes {
    double az;  // 0..360
    double el;
};

// docs/sky.md §1, sky -> dish axes: the tilt undone as one rotation matrix (the transpose of
// R_E(tilt_north) R_N(tilt_east)), then the index terms.
DishAxes dish_axes_for(double sky_az, double sky_el) {
    const double n = rad(tilt_north), e = rad(tilt_east);
    // R_E(n) R_N(e), row by row.
    const double m[3][3] = {{std::cos(e), 0.0, std::sin(e)},
                            {-std::sin(n) * std::sin(e), std::cos(n), std::sin(n) * std::cos(e)},
                            {-std::cos(n) * std::sin(e), -std::sin(n), std::cos(n) * std::cos(e)}};
    const double v[3] = {std::cos(rad(sky_el)) * std::sin(rad(sky_az)), std::cos(rad(sky_el)) * std::cos(rad(sky_az)),
                         std::sin(rad(sky_el))};
    double base[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            base[i] += m[j][i] * v[j];  // the transpose undoes the rotation
        }
    }
    double az = deg(std::atan2(base[0], base[1])) - az_index;
    az = std::fmod(az + 720.0, 360.0);
    return {az, deg(std::atan2(base[2], std::hypot(base[0], base[1]))) - el_index};
}

// Where the dish rests, in its own axes: at rest within the emulator's step quantisation (the G2
// steps 0.009 deg in azimuth, 0.0144 in elevation) and the commands' two decimals.
constexpr double rests_within = 0.02;

// `p` until it answers within 0.1 of (az, el); what it last answered.
bool answers(e2e::Rig& rig, double az, double el, std::vector<double>& reported) {
    return e2e::wait_until(
        [&] {
            reported = e2e::numbers(rig.rotctl({"p"}).out);
            return reported.size() == 2 && e2e::angle_between(reported[0], az) <= 0.1 &&
                   std::fabs(reported[1] - el) <= 0.1;
        },
        10s);
}

}  // namespace

TEST_CASE("with a mount model P 180 40 rests the dish on its own axes for that sky direction, p answers 180 40",
          "[e2e][mount]") {
    struct Case {
        const char* name;
        Variant variant;
        int model;
        double start_az, start_el;  // the emulated dish's mechanical azimuth at start
        double sky_az, sky_el;
        double mechanical_az;  // where the dish's azimuth ends, cable-wrap turns included
    };
    const DishAxes g2_axes = dish_axes_for(180.0, 40.0);
    const DishAxes travler_axes = dish_axes_for(16.0, 40.0);
    const Case cases[] = {
        // The G2's travel is -423.33..+23.33: 180 on the sky is about -186 on its axes.
        {"G2", Variant::carryout_g2, 90105, -100.0, 30.0, 180.0, 40.0, g2_axes.az - 360.0},
        // 2 on the sky is about -4 on the G2's axes: a target the map takes across the dish's 0.
        {"G2 across its 0", Variant::carryout_g2, 90105, 10.0, 30.0, 2.0, 40.0, dish_axes_for(2.0, 40.0).az - 360.0},
        // A Trav'ler at 350 on its 0..455 travel: 16 on the sky is about 10 on its axes, reached
        // past 360 (the cable-wrap branch is the dish's own), not back round to 10.
        {"Trav'ler HAL 2.05 past 360", Variant::travler_hal205, 90102, 350.0, 30.0, 16.0, 40.0,
         travler_axes.az + 360.0},
    };
    // The helper's own check: the base's zenith, seen from the sky, is the tilted axis
    // (sin te, cos te sin tn, cos te cos tn) (docs/sky.md: R_E(t) (0,0,1) = (0, sin t, cos t),
    // R_N(t) (0,0,1) = (sin t, 0, cos t)).
    const double te = rad(tilt_east), tn = rad(tilt_north);
    const double axis[3] = {std::sin(te), std::cos(te) * std::sin(tn), std::cos(te) * std::cos(tn)};
    REQUIRE(dish_axes_for(deg(std::atan2(axis[0], axis[1])), deg(std::asin(axis[2]))).el + el_index ==
            Approx(90.0).margin(1e-6));
    for (const Case& c : cases) {
        DYNAMIC_SECTION(c.name) {
            const DishAxes want = dish_axes_for(c.sky_az, c.sky_el);
            INFO("dish axes for " << c.sky_az << " " << c.sky_el << ": " << want.az << " " << want.el << ", mechanical "
                                  << c.mechanical_az);
            std::vector<std::string> args = mount_conf;
            args.insert(args.end(), {"-C", "leapfrog=0"});
            e2e::Rig rig(e2e::dish_options(c.variant, c.start_az, c.start_el), c.model, args);
            REQUIRE(rig.rotctl({"P", std::to_string(c.sky_az), std::to_string(c.sky_el)}).exit_code == 0);
            CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), want.az, want.el, rests_within); }, 60s));
            INFO("the dish rests at " << rig.dish().true_position().az << " " << rig.dish().true_position().el
                                      << ", mechanical " << rig.dish().true_mechanical_az());
            CHECK(rig.dish().true_mechanical_az() == Approx(c.mechanical_az).margin(rests_within));
            std::vector<double> reported;
            CHECK(answers(rig, c.sky_az, c.sky_el, reported));
            INFO("p: " << (reported.size() == 2 ? std::to_string(reported[0]) + " " + std::to_string(reported[1])
                                                : std::string("?")));
            // `_` names the mount and the target the backend took, on the sky (rotctl -m 2 would
            // show only its first 63 characters).
            e2e::RotctldConnection client(rig.port());
            const std::string info = client.ask("_", 1);
            INFO(info);
            char sky_target[64];
            std::snprintf(sky_target, sizeof sky_target, "; sky target az %.2f el %.2f", c.sky_az, c.sky_el);
            CHECK(info.find("; mount az_index 6.00 el_index 0.80 tilt_north 1.20 tilt_east -0.50") !=
                  std::string::npos);
            CHECK(info.find(sky_target) != std::string::npos);
            CHECK(rig.dish().hazards_received() == 0);
        }
    }
}

// The emulator's dish set up with a mount error (--mount X) and the backend told X: the beam ends
// on the sky where the client pointed it, within the motors' step quantisation; without the conf
// it ends degrees away. The beam's sky direction is the emulator's own (its dish->sky of the true
// axes), written apart from the backend's.
TEST_CASE("the conf that corrects a dish set up with a mount error is that mount itself (20 sky positions)",
          "[e2e][mount]") {
    birdcage::sim::Mount mount;
    mount.az_index = az_index;
    mount.el_index = el_index;
    mount.tilt_north = tilt_north;
    mount.tilt_east = tilt_east;
    // A fixed draw over the G2's window (18..65 in dish elevation: keep sky targets inside it).
    std::vector<std::pair<double, double>> targets;
    std::uint32_t state = 20261207u;
    const auto next = [&state] {
        state = state * 1664525u + 1013904223u;
        return static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
    };
    for (int i = 0; i < 20; ++i) {
        targets.emplace_back(360.0 * next(), 22.0 + 40.0 * next());
    }
    const auto pointing_error = [&](bool with_conf) {
        birdcage::sim::Options options = e2e::dish_options(Variant::carryout_g2, -100.0, 30.0);
        options.mount = mount;
        std::vector<std::string> args = {"-C", "leapfrog=0"};
        if (with_conf) {
            args.insert(args.end(), mount_conf.begin(), mount_conf.end());
        }
        e2e::Rig rig(options, 90105, args);
        double sum_sq = 0.0, worst = 0.0;
        for (const auto& [az, el] : targets) {
            REQUIRE(rig.rotctl({"P", std::to_string(az), std::to_string(el)}).exit_code == 0);
            // At rest where the backend sends it: the dish axes for the target, or the target
            // itself taken as dish axes without the conf.
            const DishAxes rest = with_conf ? dish_axes_for(az, el) : DishAxes{az, el};
            REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), rest.az, rest.el, rests_within); }, 60s));
            const auto beam = rig.dish().beam_direction();
            // The angle on the sky between where the beam points and the target.
            const double d = deg(std::acos(std::clamp(
                std::sin(rad(beam.el)) * std::sin(rad(el)) +
                    std::cos(rad(beam.el)) * std::cos(rad(el)) * std::cos(rad(e2e::angle_between(beam.az, az))),
                -1.0, 1.0)));
            UNSCOPED_INFO("target " << az << " " << el << ": beam " << beam.az << " " << beam.el << ", off " << d);
            sum_sq += d * d;
            worst = std::max(worst, d);
        }
        CHECK(rig.dish().hazards_received() == 0);
        return std::pair{std::sqrt(sum_sq / static_cast<double>(targets.size())), worst};
    };
    const auto [rms_corrected, worst_corrected] = pointing_error(true);
    const auto [rms_raw, worst_raw] = pointing_error(false);
    WARN("pointing error on the sky, 20 positions: with the mount's conf RMS "
         << rms_corrected << " deg (max " << worst_corrected << "), without it RMS " << rms_raw << " deg (max "
         << worst_raw << ")");
    CHECK(rms_corrected <= 0.05);
    CHECK(worst_corrected <= 0.1);
    CHECK(rms_raw >= 3.0);
}
