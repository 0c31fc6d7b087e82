// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/leapfrog.hpp"

#include <cmath>

namespace birdcage {
namespace {

// The upstream rotor scripts' thresholds (docs/firmware.md §12.1): more than 2 deg behind -> lead 1.0, more than 1 deg -> 0.5.
double lead_for(double delta) {
    const double magnitude = std::fabs(delta);
    double lead = 0.0;
    if (magnitude > 2.0) {
        lead = 1.0;
    } else if (magnitude > 1.0) {
        lead = 0.5;
    }
    return delta < 0 ? -lead : lead;
}

}  // namespace

AzEl apply_leapfrog(AzEl target, AzEl current) {
    AzEl led = target;
    led.az = normalize_azimuth(target.az + lead_for(azimuth_difference(current.az, target.az)));
    led.el = target.el + lead_for(target.el - current.el);
    return led;
}

}  // namespace birdcage
