// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage_sim/motor.hpp"

#include <algorithm>
#include <cmath>

namespace birdcage::sim {

double quantize_to_steps(double deg, int steps_per_rev) {
    if (steps_per_rev <= 0)
        return deg;
    const double step = 360.0 / steps_per_rev;
    return std::round(deg / step) * step;
}

double normalize_360(double deg) {
    double folded = std::fmod(deg, 360.0);
    if (folded < 0.0)
        folded += 360.0;
    if (folded >= 360.0)
        folded -= 360.0;
    return folded;
}

double nearest_wrap_branch(double az, double current, double min, double max) {
    const double base = normalize_360(az);
    double best = std::clamp(base, min, max);
    double best_distance = -1.0;
    const int lowest_turn = static_cast<int>(std::floor((min - base) / 360.0)) - 1;
    const int highest_turn = static_cast<int>(std::ceil((max - base) / 360.0)) + 1;
    for (int turn = lowest_turn; turn <= highest_turn; ++turn) {
        const double candidate = base + 360.0 * turn;
        if (candidate < min - 1e-9 || candidate > max + 1e-9)
            continue;
        const double distance = std::abs(candidate - current);
        if (best_distance < 0.0 || distance < best_distance) {
            best = std::clamp(candidate, min, max);
            best_distance = distance;
        }
    }
    return best;
}

double wrap_sector_start(double wrap_point, double min, double max) {
    const double first = normalize_360(wrap_point) + 360.0 * std::floor((min - normalize_360(wrap_point)) / 360.0);
    double best = first;
    double best_overlap = -1.0;
    for (double start = first; start < max; start += 360.0) {
        const double overlap = std::min(max, start + 360.0) - std::max(min, start);
        if (overlap > best_overlap + 1e-9) {
            best = start;
            best_overlap = overlap;
        }
    }
    return best;
}

double wrap_manager_target(double az, double wrap_point, double current, double min, double max) {
    const double start = wrap_sector_start(wrap_point, min, max);
    const double offset = normalize_360(az - wrap_point);
    if (offset < 1e-9 || offset > 360.0 - 1e-9) {
        return std::abs(current - start) <= std::abs(current - (start + 360.0)) ? start : start + 360.0;
    }
    return start + offset;
}

Axis::Axis(AxisParams params, double position) : params_(params), position_(position), target_(position) {}

void Axis::move_to(double target) {
    target_ = quantize_to_steps(std::clamp(target, params_.min, params_.max), params_.steps_per_rev);
    if (!moving_)
        delay_left_ = params_.startup_delay;
    moving_ = true;
}

void Axis::stop() {
    if (!moving_)
        return;
    if (delay_left_ > 0.0) {  // not started yet: nothing to ramp down
        target_ = position_;
        delay_left_ = 0.0;
        moving_ = false;
        return;
    }
    const double stopping_distance = velocity_ * std::abs(velocity_) / (2.0 * params_.max_accel);
    target_ = std::clamp(position_ + stopping_distance, params_.min, params_.max);
}

void Axis::hold(double seconds) {
    target_ = position_;
    velocity_ = 0.0;
    delay_left_ = seconds;
    moving_ = true;
}

void Axis::set_position(double position) {
    position_ = position;
    target_ = position;
    velocity_ = 0.0;
    moving_ = false;
    delay_left_ = 0.0;
}

double Axis::move_time(const AxisParams& params, double distance) {
    const double d = std::abs(distance);
    const double v = params.max_velocity;
    const double a = params.max_accel;
    if (d <= v * v / a)
        return params.startup_delay + 2.0 * std::sqrt(d / a);
    return params.startup_delay + d / v + v / a;
}

// Piecewise-analytic integration: each pass of the loop runs one phase (brake, accelerate,
// cruise, final deceleration) up to its end or up to dt, whichever comes first.
double Axis::advance(double dt) {
    const double accel = params_.max_accel;
    const double vmax = params_.max_velocity;
    const auto integrate = [this](double acceleration, double t) {
        position_ += velocity_ * t + 0.5 * acceleration * t * t;
        velocity_ += acceleration * t;
    };
    if (moving_ && delay_left_ > 0.0) {
        const double waited = std::min(dt, delay_left_);
        delay_left_ -= waited;
        dt -= waited;
    }
    for (int phase = 0; moving_ && dt > 0.0 && phase < 32; ++phase) {
        const double offset = target_ - position_;
        const double direction = offset >= 0.0 ? 1.0 : -1.0;
        const double distance = std::abs(offset);
        const double speed = velocity_ * direction;  // negative: heading away from the target

        if (speed < 0.0) {
            const double t_stop = -speed / accel;
            const double t = std::min(dt, t_stop);
            integrate(direction * accel, t);
            if (t == t_stop)
                velocity_ = 0.0;
            dt -= t;
            continue;
        }
        const double braking_distance = speed * speed / (2.0 * accel);
        const double t_to_peak =
            speed < vmax ? (std::sqrt(accel * distance + 0.5 * speed * speed) - speed) / accel : 0.0;
        if (braking_distance >= distance * (1.0 - 1e-9) - 1e-9 || (speed < vmax && t_to_peak <= 1e-12)) {
            if (speed <= 1e-12 || distance <= 1e-12) {
                position_ = target_;
                velocity_ = 0.0;
                moving_ = false;
                break;
            }
            const double t_end = 2.0 * distance / speed;
            if (dt >= t_end) {
                position_ = target_;
                velocity_ = 0.0;
                moving_ = false;
                dt -= t_end;
                break;
            }
            integrate(-direction * speed * speed / (2.0 * distance), dt);
            dt = 0.0;
            break;
        }
        if (speed < vmax) {
            const double t = std::min({dt, (vmax - speed) / accel, t_to_peak});
            integrate(direction * accel, t);
            dt -= t;
            continue;
        }
        const double t_cruise = (distance - braking_distance) / vmax;
        const double t = std::min(dt, t_cruise);
        velocity_ = direction * vmax;
        position_ += velocity_ * t;
        dt -= t;
    }
    return moving_ ? 0.0 : std::max(dt, 0.0);
}

MotorModel::MotorModel(AxisParams az, AxisParams el, AxisParams skew, double az_pos, double el_pos, double skew_pos)
    : axes_{Axis(az, az_pos), Axis(el, el_pos), Axis(skew, skew_pos)} {}

void MotorModel::enqueue(std::size_t axis, double target) {
    if (axis == axis_skew) {
        axes_[axis_skew].move_to(target);
        return;
    }
    queue_.push_back({axis, target});
}

void MotorModel::enqueue_hold(std::size_t axis, double seconds) {
    queue_.push_back({axis, 0.0, seconds});
}

void MotorModel::stop_all() {
    queue_.clear();
    for (auto& axis : axes_)
        axis.stop();
}

bool MotorModel::serial_axis_busy() const {
    return axes_[axis_az].moving() || axes_[axis_el].moving();
}

bool MotorModel::moving() const {
    return serial_axis_busy() || axes_[axis_skew].moving() || !queue_.empty();
}

void MotorModel::start_next_move() {
    const Move next = queue_.front();
    queue_.pop_front();
    if (next.hold_seconds > 0.0)
        axes_[next.axis].hold(next.hold_seconds);
    else
        axes_[next.axis].move_to(next.target);
}

void MotorModel::advance(double dt) {
    axes_[axis_skew].advance(dt);
    while (dt > 0.0) {
        Axis* active = nullptr;
        for (std::size_t index : {axis_az, axis_el}) {
            if (axes_[index].moving())
                active = &axes_[index];
        }
        if (active == nullptr) {
            if (queue_.empty())
                break;
            start_next_move();
            continue;
        }
        dt = active->advance(dt);
        if (active->moving())
            break;
    }
}

}  // namespace birdcage::sim
