// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage/base/azel.hpp"

#include <cmath>

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

}  // namespace birdcage
