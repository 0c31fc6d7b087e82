// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "base/azel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

namespace birdcage {

double normalize_azimuth(double az) {
    double wrapped = std::fmod(az, 360.0);
    if (wrapped < 0) {
        wrapped += 360.0;
    }
    // fmod of a tiny negative value plus 360 rounds to exactly 360.
    if (wrapped >= 360.0) {
        wrapped = 0.0;
    }
    return wrapped + 0.0;  // turns -0.0 into +0.0
}

double azimuth_difference(double from, double to) {
    double delta = normalize_azimuth(to) - normalize_azimuth(from);
    if (delta > 180.0) {
        delta -= 360.0;
    } else if (delta <= -180.0) {
        delta += 360.0;
    }
    return delta;
}

double sharpest_turn_deg(const std::vector<AzEl>& track, double min_step_deg) {
    using Vec = std::array<double, 3>;
    auto unit = [](AzEl p) {
        const double a = p.az * M_PI / 180.0, e = p.el * M_PI / 180.0;
        return Vec{std::cos(e) * std::sin(a), std::cos(e) * std::cos(a), std::sin(e)};
    };
    const double min_chord = 2.0 * std::sin(min_step_deg * M_PI / 360.0);
    double sharpest = 0.0;
    std::optional<Vec> previous_point, previous_step;
    for (const AzEl& direction : track) {
        const Vec point = unit(direction);
        if (!previous_point) {
            previous_point = point;
            continue;
        }
        const Vec step{point[0] - (*previous_point)[0], point[1] - (*previous_point)[1],
                       point[2] - (*previous_point)[2]};
        const double length = std::sqrt(step[0] * step[0] + step[1] * step[1] + step[2] * step[2]);
        if (length < min_chord) {
            continue;  // measured from the last point kept, so slow steps still add up
        }
        if (previous_step) {
            const Vec& p = *previous_step;
            const double cos_turn = (p[0] * step[0] + p[1] * step[1] + p[2] * step[2]) /
                                    (length * std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
            sharpest = std::max(sharpest, std::acos(std::clamp(cos_turn, -1.0, 1.0)) * 180.0 / M_PI);
        }
        previous_step = step;
        previous_point = point;
    }
    return sharpest;
}

}  // namespace birdcage
