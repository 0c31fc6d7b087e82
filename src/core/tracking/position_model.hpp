// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Where the dish is between polls, pure. A leg in flight runs its axis from where it stood when the
// leg was sent to the leg's target along the variant's motion model (variants.hpp:
// travelled_after). The latest reading places the axis on that curve (how far along it is) and,
// with the reading before it in the same leg, times it (how fast the real axis goes through the
// curve), so the model follows the dish's pace rather than the table's guess of it: the Trav'lers
// publish no speed or acceleration (docs/firmware.md 3.4). Paces seen on earlier legs carry over
// to the next leg of about the same length (AxisPaces), before its own readings time it. A motor
// may also start moving only some time after the command (StartupDelays): the curve then begins
// that much after the send, and readings before it show an axis not yet started, not a stopped one.
#pragma once

#include <array>
#include <optional>

#include "base/azel.hpp"
#include "base/plain_types.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

// `last`: the last reading; `moving`: the legs whose axes may still be moving (none: the dish is at
// `last`); `now`: dish time.
AzEl modelled_position(const FirmwareProfile& dish, AzEl last, const MovingAxes& moving, Clock::time_point now);

// A reading taken during the leg: the latest (the one it replaces becomes `previous`), and the
// first that shows the axis under way.
void add_reading(LegMotion& leg, AxisReading reading);

// One axis of that: where the leg's axis is at `now`.
double modelled_axis(const FirmwareProfile& dish, const LegMotion& leg, Clock::time_point now);

// The pace (model seconds per real second) the leg's readings show, if they time it: over the
// last two readings where they are far enough apart (the pace where the axis is now: the curve's
// shape may differ from the motor's), else from the first reading under way to the latest.
std::optional<double> observed_pace(const FirmwareProfile& dish, const LegMotion& leg);

// How fast each axis has run through the motion model's curve, per leg length: the model's
// durations come from a fit whose error depends on the length (a fixed acceleration takes
// sqrt(length) on short moves, the fit does not), so one factor per axis would not do.
class AxisPaces {
public:
    double pace(Axis axis, double distance) const;  // 1 until a leg of that length was timed
    bool learnt(Axis axis, double distance) const;
    void learn(Axis axis, double distance, double observed);

private:
    static constexpr int length_classes = 8;  // < 0.25 deg, then doubling up to >= 16 deg
    static int length_class(double distance);
    std::array<std::array<std::optional<double>, length_classes>, 2> paces_{};
};

// How long each axis takes to start moving after a move command from rest, learnt from the legs'
// own readings. A leg times its axis' start once a reading shows it under way: the motion began
// after the reading before it that did not (or the send) and no later than this one, and the
// motion curve (at the leg's pace) says how long covering what this reading shows took. Kept as
// an average over legs, so one late reading or a glitch moves it only part of the way.
class StartupDelays {
public:
    // The delay (seconds) to plan with: `initial` until a leg of that axis was timed.
    double delay(Axis axis, double initial = 0.0) const;
    bool learnt(Axis axis) const { return delays_[static_cast<std::size_t>(axis)].has_value(); }
    // The start-up delay the readings of `leg` show, if they show it yet: at the reading that first
    // shows the axis under way (the latest), for a leg sent with the axis at rest.
    static std::optional<double> observed(const FirmwareProfile& dish, const LegMotion& leg);
    void learn(Axis axis, double observed_seconds);

private:
    std::array<std::optional<double>, 2> delays_{};
};

// What the dish's own legs have shown of its motors (the move driver learns it, docs/tracking.md
// §1.5): per axis the start-up delay, and how fast the axis runs through the variant's motion curve
// per leg length once under way. A leg of d degrees then ends the delay plus the curve's time for d
// over that pace after its command. Default: no delay, the variant's curve as it is.
struct MotorTiming {
    std::array<double, 2> startup_s{};
    AxisPaces paces;
};

}  // namespace birdcage
