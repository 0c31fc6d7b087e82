// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Motor physics of the emulated dish: pure functions of simulated time, no clock, no I/O.
// Every motion is a time-optimal trapezoid (or triangle) with a velocity cap and a symmetric
// acceleration limit, integrated analytically so results do not depend on the step size
// (docs/tracking.md §1.4).
#pragma once

#include <array>
#include <cstddef>
#include <deque>

namespace birdcage::sim {

struct AxisParams {
    double max_velocity;  // deg/s
    double max_accel;     // deg/s^2
    double min;           // mechanical travel, deg (targets are clamped into it)
    double max;
    int steps_per_rev;  // 0 = continuous; otherwise targets snap to whole steps (docs/firmware.md §6.4)
    // Seconds between a move command to an axis at rest and its first motion (relay, driver
    // wake-up, firmware latency). docs/firmware.md gives only whole-move timings, so a motor that
    // starts late and then runs faster fits them as well as one that starts at once.
    double startup_delay = 0.0;
};

// Snaps an angle to the nearest whole motor step; identity when steps_per_rev is 0.
double quantize_to_steps(double deg, int steps_per_rev);

// The angle equal to `az` modulo 360 that lies inside [min, max] and is closest to
// `current`; used to map a 0..360 target into a cable-wrap window (docs/firmware.md §2, §6.4).
// If no branch fits, the nearest window edge.
double nearest_wrap_branch(double az, double current, double min, double max);

// Folds an angle into [0, 360).
double normalize_360(double deg);

// A firmware wrap manager with its wrap point at display azimuth `wrap_point` (emulator.hpp
// AzMapping::wrap_manager): the lower end of the 360-degree sector between two mechanical angles
// equal to the wrap point modulo 360 that overlaps [min, max] most (ties: the lower sector).
double wrap_sector_start(double wrap_point, double min, double max);
// The mechanical angle in that sector equal to `az` modulo 360; a value on the wrap point itself
// goes to the sector end nearer `current`. May lie outside [min, max] where the sector does.
double wrap_manager_target(double az, double wrap_point, double current, double min, double max);

class Axis {
public:
    Axis(AxisParams params, double position);

    void move_to(double target);         // clamps into travel and quantises; may be called while moving
    void stop();                         // decelerate at max_accel and stay where the ramp ends
    void set_position(double position);  // re-zero without motion (homing calibration)
    // Busy without motion for `seconds` (a firmware task pausing between two of its moves): the
    // axis counts as moving, so moves queued behind wait.
    void hold(double seconds);
    // Returns the part of dt left over after the axis came to rest on its target.
    double advance(double dt);

    double position() const { return position_; }
    double velocity() const { return velocity_; }
    double target() const { return target_; }
    bool moving() const { return moving_; }
    const AxisParams& params() const { return params_; }

    // Time a move of `distance` degrees takes from rest to rest under these parameters, the
    // start-up delay included.
    static double move_time(const AxisParams& params, double distance);

private:
    AxisParams params_;
    double position_;
    double velocity_ = 0.0;
    double target_;
    bool moving_ = false;
    double delay_left_ = 0.0;  // of startup_delay, before the current move's first motion
};

enum AxisIndex : std::size_t { axis_az = 0, axis_el = 1, axis_skew = 2 };

// Azimuth and elevation never run at the same time: moves for them execute one after another
// in the order requested (docs/firmware.md §2, §3.4). Skew (Trav'ler) runs independently.
class MotorModel {
public:
    MotorModel(AxisParams az, AxisParams el, AxisParams skew, double az_pos, double el_pos, double skew_pos = 0.0);

    void enqueue(std::size_t axis, double target);
    void enqueue_hold(std::size_t axis, double seconds);  // Axis::hold() in the queue's order
    void stop_all();                                      // abort: drop queued moves and ramp every axis down
    void advance(double dt);

    const Axis& axis(std::size_t index) const { return axes_[index]; }
    Axis& axis(std::size_t index) { return axes_[index]; }
    bool moving() const;
    std::size_t queued() const { return queue_.size(); }

private:
    struct Move {
        std::size_t axis;
        double target;
        double hold_seconds = 0.0;  // > 0: a hold (enqueue_hold), not a move
    };
    bool serial_axis_busy() const;
    void start_next_move();

    std::array<Axis, 3> axes_;
    std::deque<Move> queue_;
};

}  // namespace birdcage::sim
