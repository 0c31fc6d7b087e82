// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Plain types that several layers pass to each other: time, the legs an axis may be running, the
// LNB supply. Values only, no behaviour: a pure module (pointing, steering, the position model)
// includes this and nothing of the console, the dish or the service.
#pragma once

#include <chrono>
#include <optional>

#include "base/azel.hpp"

namespace birdcage {

using Clock = std::chrono::steady_clock;
using Deadline = Clock::time_point;

// One axis reading taken during a leg (display degrees, dish time).
struct AxisReading {
    double value = 0.0;
    Clock::time_point at{};
};

// A single-axis leg whose axis may still be moving, for a position model between polls: sent at
// `sent_at` from `start` towards `to` (display degrees). `latest` is the axis' last reading;
// `previous` the one before it and `first_moving` the first that showed the axis under way, both
// taken during this leg (add_reading()).
struct LegMotion {
    Axis axis = Axis::azimuth;
    double start = 0.0, to = 0.0;
    Clock::time_point sent_at{};
    AxisReading latest;
    std::optional<AxisReading> previous, first_moving;
    double pace = 1.0;  // until its readings time it: the axis' pace on legs this long (AxisPaces)
    // Seconds from the command to the first motion: the axis' start-up delay (StartupDelays), plus
    // what the firmware still ran before it (`a` queues behind a moving motor, docs/firmware.md §2).
    double startup_s = 0.0;
};

// At most one leg per axis: the one in flight, and the one before it on the other axis while it may
// still be covering the last of its arrival tolerance.
struct MovingAxes {
    std::optional<LegMotion> azimuth, elevation;
    bool empty() const { return !azimuth && !elevation; }
};

// The LNB supply voltage selects the polarisation the LNB receives (docs/firmware.md 6.3):
// 13 V (`lnbdc odu`) = vertical, 18 V (`lnbdc stb`, the boot default) = horizontal.
enum class LnbSupply { odu_13v, stb_18v };

inline constexpr LnbSupply lnb_boot_default = LnbSupply::stb_18v;

}  // namespace birdcage
