// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/position_model.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace birdcage {
namespace {

// A reading moved less than this from the leg's start: the axis may not have started yet.
constexpr double started_degrees = 0.02;
// Two readings of one leg time the axis only once it moved at least this much between them:
// below, the readings' rounding dominates.
constexpr double timing_degrees = 0.1;
// The axis' pace against the motion model is believed within these bounds; beyond them a reading
// is more likely a glitch than a motor running at a fraction or a multiple of its known speed.
constexpr double min_pace = 0.25, max_pace = 4.0;
// Weight of the newest observation in a learnt pace (an average over a few legs).
constexpr double pace_smoothing = 0.3;
// A start-up delay beyond this is not believed: it is a motor that did not start, or a reading
// that came late, and the leg's own timeout deals with it.
constexpr double max_startup_s = 10.0;
// Weight of the newest observation in a learnt start-up delay.
constexpr double startup_smoothing = 0.3;
constexpr int inversion_steps = 40;  // bisection on a move of <= 20 s: well under a microsecond

double seconds(Clock::duration d) {
    return std::chrono::duration<double>(d).count();
}

// Signed degrees from `from` to `to` along the leg's axis (azimuth: the short way round).
double delta(Axis axis, double from, double to) {
    return axis == Axis::azimuth ? azimuth_difference(from, to) : to - from;
}

// The model time at which a move of `distance` has covered `done` degrees.
double time_at(const FirmwareProfile& dish, Axis axis, double distance, double done, double total) {
    double low = 0.0, high = total;
    for (int i = 0; i < inversion_steps; ++i) {
        const double mid = 0.5 * (low + high);
        (travelled_after(dish, axis, distance, mid) < done ? low : high) = mid;
    }
    return 0.5 * (low + high);
}

// A leg's geometry on its motion curve: how far it goes, which way, in how long (the model's
// duration), and how far along it a reading of the axis is.
struct LegCurve {
    LegCurve(const FirmwareProfile& dish, const LegMotion& of) : leg(of) {
        const double signed_distance = delta(leg.axis, leg.start, leg.to);
        distance = std::fabs(signed_distance);
        direction = signed_distance < 0.0 ? -1.0 : 1.0;
        total = seconds(estimated_move_time(dish, leg.axis, distance));
    }
    double done(double value) const { return std::clamp(direction * delta(leg.axis, leg.start, value), 0.0, distance); }

    const LegMotion& leg;
    double distance = 0.0, direction = 1.0, total = 0.0;
};

}  // namespace

double modelled_axis(const FirmwareProfile& dish, const LegMotion& leg, Clock::time_point now) {
    const LegCurve curve(dish, leg);
    const double distance = curve.distance, total = curve.total;
    if (distance < started_degrees || total <= 0.0) {
        return leg.latest.value;
    }
    auto done = [&](double value) { return curve.done(value); };

    const double prior = std::clamp(leg.pace, min_pace, max_pace);
    // Before its learnt start-up delay has run out the axis has not started; once a reading showed
    // it still unstarted after that, the start is no earlier than that reading.
    const double expected_start_s = std::max(leg.startup_s, 0.0);
    double model_time = 0.0;
    if (leg.latest.at <= leg.sent_at) {
        model_time = prior * std::max(0.0, seconds(now - leg.sent_at) - expected_start_s);  // no reading since the send
    } else if (const double latest = done(leg.latest.value); latest < started_degrees) {
        const double since_start =
            std::min(seconds(now - leg.sent_at) - expected_start_s, seconds(now - leg.latest.at));
        model_time = prior * std::max(0.0, since_start);  // not moving yet when last read
    } else {
        const double pace = observed_pace(dish, leg).value_or(prior);
        model_time = time_at(dish, leg.axis, distance, latest, total) + pace * seconds(now - leg.latest.at);
    }
    const double position = leg.start + curve.direction * travelled_after(dish, leg.axis, distance, model_time);
    return leg.axis == Axis::azimuth ? normalize_azimuth(position) : position;
}

void add_reading(LegMotion& leg, AxisReading reading) {
    if (leg.latest.at > leg.sent_at) {
        leg.previous = leg.latest;
    }
    leg.latest = reading;
    if (!leg.first_moving && reading.at > leg.sent_at &&
        std::fabs(delta(leg.axis, leg.start, reading.value)) >= started_degrees) {
        leg.first_moving = reading;
    }
}

std::optional<double> observed_pace(const FirmwareProfile& dish, const LegMotion& leg) {
    const LegCurve curve(dish, leg);
    const double distance = curve.distance, total = curve.total;
    auto done = [&](double value) { return curve.done(value); };
    const double latest = done(leg.latest.value);
    // Readings at the end of the curve (arrived) say nothing of the time spent getting there.
    if (total <= 0.0 || leg.latest.at <= leg.sent_at || latest > distance - started_degrees) {
        return std::nullopt;
    }
    auto pace_since = [&](const std::optional<AxisReading>& from) -> std::optional<double> {
        if (!from || from->at <= leg.sent_at || from->at >= leg.latest.at) {
            return std::nullopt;
        }
        const double earlier = done(from->value);
        if (earlier < started_degrees || latest - earlier < timing_degrees) {
            return std::nullopt;
        }
        const double modelled =
            time_at(dish, leg.axis, distance, latest, total) - time_at(dish, leg.axis, distance, earlier, total);
        return std::clamp(modelled / seconds(leg.latest.at - from->at), min_pace, max_pace);
    };
    if (const auto local = pace_since(leg.previous)) {
        return local;
    }
    return pace_since(leg.first_moving);
}

int AxisPaces::length_class(double distance) {
    if (distance < 0.25) {
        return 0;
    }
    return std::min(length_classes - 1, 1 + static_cast<int>(std::floor(std::log2(distance / 0.25))));
}

double AxisPaces::pace(Axis axis, double distance) const {
    return paces_[static_cast<std::size_t>(axis)][static_cast<std::size_t>(length_class(distance))].value_or(1.0);
}

bool AxisPaces::learnt(Axis axis, double distance) const {
    return paces_[static_cast<std::size_t>(axis)][static_cast<std::size_t>(length_class(distance))].has_value();
}

void AxisPaces::learn(Axis axis, double distance, double observed) {
    auto& pace = paces_[static_cast<std::size_t>(axis)][static_cast<std::size_t>(length_class(distance))];
    pace = pace ? (1.0 - pace_smoothing) * *pace + pace_smoothing * observed : observed;
}

std::optional<double> StartupDelays::observed(const FirmwareProfile& dish, const LegMotion& leg) {
    if (!leg.first_moving || leg.first_moving->at != leg.latest.at || leg.first_moving->at <= leg.sent_at) {
        return std::nullopt;
    }
    const LegCurve curve(dish, leg);
    if (curve.distance < started_degrees || curve.total <= 0.0) {
        return std::nullopt;
    }
    // The motion began in (earliest, latest]: after the last reading of this leg that did not show
    // it (or the send), by the reading that does.
    const double latest = seconds(leg.first_moving->at - leg.sent_at);
    const double earliest = leg.previous && leg.previous->at > leg.sent_at && leg.previous->at < leg.first_moving->at
                                ? seconds(leg.previous->at - leg.sent_at)
                                : 0.0;
    const double pace = std::clamp(leg.pace, min_pace, max_pace);
    const double covering =
        time_at(dish, leg.axis, curve.distance, curve.done(leg.first_moving->value), curve.total) / pace;
    return std::clamp(latest - covering, earliest, latest);
}

double StartupDelays::delay(Axis axis, double initial) const {
    return delays_[static_cast<std::size_t>(axis)].value_or(initial);
}

void StartupDelays::learn(Axis axis, double observed_seconds) {
    const double bounded = std::clamp(observed_seconds, 0.0, max_startup_s);
    auto& delay = delays_[static_cast<std::size_t>(axis)];
    delay = delay ? (1.0 - startup_smoothing) * *delay + startup_smoothing * bounded : bounded;
}

AzEl modelled_position(const FirmwareProfile& dish, AzEl last, const MovingAxes& moving, Clock::time_point now) {
    if (moving.azimuth) {
        last.az = modelled_axis(dish, *moving.azimuth, now);
    }
    if (moving.elevation) {
        last.el = modelled_axis(dish, *moving.elevation, now);
    }
    return last;
}

}  // namespace birdcage
