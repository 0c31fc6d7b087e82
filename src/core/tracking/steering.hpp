// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Predictive steering, pure: from the estimate of where the satellite goes (TargetPredictor), the
// dish's limits and speeds, and the aim last handed to the controller, the next aim — or none
// when the dish should stay where it is aimed. No I/O, no threads, no clock: the caller passes
// the time. RotatorService calls it once per worker step; tests call it directly.
#pragma once

#include <optional>

#include "base/azel.hpp"
#include "base/option_range.hpp"
#include "base/plain_types.hpp"
#include "firmware/variants.hpp"
#include "tracking/pointing.hpp"
#include "tracking/position_model.hpp"

namespace birdcage {

// A motor described outright rather than learnt: its start-up delay (seconds from the command to
// the first motion), top speed (deg/s) and acceleration (deg/s^2), on a trapezoidal profile. The
// backend never assumes one; a caller that knows the motor (the benchmark's oracle) may say so.
struct KnownMotor {
    double startup_s = 0.0, speed_dps = 1.0, accel_dps2 = 1.0;
};

struct PointingOptions {
    static constexpr OptionRange deadband_range_deg{0.01, 5.0, 0.01};
    static constexpr OptionRange client_threshold_share_range{0.0, 1.0, 0.05};
    static constexpr OptionRange start_cost_range_s{0.0, 600.0, 1.0};
    static constexpr OptionRange known_startup_range_s{0.0, 30.0, 0.1};
    static constexpr OptionRange known_rate_range{0.01, 1000.0, 0.01};  // deg/s, deg/s^2

    // Unset: the variant's default (FirmwareProfile::predictive_by_default), resolved at start()
    // once the variant is known. Leapfrog is applied by the Controller (its option).
    std::optional<PointingMode> mode;
    // Predictive mode: the largest on-sky error (degrees) allowed per axis before the dish is moved
    // again. The dish is aimed this far ahead, so the error sweeps -deadband..+deadband instead of
    // lagging; it is widened where the motor cannot step that finely at the satellite's rate.
    double deadband_deg = 0.1;
    // Time from deciding a move to the motor starting (worker period, command exchange), in the
    // dish's seconds; the aim is taken this much (plus the move time) ahead.
    double command_overhead_s = 0.1;
    // How far the deadband may be widened for a slow mount.
    double max_deadband_deg = 0.5;
    // The client re-sends only when the dish is off by more than its threshold, and the estimator
    // learns that threshold from the targets (TargetPredictor::client_coarseness_deg()). Holding the
    // dish much tighter than the client looks costs motor starts and buys nothing it asked for:
    // the deadband grows to this share of the learned threshold (0: never), at most
    // max_client_deadband_deg. At 0.5 it cut the G2's motor commands by 80% at Gpredict's 5 deg
    // threshold (iss-45: 807 -> 131) for 0.05-0.2 deg more RMS, and by 10-20% at 0.5 deg with the
    // same RMS (docs/benchmarks.md).
    double client_threshold_share = 0.5;
    double max_client_deadband_deg = 1.0;
    // What a motor start costs, in seconds of the dish off by that deadband (d0), for a client
    // without look-ahead (one that leads keeps d0: docs/tracking.md §6): per axis the
    // deadband then minimises the error's square over time plus this cost per start. An axis that
    // steps by 2d at r deg/s on the sky errs by (2d)^2/12 on average and starts r/(2d) times a
    // second, so d = (3/4 * cost * d0^2 * r)^(1/3), between `deadband_deg` and half the client's
    // threshold: a fast axis steps coarser, a slow one finer (docs/tracking.md §6, "A motor start
    // has a cost"). At 15 s, with a client without look-ahead at 5 deg on the held-out pass, the
    // G2 started its motors 56 times (from 89) for 2.01 deg RMS (from 1.79), HAL 2.05 65 times
    // (from 78) for 2.50 deg (from 2.38): fewer starts than the Python system at a lower error
    // (docs/benchmarks.md, "Motor starts as a cost"). 0: d0 on both axes.
    double start_cost_s = 15.0;
    std::optional<KnownMotor> known_motor;  // unset: the motor as the legs' readings show it
    PredictorSettings predictor;
};

struct SteeringInput {
    Clock::time_point now;
    const TargetPredictor& predictor;
    const FirmwareProfile& dish;
    double el_min = 0.0, el_max = 90.0;  // the controller's effective limits
    PointingOptions pointing;
    double measured_overhead_s = 0.0;   // per leg beyond start-up and motion, as measured (0: unknown)
    std::optional<AzEl> aim;            // what was last handed to the controller
    std::optional<AzEl> client_target;  // the client's last target, as sent
    std::optional<AzEl> dish_position;  // the dish's last reading
    MotorTiming motor;                  // start-up and motion per leg, as learnt
};

struct SteeringDecision {
    AzEl aim;
    // The satellite's azimuth rate (deg/s) for the controller's cable-wrap choice; 0 when the
    // estimate is stationary (the caller may supply a direction of its own).
    double az_rate = 0.0;
    bool holding = false;   // a stationary target: aim at it, no lead
    int legs = 0;           // axes that move (for timing the step); 0 on the first aim
    double motion_s = 0.0;  // their estimated motor time, start-up delays included
};

// Aims each axis `deadband` ahead of where the satellite will be when the move completes (its
// start-up delay and its travel over the move's length, iterated: the length depends on the aim), and
// moves it again once the satellite is `deadband` past that aim, so the error sweeps
// -deadband..+deadband around zero instead of trailing. nullopt: keep the current aim.
std::optional<SteeringDecision> next_aim(const SteeringInput& input);

}  // namespace birdcage

namespace birdcage {

// The azimuth direction a pass is taking, for the controller's cable-wrap choice, when the
// estimate has no rate yet (deg/s; only its sign matters; 0 = unknown): `previous_target` and
// `target` are the client's last two targets, as sent (no previous one: the dish's position stands
// in for it). See steering.cpp.
double azimuth_direction_hint(const std::optional<Prediction>& estimate, const std::optional<AzEl>& dish,
                              const std::optional<AzEl>& previous_target, AzEl target, double el_min);

// The aims predictive steering leaves behind when it hands the dish back to the client's targets
// (a slow mount steers predictively only while the orbit is trusted): they run ahead of the
// client's target along the pass, by the motor's lead. Going back to that target and forward
// again costs two motor starts and reverses the axis by the whole lead (4.5 deg on a Trav'ler,
// docs/tracking.md §6), while the pass reaches the aim within seconds.
struct AimsAhead {
    std::optional<double> az, el;
    bool any() const { return az || el; }
};

// The target to hand the controller: the client's, except on an axis whose aim is still held.
// An axis is let go for good once the client's target reaches its aim, or once the estimate says
// the pass will not reach it soon (it slows, turns, or the aim is far ahead).
AzEl hold_aims_ahead(AimsAhead& held, AzEl client_target, const std::optional<Prediction>& estimate);

// What one leg costs beyond its start-up delay and motion as learnt (exchange, polling, whatever the
// learnt motor misses), timed on steered steps from the aim to the dish idle again, and smoothed.
// next_aim() aims that much further ahead. The start-up delay and the travel are the driver's
// (MotorTiming): counting them here as well would lead by them twice. Only a step the controller ran alone is timed: whatever else it was given
// meanwhile (the client's targets as sent once the orbit lost trust, a re-aim before the dish was
// idle, a receiver job, a stop, a recovery) would be counted as this step's overhead: one G2 step
// can span 19 s of such legs, which would put the aims 16 deg ahead of the satellite
// (docs/tracking.md §1.5).
class LegOverheadMeter {
public:
    // A steered step of `legs` legs and `motion_s` of motor time starts from an idle dish.
    void start(Clock::time_point now, int legs, double motion_s);
    // The controller was given something else: the step in progress proves nothing.
    void interrupt() { step_.reset(); }
    // The dish is idle again: the step in progress, if any, is measured.
    void finished(Clock::time_point now);
    bool timing() const { return step_.has_value(); }
    // Per leg, beyond the motion; none before the first step.
    std::optional<double> overhead_s() const { return overhead_s_; }

private:
    struct Step {
        Clock::time_point started;
        int legs = 0;
        double motion_s = 0.0;
    };
    std::optional<Step> step_;
    std::optional<double> overhead_s_;
};

}  // namespace birdcage
