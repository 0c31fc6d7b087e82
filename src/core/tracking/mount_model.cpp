// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/mount_model.hpp"

#include <algorithm>
#include <cmath>

namespace birdcage {
namespace {

struct Vec {
    double x, y, z;  // east, north, up
};

constexpr double rad(double deg) {
    return deg * M_PI / 180.0;
}

constexpr double deg(double rad) {
    return rad * 180.0 / M_PI;
}

// Closer to the zenith than this (the horizontal part of a unit vector, ~2e-10 deg) the azimuth
// is rounding noise: the tilt then turns no azimuth.
constexpr double zenith_horizontal = 1e-12;

Vec unit(double az_deg, double el_deg) {
    const double a = rad(az_deg), e = rad(el_deg);
    return {std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
}

// R_E(t): turns up toward north (docs/sky.md §1).
Vec turn_up_north(Vec v, double t_deg) {
    const double c = std::cos(rad(t_deg)), s = std::sin(rad(t_deg));
    return {v.x, v.y * c + v.z * s, -v.y * s + v.z * c};
}

// R_N(t): turns up toward east.
Vec turn_up_east(Vec v, double t_deg) {
    const double c = std::cos(rad(t_deg)), s = std::sin(rad(t_deg));
    return {v.x * c + v.z * s, v.y, -v.x * s + v.z * c};
}

// `v` as azimuth and elevation, the azimuth as `near` plus the turn to v's own (within 180 either
// way), so it stays on `near`'s cable-wrap branch; `near` itself at the zenith.
AzEl direction(Vec v, double near) {
    const double horizontal = std::hypot(v.x, v.y);
    const double el = deg(std::atan2(v.z, horizontal));
    if (horizontal < zenith_horizontal) {
        return {near, el};
    }
    return {near + azimuth_difference(near, deg(std::atan2(v.x, v.y))), el};
}

}  // namespace

AzEl dish_to_sky(const MountModel& mount, AzEl dish) {
    if (mount.identity()) {
        return dish;
    }
    const double base_az = dish.az + mount.az_index;
    const Vec base = unit(base_az, dish.el + mount.el_index);
    return direction(turn_up_north(turn_up_east(base, mount.tilt_east), mount.tilt_north), base_az);
}

AzEl sky_to_dish(const MountModel& mount, AzEl sky) {
    if (mount.identity()) {
        return sky;
    }
    const Vec base = turn_up_east(turn_up_north(unit(sky.az, sky.el), -mount.tilt_north), -mount.tilt_east);
    const AzEl in_base = direction(base, sky.az);
    return {in_base.az - mount.az_index, in_base.el - mount.el_index};
}

double dish_azimuth_rate(const MountModel& mount, AzEl sky, double az_rate, double el_rate) {
    if (mount.identity() || az_rate == 0.0) {
        return az_rate;
    }
    // A step short enough to keep the sign of a turn near the dish's zenith, long enough to stay
    // clear of rounding: 0.01 deg along the faster coordinate.
    const double step_s = 0.01 / std::max(std::fabs(az_rate), std::fabs(el_rate));
    const AzEl from = sky_to_dish(mount, sky);
    const AzEl to = sky_to_dish(mount, {sky.az + az_rate * step_s, sky.el + el_rate * step_s});
    return azimuth_difference(from.az, to.az) / step_s;
}

}  // namespace birdcage
