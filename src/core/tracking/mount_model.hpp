// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The mount model (docs/sky.md §1): how the dish's axes sit against the sky. Clients aim and read
// in the sky frame; limits, cable wrap and the console stay in the dish's axes. Pure: the service
// maps every target and every reading through here, in one place (service_worker.hpp).
#pragma once

#include "base/azel.hpp"
#include "base/option_range.hpp"

namespace birdcage {

// Four terms, in degrees, with the names and signs of docs/sky.md §1. All zero (the default) is
// the identity, bit for bit.
struct MountModel {
    static constexpr OptionRange az_index_range{-180.0, 180.0, 0.01};
    static constexpr OptionRange el_index_range{-10.0, 10.0, 0.01};
    static constexpr OptionRange tilt_range{-10.0, 10.0, 0.01};

    double az_index = 0.0;    // the sky azimuth the dish looks at when its azimuth reads 0 (east +)
    double el_index = 0.0;    // how far the beam points above the elevation the dish reads
    double tilt_north = 0.0;  // the azimuth axis' lean from the zenith toward true north
    double tilt_east = 0.0;   // ... toward true east

    bool identity() const { return az_index == 0.0 && el_index == 0.0 && tilt_north == 0.0 && tilt_east == 0.0; }
};

// Where the beam points in the sky with the dish's axes at `dish`. The azimuth comes out as a
// difference from the one given (az + az_index, turned by the tilt by at most 180 either way), so
// it stays on the cable-wrap branch it came from (400 -> about 400 + az_index, never 40), and at
// the zenith, where the tilt's turn is undefined, it is az + az_index.
AzEl dish_to_sky(const MountModel& mount, AzEl dish);

// The dish's axes that point the beam at `sky`: the exact inverse (round trips agree to rounding).
// Its azimuth likewise stays near sky.az - az_index. A dish elevation whose el + el_index lies past
// 90 (the beam over the base's zenith) maps to the sky, but comes back as the same beam from the
// other side (az + 180): sky_to_dish() never answers an elevation above 90 - el_index.
AzEl sky_to_dish(const MountModel& mount, AzEl sky);

// The azimuth rate (deg/s) the dish's axis turns at while the beam follows a sky direction at
// `sky` moving at `az_rate`, `el_rate` (deg/s): the same motion seen in the dish's axes, for the
// cable-wrap choice, which only needs its sign. 0 stays 0.
double dish_azimuth_rate(const MountModel& mount, AzEl sky, double az_rate, double el_rate);

}  // namespace birdcage
