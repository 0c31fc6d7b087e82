// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The range a user-settable option accepts, declared next to the option it bounds so that every
// front end (the Hamlib conf keys, their `rotctl -L` listing) takes it from the same place.
#pragma once

namespace birdcage {

struct OptionRange {
    double min;
    double max;
    double step;  // the granularity a front end offers

    constexpr bool contains(double value) const { return value >= min && value <= max; }
};

}  // namespace birdcage
