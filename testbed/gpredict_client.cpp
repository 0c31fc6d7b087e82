// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "gpredict_client.hpp"

#include "rotctl_client.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

namespace bench {

using Clock = std::chrono::steady_clock;

namespace {

// How far a reported position is from where the dish truly was while the question was in flight:
// the closest point of the true path between the two readings (a straight line in az/el over the
// sub-millisecond round trip). Comparing against one reading taken after the reply would charge
// the backend for the round trip times the time scale (at 5x and 65 deg/s, ~0.04 deg).
double distance_to_path(Direction reported, Direction before, Direction after) {
    constexpr int steps = 16;
    const double daz = az_difference(after.az, before.az);
    double best = angle_between(reported, before);
    for (int i = 1; i <= steps; ++i) {
        const double f = static_cast<double>(i) / steps;
        best = std::min(best, angle_between(reported, {before.az + f * daz, before.el + f * (after.el - before.el)}));
    }
    return best;
}

}  // namespace

GpredictClient::GpredictClient(const Pass& pass, ClientSettings settings, const birdcage::sim::Emulator& dish,
                               double time_scale, int rotctld_port, double pass_clock_start)
    : pass_(pass),
      settings_(settings),
      dish_(dish),
      time_scale_(time_scale),
      port_(rotctld_port),
      sim_origin_(dish.sim_time()),
      pass_origin_(pass_clock_start) {}

double GpredictClient::pass_now() const {
    return pass_time_of(dish_.sim_time());
}

void GpredictClient::sleep_sim(double seconds) const {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds / time_scale_));
}

Direction GpredictClient::lead_target(double now, Direction current) const {
    // Gpredict searches in days with the cycle as the coarsest and a quarter cycle as the finest
    // step; here the same in seconds.
    double time_delta = pass_.los() - now;
    double step = std::max(time_delta / 2.0, settings_.cycle_s);
    Direction future = current;
    while (step > settings_.cycle_s / 4.0) {
        future = pass_.at(now + time_delta);
        const bool too_far = future.el < 0.0 || std::fabs(current.az - future.az) > settings_.threshold_deg ||
                             std::fabs(current.el - future.el) > settings_.threshold_deg;
        time_delta += too_far ? -step : step;
        step /= 2.0;
    }
    return future;
}

void GpredictClient::timer_tick() {
    const double now = pass_now();
    // Gpredict's timer reads the time and the satellite the module computed at its last refresh.
    double seen = now;
    if (gpredict_timing() && settings_.module_refresh_s > 0.0) {
        seen = engaged_at_ + std::floor((now - engaged_at_) / settings_.module_refresh_s) * settings_.module_refresh_s;
    }
    {
        std::lock_guard lock(mutex_);
        if (!engaged_) {
            return;  // never engaged again
        }
        if (!io_error_) {
            error_count_ = 0;
            error_streak_ = 0;
        } else {
            ++record_.erroring_cycles;
            record_.longest_error_streak = std::max(record_.longest_error_streak, ++error_streak_);
            if (settings_.max_error_count > 0 && error_count_ >= settings_.max_error_count) {
                engaged_ = false;
                record_.disengaged = true;
                record_.disengaged_at = now;
                return;
            }
            ++error_count_;
        }
    }
    const Direction sat = pass_.at(seen);
    auto clamp_az = [this](double az) { return std::clamp(az, settings_.min_az, settings_.max_az); };
    auto clamp_el = [this](double el) { return std::clamp(el, settings_.min_el, settings_.max_el); };
    Direction set{};
    if (sat.el < 0.0) {
        const bool before = seen < pass_.aos();
        set = {clamp_az(before ? pass_.aos_az() : pass_.los_az()), clamp_el(0.0)};
    } else {
        set = {clamp_az(sat.az), clamp_el(sat.el)};
    }
    std::lock_guard lock(mutex_);
    if (settings_.true_position_every_cycle) {
        pending_ = set;
        new_target_ = true;
        return;
    }
    if (!settings_.look_ahead) {
        if (last_sent_ && std::fabs(std::remainder(set.az - last_sent_->az, 360.0)) <= settings_.threshold_deg &&
            std::fabs(last_sent_->el - set.el) <= settings_.threshold_deg) {
            return;
        }
        last_sent_ = set;
        pending_ = set;
        new_target_ = true;
        return;
    }
    Direction rot = read_back_;
    while (rot.az < 0.0) {
        rot.az += 360.0;
    }
    while (rot.az > 360.0) {
        rot.az -= 360.0;
    }
    if (std::fabs(set.az - rot.az) <= settings_.threshold_deg &&
        std::fabs(set.el - rot.el) <= settings_.threshold_deg) {
        return;
    }
    if (sat.el > 0.0) {
        // The search compares against the clamped current target, as Gpredict's does.
        const Direction ahead = lead_target(seen, set);
        set = {clamp_az(ahead.az), clamp_el(ahead.el)};
    }
    pending_ = set;
    new_target_ = true;
}

void GpredictClient::io_loop(double end) {
    // Gpredict speaks the plain protocol, one connection, no probe.
    birdcage::rotctl::Client connection(
        "127.0.0.1", port_,
        {.protocol = birdcage::rotctl::Protocol::plain, .timeout = std::chrono::seconds(10), .probe = false});
    (void)connection.connect();
    auto elapsed_ms = [](Clock::time_point since) {
        return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
    };
    while (!stop_ && pass_now() < end) {
        const auto loop_start = Clock::now();
        if (!connection.connected()) {
            // The library closes a link that went out of step (a reply past its deadline); Gpredict's
            // socket stays open through such a loop, so this client opens it again at once.
            (void)connection.connect();
        }
        std::optional<Direction> target;
        bool io_error = false;
        {
            std::lock_guard lock(mutex_);
            if (!engaged_) {
                break;
            }
            if (new_target_) {
                target = pending_;
            }
        }
        // Gpredict's thread keeps the flag to itself until the end of the loop (below).
        bool still_to_send = false;
        if (target) {
            const auto sent_at = Clock::now();
            const int code = connection.set_position(target->az, target->el);
            record_.set_round_trip_ms.push_back(elapsed_ms(sent_at));
            if (code == 0) {
                record_.sent_targets.push_back({pass_now(), *target});
                if (!gpredict_timing()) {
                    std::lock_guard lock(mutex_);
                    new_target_ = false;
                }
            } else {
                ++record_.failed_replies;
                io_error = true;
                still_to_send = true;  // Gpredict retries a failed P on the next loop
            }
        }
        sleep_sim(settings_.io_sleep_s);
        const birdcage::sim::Pose truth_before = dish_.true_position();
        const auto asked_at = Clock::now();
        double az = 0, el = 0;
        const int code = connection.get_position(az, el);
        record_.p_round_trip_ms.push_back(elapsed_ms(asked_at));
        const birdcage::sim::Pose truth_after = dish_.true_position();
        if (code == 0) {
            record_.p_error_deg.push_back(
                distance_to_path({az, el}, {truth_before.az, truth_before.el}, {truth_after.az, truth_after.el}));
            record_.read_backs.push_back(
                {pass_now(), {az, el}, {truth_before.az, truth_before.el}, {truth_after.az, truth_after.el}});
            std::lock_guard lock(mutex_);
            read_back_ = {az, el};
        } else {
            ++record_.failed_replies;
            io_error = true;
            if (gpredict_timing() && target) {
                // Gpredict reads the position into the variables that held the target it sent,
                // and hands them over as the read-back even when `p` failed.
                std::lock_guard lock(mutex_);
                read_back_ = *target;
            }
        }
        {
            std::lock_guard lock(mutex_);
            io_error_ = io_error;
            if (gpredict_timing()) {
                // The hand-over: whatever the timer posted since the flag was taken is dropped.
                new_target_ = still_to_send;
            }
        }
        const double elapsed_sim_s = elapsed_ms(loop_start) / 1000.0 * time_scale_;
        sleep_sim(std::max(elapsed_sim_s, settings_.io_min_period_s));
    }
    bool disengaged = false;
    {
        std::lock_guard lock(mutex_);
        disengaged = !engaged_;
    }
    if (disengaged) {
        (void)connection.stop();  // Gpredict stops the rotator when it disengages
    }
}

ClientRecord GpredictClient::run_until(double end) {
    engaged_at_ = pass_now();
    std::thread io([this, end] { io_loop(end); });
    // The GUI timer: fixed real-time period of cycle / scale, like a GLib timeout.
    const auto period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(settings_.cycle_s / time_scale_));
    auto next = Clock::now();
    if (gpredict_timing()) {
        next += std::chrono::duration_cast<Clock::duration>(
            std::chrono::duration<double>(settings_.timer_offset_s / time_scale_));
        std::this_thread::sleep_until(next);
    }
    while (pass_now() < end) {
        timer_tick();
        next += period;
        std::this_thread::sleep_until(next);
    }
    stop_ = true;
    io.join();
    return record_;
}

}  // namespace bench
