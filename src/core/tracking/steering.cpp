// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/steering.hpp"
#include "tracking/wrap.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

namespace birdcage {
namespace {

// The azimuth deadband is the on-sky one over cos(el) (an azimuth error shrinks on the sky by
// cos(el)); near the zenith cos(el) is floored here so the deadband stays finite.
constexpr double min_cos_el = 0.1;
// Deadband widening for a mount too slow for the satellite's rate: both deadbands grow by this
// factor per round until the steps need at most `max_motor_share` of the motor's time (one axis
// moves at a time; above that share the dish falls behind and its commands queue).
constexpr double widen_factor = 1.2;
constexpr int max_widen_rounds = 30;  // 1.2^30 ≈ 240x: far beyond any max_deadband_deg
constexpr double max_motor_share = 0.5;
// An axis rate below this (deg/s) is no motion: the axis is only re-aimed when off by a deadband.
constexpr double still_rate_dps = 1e-6;
// The estimate jumped when the satellite is this many deadbands *behind* the aim (a new pass,
// a corrected fit): re-aim at once rather than wait for it to come past.
constexpr double behind_deadbands = 3.0;
// A client's step along the track while the dish waits low for the pass (degrees): Gpredict's
// default 5 deg threshold, its lead of up to one more threshold, and the satellite's motion since.
// A larger step is a new pointing, not a direction.
constexpr double tracking_step_max_deg = 20.0;
// The rate azimuth_direction_hint() returns for a known direction: a sign, not a speed.
constexpr double direction_only_rate = 1e-3;
// The dish counts as waiting at its lowest elevation (where Gpredict parks it before AOS) within
// this many degrees of it.
constexpr double waiting_low_deg = 1.0;
// The longest the aim runs ahead of the satellite (seconds): a deadband ahead of an axis that has
// nearly stopped (a culmination) is not where the satellite is going.
constexpr double max_aim_ahead_s = 20.0;
// The azimuth deadband (degrees) while the dish waits at its floor for the satellite to rise.
constexpr double waiting_deadband_deg = 2.0;
constexpr int extent_samples = 8;
// Floors for a known motor's speed and acceleration (a zero would make every move endless).
constexpr double min_speed_dps = 0.01, min_accel_dps2 = 0.01;
// Rounds of "when does the leg end, so where is the aim, so how long is the leg": the travel grows
// with the root of the length or slower, so a mount that keeps up settles within a few.
constexpr int lead_rounds = 3;
// Weight of the newest measurement in the leg-overhead average (an EMA over about five steps).
constexpr double overhead_smoothing = 0.2;

Clock::duration seconds(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

std::optional<SteeringDecision> next_aim(const SteeringInput& in) {
    const auto current = in.predictor.predict(in.now);
    if (!current) {
        return std::nullopt;
    }
    auto clamp_el = [&](double el) { return std::clamp(el, in.el_min, in.el_max); };
    if (!current->moving) {
        const AzEl hold{current->position.az, clamp_el(current->position.el)};
        if (in.aim && std::fabs(azimuth_difference(in.aim->az, hold.az)) < same_angle_degrees &&
            std::fabs(in.aim->el - hold.el) < same_angle_degrees) {
            return std::nullopt;
        }
        return SteeringDecision{hold, 0.0, true, 0, 0.0};
    }
    const double overhead_s = std::max(in.pointing.command_overhead_s, in.measured_overhead_s);
    // A leg from its command to its end: the motor's start-up delay, then its travel over the
    // leg's length (as known, or the variant's curve at the pace the axis has shown on legs that long).
    auto move_time = [&](Axis axis, double degrees) {
        if (degrees < same_angle_degrees) {
            return 0.0;
        }
        if (const auto& known = in.pointing.known_motor) {
            const double a = std::max(known->accel_dps2, min_accel_dps2);
            const double v = std::max(known->speed_dps, min_speed_dps);
            return std::max(known->startup_s, 0.0) + trapezoid_move_seconds(degrees, v, a);
        }
        const double curve_s = std::chrono::duration<double>(estimated_move_time(in.dish, axis, degrees)).count();
        return in.motor.startup_s[static_cast<std::size_t>(axis)] + curve_s / in.motor.paces.pace(axis, degrees);
    };
    auto step_time = [&](Axis axis, double degrees) { return move_time(axis, degrees) + overhead_s; };
    const double cos_el = std::max(std::cos(clamp_el(current->position.el) * M_PI / 180.0), min_cos_el);
    const double az_rate = std::fabs(current->az_rate);
    // Above the elevation cap (the client's target at or over it) the dish holds the cap and
    // follows only the azimuth (docs/tracking.md §2.2), until a target comes back below the cap:
    // the fitted elevation would otherwise start descending before the satellite does.
    const bool above_cap = in.client_target && in.client_target->el >= in.el_max - same_angle_degrees;
    const double el_rate = above_cap || current->position.el >= in.el_max || current->position.el <= in.el_min
                               ? 0.0
                               : std::fabs(current->el_rate);
    // The deadband on the sky, per axis (PointingOptions::start_cost_s).
    double base_deadband = in.pointing.deadband_deg;
    double deadband_el = base_deadband, deadband_az_sky = base_deadband;
    if (const auto coarseness = in.predictor.client_coarseness_deg()) {
        base_deadband = std::max(base_deadband, std::min(in.pointing.client_threshold_share * *coarseness,
                                                         in.pointing.max_client_deadband_deg));
        // Only for a client without look-ahead, at most the share of its threshold (twice its
        // coarseness): beyond, a client that re-sends when the dish is off by its threshold would
        // re-send every cycle. A client that leads (Gpredict) keeps d0: with it the coarser steps
        // cost real Gpredict at 5 deg 0.25-0.42 deg RMS for a third fewer starts
        // (docs/benchmarks.md, "Motor starts as a cost").
        const bool without_look_ahead = in.predictor.client_without_look_ahead();
        const double widest = in.pointing.client_threshold_share * 2.0 * *coarseness;
        auto from_rate = [&](double sky_rate) {
            if (!without_look_ahead || in.pointing.start_cost_s <= 0.0 || sky_rate < still_rate_dps) {
                return base_deadband;
            }
            const double d = std::cbrt(0.75 * in.pointing.start_cost_s * base_deadband * base_deadband * sky_rate);
            return std::clamp(d, in.pointing.deadband_deg, std::max(base_deadband, widest));
        };
        deadband_el = from_rate(el_rate);
        deadband_az_sky = from_rate(az_rate * cos_el);
    }
    double deadband_az = deadband_az_sky / cos_el;
    for (int round = 0; round < max_widen_rounds; ++round) {
        const double busy = step_time(Axis::azimuth, 2 * deadband_az) * az_rate / (2 * deadband_az) +
                            step_time(Axis::elevation, 2 * deadband_el) * el_rate / (2 * deadband_el);
        // Beyond max_deadband_deg the aim would run so far ahead that the client sees the dish
        // off by more than its threshold and re-sends: a slow mount then just trails.
        if (busy <= max_motor_share || std::min(deadband_el, deadband_az * cos_el) * widen_factor >
                                           std::max(base_deadband, in.pointing.max_deadband_deg)) {
            break;
        }
        deadband_az *= widen_factor;
        deadband_el *= widen_factor;
    }
    // While the satellite is still below the dish's floor the dish waits there, and only needs to
    // be near where the satellite will come up: a client that sends every cycle meanwhile (its
    // limits wider than the dish's) would otherwise start the azimuth motor every second.
    if (current->position.el < in.el_min - deadband_el) {
        deadband_az = std::max(deadband_az, waiting_deadband_deg);
    }
    AzEl next = in.aim.value_or(in.dish_position.value_or(current->position));
    // When a leg started now ends: it runs from where the dish is to a deadband past where the
    // satellite will be then, and its length sets its time. A dish still short of its aim (a late
    // start, a slow leg) has further to go, and so aims further ahead.
    const AzEl from = in.dish_position.value_or(next);
    const double az_sign = current->az_rate >= 0 ? 1.0 : -1.0;
    const double el_sign = current->el_rate >= 0 ? 1.0 : -1.0;
    auto lead_s = [&](Axis axis, double deadband) {
        double lead = step_time(axis, 2 * deadband);
        for (int round = 0; round < lead_rounds; ++round) {
            const auto then = in.predictor.predict(in.now + seconds(lead));
            if (!then) {
                break;
            }
            const double length = axis == Axis::azimuth
                                      ? std::fabs(azimuth_difference(from.az, then->position.az) + az_sign * deadband)
                                      : std::fabs(clamp_el(then->position.el + el_sign * deadband) - from.el);
            lead = step_time(axis, length);
        }
        return std::min(lead, max_aim_ahead_s);
    };
    const double az_lead = lead_s(Axis::azimuth, deadband_az);
    const double el_lead = lead_s(Axis::elevation, deadband_el);
    const auto az_at = in.predictor.predict(in.now + seconds(az_lead));
    const auto el_at = in.predictor.predict(in.now + seconds(el_lead));
    if (!az_at || !el_at) {
        return std::nullopt;
    }
    bool changed = !in.aim;
    // Signed along-motion distance of the satellite past the aim: re-aim at +deadband, or when
    // the estimate jumped so that the aim is far off either way.
    auto re_aim = [](double past, double rate, double deadband) {
        if (rate < still_rate_dps) {
            return std::fabs(past) > deadband;
        }
        return past >= deadband || past < -behind_deadbands * deadband;
    };
    // The aim runs a deadband ahead of the estimate, but never past where the estimate stops (the
    // client's last target on a young track, the end of the extrapolation once its horizon has
    // passed): manual pointing ends exactly where it was sent (docs/tracking.md §7).
    // How long the axis takes to run a deadband past the aim, bounded: near a culmination the
    // elevation's rate falls to nothing, and a deadband ahead is then hours away (past the pass's
    // end, where the estimate stops below the horizon).
    auto time_to_cover = [&](double deadband, double rate) { return std::min(deadband / rate, max_aim_ahead_s); };
    auto stop_within_deadband = [&](Axis axis, double deadband, double rate) -> std::optional<Prediction> {
        if (rate < still_rate_dps) {
            return std::nullopt;
        }
        const double lead = axis == Axis::azimuth ? az_lead : el_lead;
        const auto beyond = in.predictor.predict(in.now + seconds(lead + time_to_cover(deadband, rate)));
        return beyond && !beyond->moving ? beyond : std::nullopt;
    };
    // The elevation the satellite reaches while the aim holds: the aim goes no higher than a
    // culmination and no lower than a low point, so the dish waits there instead of overshooting.
    auto el_reached = [&](double deadband, double rate) {
        const double span = time_to_cover(deadband, std::max(rate, still_rate_dps));
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (int k = 0; k <= extent_samples; ++k) {
            if (const auto p = in.predictor.predict(in.now + seconds(el_lead + span * k / extent_samples))) {
                lo = std::min(lo, p->position.el);
                hi = std::max(hi, p->position.el);
            }
        }
        return std::pair{lo, hi};
    };
    const double az_past = azimuth_difference(next.az, az_at->position.az) * az_sign;
    if (changed || re_aim(az_past, az_rate, deadband_az)) {
        if (az_rate < still_rate_dps) {
            next.az = az_at->position.az;
        } else if (const auto stop = stop_within_deadband(Axis::azimuth, deadband_az, az_rate)) {
            next.az = stop->position.az;
        } else {
            next.az = normalize_azimuth(az_at->position.az + az_sign * deadband_az);
        }
        changed = true;
    }
    const double el_wanted = above_cap ? in.el_max : clamp_el(el_at->position.el);
    const double el_past = (el_wanted - next.el) * el_sign;
    if (!in.aim || re_aim(el_past, el_rate, deadband_el)) {
        if (el_rate < still_rate_dps) {
            next.el = el_wanted;
        } else if (const auto stop = stop_within_deadband(Axis::elevation, deadband_el, el_rate)) {
            next.el = clamp_el(stop->position.el);
        } else if (above_cap) {
            next.el = clamp_el(el_wanted + el_sign * deadband_el);
        } else {
            const auto [lowest, highest] = el_reached(deadband_el, el_rate);
            next.el = clamp_el(std::clamp(el_wanted + el_sign * deadband_el, std::min(lowest, el_wanted),
                                          std::max(highest, el_wanted)));
        }
        changed = true;
    }
    if (!changed) {
        return std::nullopt;
    }
    SteeringDecision decision{next, current->az_rate, false, 0, 0.0};
    if (in.aim) {
        const double az_move = std::fabs(azimuth_difference(in.aim->az, next.az));
        const double el_move = std::fabs(next.el - in.aim->el);
        decision.legs = (az_move > same_angle_degrees ? 1 : 0) + (el_move > same_angle_degrees ? 1 : 0);
        decision.motion_s = move_time(Axis::azimuth, az_move) + move_time(Axis::elevation, el_move);
    }
    return decision;
}

// Before the estimate has a rate one case is already clear: a client following a satellite that
// is still below or near the dish's lowest elevation moves the dish, waiting there, a small step
// along the satellite's azimuth track, as Gpredict does from the AOS point. The direction of that
// step is the pass's, and knowing it now lets the one unwind a pass may need happen while the
// satellite is still out of reach rather than as it rises into the beam. The step is the client's,
// from its previous target: measured from the dish it would include the dish's own lead (predictive
// aims run a deadband ahead), and a dish led past a target reads as a pass going the other way.
// The client's first target has no previous one; the dish, not yet steered by this session, is
// where the client left it (at a coarse threshold the next target may come only once the satellite
// is well inside the beam, too late for an unwind before it).
double azimuth_direction_hint(const std::optional<Prediction>& estimate, const std::optional<AzEl>& dish,
                              const std::optional<AzEl>& previous_target, AzEl target, double el_min) {
    if (estimate && estimate->az_rate != 0.0) {
        return estimate->az_rate;
    }
    if (!dish || dish->el > el_min + waiting_low_deg || target.el > el_min + wrap::pass_start_band_deg) {
        return 0.0;
    }
    const double step = azimuth_difference(previous_target.value_or(*dish).az, target.az);
    const bool along_track = std::fabs(step) > same_angle_degrees && std::fabs(step) <= tracking_step_max_deg;
    return along_track ? std::copysign(direction_only_rate, step) : 0.0;
}

AzEl hold_aims_ahead(AimsAhead& held, AzEl client_target, const std::optional<Prediction>& estimate) {
    if (!estimate || !estimate->moving) {
        held = {};
        return client_target;
    }
    // Kept while the aim lies ahead of the client's target along the axis' motion (degrees) and the
    // pass reaches it soon enough to wait for it.
    auto keep = [](std::optional<double>& aim, double ahead, double rate) {
        const double along = rate >= 0.0 ? ahead : -ahead;
        if (aim && (std::fabs(rate) < still_rate_dps || along <= same_angle_degrees ||
                    along / std::fabs(rate) > max_aim_ahead_s)) {
            aim.reset();
        }
    };
    keep(held.az, held.az ? azimuth_difference(client_target.az, *held.az) : 0.0, estimate->az_rate);
    keep(held.el, held.el ? *held.el - client_target.el : 0.0, estimate->el_rate);
    return AzEl{held.az.value_or(client_target.az), held.el.value_or(client_target.el)};
}

void LegOverheadMeter::start(Clock::time_point now, int legs, double motion_s) {
    step_ = legs > 0 ? std::optional<Step>(Step{now, legs, motion_s}) : std::nullopt;
}

void LegOverheadMeter::finished(Clock::time_point now) {
    if (!step_) {
        return;
    }
    const Step step = *std::exchange(step_, std::nullopt);
    const double busy_s = std::chrono::duration<double>(now - step.started).count();
    const double overhead = std::max(0.0, (busy_s - step.motion_s) / step.legs);
    overhead_s_ = overhead_s_ ? (1.0 - overhead_smoothing) * *overhead_s_ + overhead_smoothing * overhead : overhead;
}

}  // namespace birdcage
