// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Pointing direction and the angle arithmetic every layer shares.
#pragma once

#include <vector>

namespace birdcage {

struct AzEl {
    double az = 0;
    double el = 0;
};

enum class Axis { azimuth = 0, elevation = 1 };  // the firmware's motor ids

// Targets and commands carry two decimals (rotctl's %.2f, the firmware's readback): angles closer
// than this are the same angle.
inline constexpr double same_angle_degrees = 0.005;

// Maps any finite azimuth into [0, 360).
double normalize_azimuth(double az);

// Signed shortest rotation from `from` to `to`, in (-180, 180].
double azimuth_difference(double from, double to);

// The largest turn (degrees) between successive steps of a track, on the sphere (so the azimuth's
// own swing near the zenith is no turn). Steps shorter than `min_step_deg` carry only a client's
// rounding and timing and are left out. A satellite's track turns gently; a sky scan's serpentine
// turns by 90 and 180 degrees, a jogging user wherever they like.
double sharpest_turn_deg(const std::vector<AzEl>& track, double min_step_deg);

}  // namespace birdcage
