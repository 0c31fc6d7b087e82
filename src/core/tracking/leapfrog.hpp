// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Leap-frog: lead the target in the direction of travel to make up for mechanical lag.
#pragma once

#include "base/azel.hpp"

namespace birdcage {

// Per axis: lag > 2 deg adds 1.0 deg, lag > 1 deg adds 0.5 deg, in the direction of travel.
// Azimuth lag is the shortest way round (359 -> 1 is +2); the result's azimuth is in [0, 360).
// Elevation lag nudges elevation (upstream travler_rotor.py nudged azimuth there: docs/firmware.md 12.1).
// The caller clamps the result to the variant's limits.
AzEl apply_leapfrog(AzEl target, AzEl current);

}  // namespace birdcage
