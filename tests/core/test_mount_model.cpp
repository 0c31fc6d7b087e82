// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The mount model (docs/sky.md §1): the two maps invert each other, keep the cable-wrap branch,
// are the identity at zero, and have the signs the page defines, on examples worked by hand.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <vector>

#include "tracking/mount_model.hpp"

using namespace birdcage;

namespace {

constexpr double tight = 1e-9;

double rad(double deg) {
    return deg * M_PI / 180.0;
}

double deg(double rad) {
    return rad * 180.0 / M_PI;
}

MountModel mount(double az_index, double el_index, double tilt_north, double tilt_east) {
    MountModel m;
    m.az_index = az_index;
    m.el_index = el_index;
    m.tilt_north = tilt_north;
    m.tilt_east = tilt_east;
    return m;
}

const std::vector<MountModel> mounts = {
    mount(6, 0, 0, 0),          mount(0, 0.8, 0, 0),   mount(0, 0, 1.2, 0),    mount(0, 0, 0, -0.5),
    mount(6, 0.8, 1.2, -0.5),   mount(-37, -3, -7, 9), mount(180, 10, 10, 10), mount(-180, -10, -10, -10),
    mount(0.01, 0.01, 0.01, 0), mount(95, 2.5, -4, 6),
};

// Dish azimuths on the variants' travels: the G2's negative window (-423.33..+23.33), the
// Trav'lers' beyond 360 (0..455).
std::vector<double> dish_azimuths() {
    std::vector<double> out;
    for (double az = -423.33; az <= 455.0; az += 23.7) {
        out.push_back(az);
    }
    return out;
}

std::string describe(const MountModel& m) {
    return "az_index " + std::to_string(m.az_index) + " el_index " + std::to_string(m.el_index) + " tilt_north " +
           std::to_string(m.tilt_north) + " tilt_east " + std::to_string(m.tilt_east);
}

}  // namespace

TEST_CASE("mount model: all four terms zero is the identity, bit for bit") {
    const MountModel zero;
    REQUIRE(zero.identity());
    for (const double az : {-423.33, -0.0, 0.0, 1e-300, 123.456789012345, 359.99999999, 400.0, 455.0}) {
        for (const double el : {-5.0, 0.0, 17.3, 89.999999, 90.0, 95.0}) {
            const AzEl sky = dish_to_sky(zero, {az, el});
            const AzEl dish = sky_to_dish(zero, {az, el});
            CHECK(std::memcmp(&sky, &dish, sizeof sky) == 0);
            CHECK(std::memcmp(&sky.az, &az, sizeof az) == 0);
            CHECK(std::memcmp(&sky.el, &el, sizeof el) == 0);
        }
    }
    CHECK(dish_azimuth_rate(zero, {100, 40}, -0.37, 0.2) == -0.37);
    CHECK_FALSE(mount(0, 0, 0, 1e-12).identity());
}

TEST_CASE("mount model: dish -> sky -> dish and sky -> dish -> sky agree to 1e-9, on the dish's wrap branch") {
    for (const MountModel& m : mounts) {
        INFO(describe(m));
        for (const double az : dish_azimuths()) {
            for (double el = -5.0; el <= 90.0; el += 4.75) {
                // The beam over the base's zenith comes back as the same beam from the other side
                // (mount_model.hpp); and within a whisker of that zenith the azimuth is noise.
                if (el + m.el_index > 89.9 || el + m.el_index < -89.9) {
                    continue;
                }
                INFO("dish " << az << " " << el);
                const AzEl sky = dish_to_sky(m, {az, el});
                const AzEl back = sky_to_dish(m, sky);
                CHECK(back.az == Approx(az).margin(tight));
                CHECK(back.el == Approx(el).margin(tight));
                // The sky azimuth stays on the branch the dish's was on: az + az_index plus the
                // tilt's turn, which is small away from the zeniths.
                if (el + m.el_index < 60.0 && el + m.el_index > -60.0) {
                    CHECK(std::fabs(sky.az - (az + m.az_index)) < 45.0);
                }
            }
        }
        for (const double az : {-423.33, -180.0, -0.5, 0.0, 42.0, 180.0, 359.5, 400.0, 455.0}) {
            for (double el = -5.0; el <= 89.5; el += 3.1) {
                INFO("sky " << az << " " << el);
                const AzEl dish = sky_to_dish(m, {az, el});
                if (dish.el + m.el_index > 89.9) {
                    continue;  // near the base's zenith: the azimuth is ill-conditioned there
                }
                const AzEl back = dish_to_sky(m, dish);
                CHECK(back.az == Approx(az).margin(tight));
                CHECK(back.el == Approx(el).margin(tight));
            }
        }
    }
}

TEST_CASE("mount model: the docs' example and the signs of docs/sky.md §1, worked by hand") {
    SECTION("az_index=6: the dish at 180 looks at 186, so a client's 180 is 174 on the dish") {
        const MountModel m = mount(6, 0, 0, 0);
        CHECK(dish_to_sky(m, {180, 40}).az == Approx(186).margin(tight));
        CHECK(dish_to_sky(m, {180, 40}).el == Approx(40).margin(tight));
        CHECK(sky_to_dish(m, {180, 40}).az == Approx(174).margin(tight));
        CHECK(sky_to_dish(m, {180, 40}).el == Approx(40).margin(tight));
        // Differences, not angles mod 360: the G2's -100 and the Trav'ler's 400 keep their branch.
        CHECK(dish_to_sky(m, {-100, 30}).az == Approx(-94).margin(tight));
        CHECK(dish_to_sky(m, {400, 30}).az == Approx(406).margin(tight));
        CHECK(sky_to_dish(m, {2, 30}).az == Approx(-4).margin(tight));
        CHECK(sky_to_dish(mount(-6, 0, 0, 0), {358, 30}).az == Approx(364).margin(tight));
    }
    SECTION("el_index: the beam above the reading") {
        const MountModel m = mount(0, 0.8, 0, 0);
        CHECK(dish_to_sky(m, {123, 20}).az == Approx(123).margin(tight));
        CHECK(dish_to_sky(m, {123, 20}).el == Approx(20.8).margin(tight));
        CHECK(sky_to_dish(m, {123, 20}).el == Approx(19.2).margin(tight));
    }
    SECTION("tilt_north=1 (the base's north side lower): looking south the beam is higher, north lower") {
        const MountModel m = mount(0, 0, 1, 0);
        CHECK(dish_to_sky(m, {180, 30}).el == Approx(31).margin(tight));
        CHECK(dish_to_sky(m, {180, 30}).az == Approx(180).margin(tight));
        CHECK(dish_to_sky(m, {0, 30}).el == Approx(29).margin(tight));
        CHECK(dish_to_sky(m, {0, 30}).az == Approx(0).margin(tight));
        // Looking east, the leaning axis turns the beam toward north: the unit vector
        // (cos 30, 0, sin 30) turned up toward north by 1 deg is (cos 30, sin 30 sin 1, sin 30 cos 1).
        const AzEl east = dish_to_sky(m, {90, 30});
        CHECK(east.az == Approx(90 - deg(std::atan(std::tan(rad(30)) * std::sin(rad(1))))).margin(tight));
        CHECK(east.el == Approx(deg(std::asin(0.5 * std::cos(rad(1))))).margin(tight));
        CHECK(east.az < 90.0);
        // The base's zenith leans 1 deg toward north.
        CHECK(dish_to_sky(m, {250, 90}).el == Approx(89).margin(tight));
        CHECK(azimuth_difference(0, dish_to_sky(m, {250, 90}).az) == Approx(0).margin(tight));
    }
    SECTION("tilt_east=1 (the base's east side lower): looking east the beam is lower, west higher") {
        const MountModel m = mount(0, 0, 0, 1);
        CHECK(dish_to_sky(m, {90, 30}).el == Approx(29).margin(tight));
        CHECK(dish_to_sky(m, {90, 30}).az == Approx(90).margin(tight));
        CHECK(dish_to_sky(m, {270, 30}).el == Approx(31).margin(tight));
        CHECK(dish_to_sky(m, {270, 30}).az == Approx(270).margin(tight));
        const AzEl north = dish_to_sky(m, {0, 30});
        CHECK(north.az == Approx(deg(std::atan(std::tan(rad(30)) * std::sin(rad(1))))).margin(tight));
        CHECK(north.el == Approx(deg(std::asin(0.5 * std::cos(rad(1))))).margin(tight));
        CHECK(dish_to_sky(m, {17, 90}).el == Approx(89).margin(tight));
        CHECK(dish_to_sky(m, {17, 90}).az == Approx(90).margin(tight));
    }
    SECTION("both tilts: the beam's angle from the tilted azimuth axis is 90 - (el + el_index)") {
        // Independent of the order of the rotations: the axis is R_E(tn) R_N(te) (0,0,1) =
        // (sin te, cos te sin tn, cos te cos tn), and a beam at base elevation e makes 90 - e with it.
        for (const MountModel& m : mounts) {
            INFO(describe(m));
            const double tn = rad(m.tilt_north), te = rad(m.tilt_east);
            const double axis[3] = {std::sin(te), std::cos(te) * std::sin(tn), std::cos(te) * std::cos(tn)};
            for (const double az : dish_azimuths()) {
                for (const double el : {-5.0, 0.0, 15.0, 45.0, 70.0}) {
                    const AzEl sky = dish_to_sky(m, {az, el});
                    const double v[3] = {std::cos(rad(sky.el)) * std::sin(rad(sky.az)),
                                         std::cos(rad(sky.el)) * std::cos(rad(sky.az)), std::sin(rad(sky.el))};
                    const double along = v[0] * axis[0] + v[1] * axis[1] + v[2] * axis[2];
                    CHECK(deg(std::asin(along)) == Approx(el + m.el_index).margin(1e-8));
                }
            }
        }
    }
}

TEST_CASE("mount model: at and near the zenith the azimuth is kept, and the beam is continuous") {
    SECTION("exactly at the zenith without tilt: the azimuth given, plus az_index") {
        const MountModel m = mount(6, 0.8, 0, 0);
        const AzEl sky = dish_to_sky(m, {123.4, 89.2});
        CHECK(sky.el == Approx(90).margin(tight));
        CHECK(sky.az == Approx(129.4).margin(1e-6));
        const AzEl dish = sky_to_dish(m, {-200, 90});
        CHECK(dish.el == Approx(89.2).margin(tight));
        CHECK(dish.az == Approx(-206).margin(1e-6));
    }
    SECTION("at the sky's zenith with tilt: the dish's axes are where the zenith is in the base") {
        // tilt_north=1: the sky's zenith is 1 deg south of the base's, whatever azimuth was asked.
        const MountModel m = mount(0, 0, 1, 0);
        for (const double az : {0.0, 123.0, 300.0}) {
            const AzEl dish = sky_to_dish(m, {az, 90});
            CHECK(dish.el == Approx(89).margin(tight));
            CHECK(azimuth_difference(180, dish.az) == Approx(0).margin(tight));
            CHECK(std::fabs(dish.az - az) <= 180.0);
        }
    }
    SECTION("near the zenith a small step of the beam is a small step on the sky") {
        const MountModel m = mount(6, 0.8, 1.2, -0.5);
        for (const double az : {10.0, 100.0, 190.0, 280.0}) {
            for (const double el : {89.0, 89.9, 89.99, 89.999}) {
                const AzEl dish = sky_to_dish(m, {az, el});
                const AzEl back = dish_to_sky(m, dish);
                // The same direction on the sphere, however the azimuth came out.
                const double separation = deg(std::acos(
                    std::min(1.0, std::sin(rad(el)) * std::sin(rad(back.el)) +
                                      std::cos(rad(el)) * std::cos(rad(back.el)) * std::cos(rad(back.az - az)))));
                CHECK(separation < 1e-6);
                CHECK(std::fabs(back.az - az) <= 180.0);
            }
        }
    }
}

TEST_CASE("mount model: an azimuth rate keeps its sign on the dish, and a pass across the dish's zenith turns it") {
    const MountModel m = mount(6, 0.8, 1.2, -0.5);
    CHECK(dish_azimuth_rate(m, {100, 40}, 0.0, 0.3) == 0.0);  // unknown stays unknown
    CHECK(dish_azimuth_rate(mount(6, 0, 0, 0), {100, 40}, -0.37, 0.2) == Approx(-0.37).margin(1e-9));
    for (const double az : {0.0, 90.0, 200.0, 350.0}) {
        CHECK(dish_azimuth_rate(m, {az, 30}, 0.5, 0.1) > 0.0);
        CHECK(dish_azimuth_rate(m, {az, 30}, -0.5, -0.1) < 0.0);
        CHECK(dish_azimuth_rate(m, {az, 30}, 1e-3, 0.0) == Approx(1e-3).epsilon(0.1));
    }
}
