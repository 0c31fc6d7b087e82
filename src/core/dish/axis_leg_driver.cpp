// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "dish/move_drivers.hpp"
#include "firmware/protocol.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto query_timeout = 2000ms;  // `a`: ~60 bytes even at 57600 baud is ~11 ms
constexpr auto poll_interval = 100ms;   // >= 10 Hz position polls while a leg runs (docs/tracking.md 1.2)
constexpr auto still_window = 2000ms;   // an axis unchanged this long has stopped
constexpr auto leg_margin = 3000ms;     // added to 2 x the estimated move time
// An axis that has not moved since its command is not stopped while it may still be starting
// (a motor may start seconds after the command, docs/tracking.md 1.5): it gets its learnt start-up
// delay times this, plus the still window; until a leg has timed the axis' start, this long.
constexpr double startup_margin = 1.5;
constexpr double under_way_degrees = 0.02;  // as the position model's start (position_model.cpp)
constexpr auto unlearnt_startup_allowance = 5000ms;
// With prompts, the reply to a move may wait for the move's end (G2 after-motion acks): this much
// beyond the leg's budget. Without prompts the reply is the quiet gap after the move's output.
constexpr auto prompt_after_move_margin = 2000ms;
constexpr auto unknown_prompt_send_timeout = 1000ms;
constexpr double stillness_degrees = 0.02;  // position changes smaller than this are noise
// An acknowledged angle this far from the one sent means the firmware changed it (clamped, or
// named another branch); the ack prints two decimals.
constexpr double ack_match_degrees = 0.01;
// A mechanical acknowledgement further than this from both the number sent and the intended
// branch names a branch the backend did not plan.
constexpr double ack_branch_degrees = 1.0;
// Motion of the dish before a leg is under way that is not the leg's (away from its end, or of the
// other axis) beyond this: the firmware still runs something else. Above a reply's noise and a
// motor's settling, far below any move.
constexpr double own_motion_degrees = 0.5;
// Consecutive readings further apart than this were not one continuous path (the estimate's branch
// was wrong, or the readings too sparse to follow the axis): the leg teaches nothing about the mapping.
constexpr double path_jump_degrees = 90.0;

std::string degrees_text(double value) {
    return format_degrees(value);
}
double axis_value(AzEl position, Axis axis) {
    return axis == Axis::azimuth ? position.az : position.el;
}
double signed_difference(Axis axis, double from, double to) {
    return axis == Axis::azimuth ? azimuth_difference(from, to) : to - from;
}
double axis_error(Axis axis, double from, double to) {
    return std::fabs(signed_difference(axis, from, to));
}
std::string axis_text(Axis axis) {
    return std::to_string(static_cast<int>(axis));
}

}  // namespace

void AxisLegDriver::reset() {
    pending_.clear();
    in_flight_.reset();
    settling_ = {};
    firmware_busy_ = {};
    unstarted_stop_.reset();
    forget_commands();
}

void AxisLegDriver::forget_commands() {
    commanded_az_.reset();
    commanded_el_.reset();
}

void AxisLegDriver::plan(AzEl wanted, AzEl command, const std::optional<AzEl>& previous, double az_rate_dps,
                         const std::optional<wrap::PassAhead>& ahead) {
    pending_.clear();
    // The mechanical azimuth: the target's branch, plus the leapfrog lead, inside the usable window.
    const std::optional<double> leg_end = in_flight_ && in_flight_->axis == Axis::azimuth
                                              ? std::optional<double>(in_flight_->final_mech_az)
                                              : std::nullopt;
    const double target_mech =
        c_.wrap.choose_branch(wanted, previous, az_rate_dps, c_.el_min, leg_end, commanded_az_, ahead);
    const wrap::Window plan = c_.wrap.plan_window();
    const double command_mech = std::clamp(target_mech + azimuth_difference(wanted.az, command.az), plan.min, plan.max);
    command.az = c_.wrap.command_value(command_mech);

    const auto mech_az = c_.wrap.mechanical();
    const auto& last = c_.state.last_position;
    auto needed = [&](Axis axis, double value) {
        const auto& commanded = axis == Axis::azimuth ? commanded_az_ : commanded_el_;
        if (commanded) {
            return std::fabs(*commanded - value) >= same_angle_degrees;
        }
        // Nothing commanded on this axis yet: skip the leg only if the dish already reads the target
        // (arrival_tolerance is for ending a leg in motion; skipping by it would leave up to that
        // much pointing error, e.g. after a TV search stopped the dish near the target).
        if (axis == Axis::azimuth) {
            return !mech_az || std::fabs(*mech_az - value) >= same_angle_degrees;
        }
        return !last || std::fabs(last->el - value) >= same_angle_degrees;
    };
    Leg az_leg;
    az_leg.axis = Axis::azimuth;
    az_leg.target = command;
    az_leg.mech_az = command_mech;
    az_leg.final_mech_az = command_mech;
    Leg el_leg;
    el_leg.axis = Axis::elevation;
    el_leg.target = command;
    // Alternate which axis goes first so neither starves the other (the upstream v2.0 clients do the same, docs/firmware.md §3.4, §3.6).
    // A leg in flight decides: the other axis goes next. Steering re-aims whenever the satellite is a
    // deadband past the aim, and on a slow mount near a culmination that happens more often than a
    // leg ends, so alternating per plan let the azimuth's legs run back to back while the elevation
    // waited (a Trav'ler 7 deg low for 20 s at a 62 deg culmination, docs/benchmarks.md).
    bool az_first = in_flight_ ? in_flight_->axis != Axis::azimuth : move_count_ % 2 == 0;
    if (std::exchange(farther_axis_first_, false) && mech_az && last) {
        // After a recovery the dish may be far off on one axis only (a Trav'ler's calibration can
        // leave it at AZ 0, 19 deg from the satellite and 2 deg below it): the axis farther off on
        // the sky goes first, so the error falls soonest. The alternation's parity says nothing
        // here; it resumes from this move.
        const double az_off = std::fabs(command_mech - *mech_az) * std::cos(last->el * M_PI / 180.0);
        az_first = az_off >= std::fabs(command.el - last->el);
        move_count_ = az_first ? 0 : 1;
    }
    ++move_count_;
    for (const Leg& leg : az_first ? std::array<Leg, 2>{az_leg, el_leg} : std::array<Leg, 2>{el_leg, az_leg}) {
        if (needed(leg.axis, leg.axis == Axis::azimuth ? leg.mech_az : leg.target.el)) {
            pending_.push_back(leg);
        }
    }
}

Status AxisLegDriver::service() {
    if (in_flight_) {
        const Status status = follow();
        if (in_flight_ || !status) {
            return status;
        }
    }
    if (pending_.empty()) {
        return Status::ok();
    }
    Leg leg = pending_.front();
    pending_.pop_front();
    if (leg.axis == Axis::azimuth) {
        plan_azimuth_leg(leg);
    }
    return send(leg);
}

// An azimuth leg longer than wrap::max_leg_deg goes by waypoints (see wrap::next_waypoint() for
// why), each planned from where the dish is when it is sent; the rest of the leg stays queued.
void AxisLegDriver::plan_azimuth_leg(Leg& leg) {
    const double from = c_.wrap.mechanical().value_or(commanded_az_.value_or(leg.final_mech_az));
    leg.mech_az = leg.waypoints_left > 0 ? wrap::next_waypoint(from, leg.final_mech_az) : leg.final_mech_az;
    leg.target.az = c_.wrap.command_value(leg.mech_az);
    if (leg.mech_az == leg.final_mech_az) {
        return;
    }
    Leg rest = leg;
    rest.mech_az = rest.final_mech_az;
    rest.target.az = c_.wrap.command_value(rest.final_mech_az);
    --rest.waypoints_left;
    pending_.push_front(rest);
    emit(c_.log, LogLevel::verbose,
         "azimuth by waypoints: " + degrees_text(leg.target.az) + " (mechanical " + degrees_text(leg.mech_az) +
             ") on the way from " + degrees_text(from) + " to mechanical " + degrees_text(leg.final_mech_az));
}

std::optional<double> AxisLegDriver::azimuth_waypoint() const {
    if (in_flight_ && in_flight_->axis == Axis::azimuth && in_flight_->mech_az != in_flight_->final_mech_az) {
        return in_flight_->target.az;
    }
    return std::nullopt;
}

double AxisLegDriver::distance(const Leg& leg) const {
    if (leg.axis == Axis::azimuth) {
        const auto mech_az = c_.wrap.mechanical();
        return mech_az ? std::fabs(leg.mech_az - *mech_az) : wrap::max_leg_deg;
    }
    if (!c_.state.last_position) {
        return c_.el_max - c_.el_min;
    }
    return std::fabs(leg.target.el - c_.state.last_position->el);
}

std::chrono::milliseconds AxisLegDriver::startup_allowance() const {
    std::chrono::milliseconds longest{0};
    for (const Axis axis : {Axis::azimuth, Axis::elevation}) {
        Leg leg;
        leg.axis = axis;
        longest = std::max(longest, start_allowance(leg));
    }
    return longest;
}

// Also for a leg sent while the axis may still have been settling: it may have come to rest since.
std::chrono::milliseconds AxisLegDriver::start_allowance(const Leg& leg) const {
    if (!startup_.learnt(leg.axis)) {
        return std::max(still_window, unlearnt_startup_allowance) + leg.queued_at_most;
    }
    const auto delay = std::chrono::duration<double>(startup_margin * startup_.delay(leg.axis));
    return std::chrono::duration_cast<std::chrono::milliseconds>(delay) + still_window + leg.queued_at_most;
}

Status AxisLegDriver::send(Leg& leg) {
    const auto estimate = estimated_move_time(c_.profile, leg.axis, distance(leg));
    leg.estimate = estimate;
    const auto until = [&](Clock::time_point end) {
        return std::max(std::chrono::milliseconds{0},
                        std::chrono::duration_cast<std::chrono::milliseconds>(end - c_.now()));
    };
    leg.queued_behind = until(firmware_busy_.expected);
    leg.queued_at_most = until(firmware_busy_.at_most);
    // A leg sent while its axis still covers the previous one, while it may still wait out the
    // delay of a leg that ended before it started, or while the firmware still runs the other
    // axis' leg, starts when that is over: the start it shows is not its own start-up delay.
    leg.from_rest = !settling(leg.axis) && unstarted_stop_ != leg.axis && leg.queued_at_most.count() == 0;
    if (unstarted_stop_ == leg.axis) {
        unstarted_stop_.reset();
    }
    leg.budget = estimate * 2 + leg_margin + start_allowance(leg);
    const std::string command = build_axis_move(leg.axis, axis_value(leg.target, leg.axis));
    // An after-motion acknowledgement comes once the move is over, start-up delay included; but
    // only a delay the readings have shown counts here. A prompt lost on the line costs this whole
    // wait, so the unlearnt allowance, which only keeps an unstarted axis from being called
    // stopped, would make every lost prompt byte seconds longer (docs/tracking.md §1.5).
    const auto reply_budget =
        estimate * 2 + leg_margin +
        (startup_.learnt(leg.axis) ? start_allowance(leg) - still_window : std::chrono::milliseconds{0});
    const auto timeout =
        c_.profile.prompt_known() ? reply_budget + prompt_after_move_margin : unknown_prompt_send_timeout;
    ReplyComplete complete;
    if (c_.profile.move_ack == MoveAckFormat::g2_angle) {
        complete = [](Span<const std::string> lines) { return static_cast<bool>(parse_g2_move_ack(lines)); };
    }
    const auto reply = c_.session.transact(command, timeout, complete);
    if (!reply && reply.status.code != Errc::timeout) {
        if (reply.status.code == Errc::not_homed) {
            c_.state.unhomed = true;
        }
        return reply.status;
    }
    if (!reply) {
        emit(c_.log, LogLevel::warning, "no prompt after " + command + "; assuming the move runs");
    } else if (c_.profile.move_ack == MoveAckFormat::g2_angle) {
        const auto ack = parse_g2_move_ack(reply.value.lines);
        if (ack.status.code == Errc::not_homed) {
            c_.state.unhomed = true;
            c_.session.set_axes_unhomed(true);
            c_.session.report(ConsoleEvent::reply_to(ConsoleEvent::Kind::unhomed, command));
            return ack.status;
        }
        if (ack) {
            c_.session.report(ConsoleEvent::move_acknowledged(command, ack.value));
        }
        if (!ack) {
            const std::string first_line = reply.value.lines.empty() ? std::string() : reply.value.lines.front();
            c_.session.report(ConsoleEvent::reply_to(ConsoleEvent::Kind::unrecognised, command, first_line));
            emit(c_.log, LogLevel::warning, "move not acknowledged: " + ack.status.message);
        } else if (axis_error(leg.axis, ack.value, axis_value(leg.target, leg.axis)) > ack_match_degrees) {
            emit(c_.log, LogLevel::verbose, "dish acknowledged " + degrees_text(ack.value) + " for " + command);
        } else if (leg.axis == Axis::azimuth && std::fabs(ack.value - leg.target.az) > ack_branch_degrees &&
                   std::fabs(ack.value - leg.mech_az) > ack_branch_degrees) {
            // A mechanical acknowledgement (e.g. -60.00 for `a 0 300.00`) names the branch taken.
            emit(c_.log, LogLevel::warning,
                 "dish acknowledged " + degrees_text(ack.value) + " for " + command + ", not the intended mechanical " +
                     degrees_text(leg.mech_az) + ": its wrap mapping differs from the backend's model");
        }
    }
    if (leg.axis == Axis::azimuth) {
        commanded_az_ = leg.mech_az;
        const auto mech_az = c_.wrap.mechanical();
        leg.path_known = mech_az.has_value();
        leg.from_mech = leg.lowest = leg.highest = mech_az.value_or(leg.mech_az);
        leg.expected_end.reset();
    } else {
        commanded_el_ = leg.target.el;
    }
    leg.sent_at = c_.now();
    leg.last_change = leg.sent_at;
    leg.last_seen.reset();
    leg.under_way = false;
    const auto& last = c_.state.last_position;
    {
        // The axis still covering the previous leg moves before this one has begun: that motion is
        // not this leg under way.
        // It ends anywhere within the arrival tolerance of that leg's end.
        const bool azimuth = leg.axis == Axis::azimuth;
        const double goal = azimuth ? leg.mech_az : leg.target.el;
        leg.unmoved_ref = azimuth ? leg.from_mech : (last ? last->el : goal);
        leg.under_way_degrees = under_way_degrees;
        if (const auto& previous = settling(leg.axis)) {
            const double previous_end = azimuth ? previous->mech_az : previous->target.el;
            if ((previous_end - leg.unmoved_ref) * (goal - leg.unmoved_ref) > 0.0 &&
                std::fabs(previous_end - leg.unmoved_ref) < std::fabs(goal - leg.unmoved_ref)) {
                leg.unmoved_ref = previous_end;
            }
            leg.under_way_degrees = std::max(under_way_degrees, c_.profile.arrival_tolerance);
        }
    }
    leg.nearest.reset();
    leg.other_still.reset();
    if (const Axis other = leg.axis == Axis::azimuth ? Axis::elevation : Axis::azimuth; last && !settling(other)) {
        leg.other_still = axis_value(*last, other);
    }
    leg.motion = LegMotion{};
    leg.motion.axis = leg.axis;
    leg.motion.start = axis_value(last ? *last : leg.target, leg.axis);
    // Display degrees: an azimuth leg may command a number beyond 360 (az_mapping.hpp).
    leg.motion.to = leg.axis == Axis::azimuth ? normalize_azimuth(leg.target.az) : leg.target.el;
    leg.motion.sent_at = leg.sent_at;
    leg.motion.latest = AxisReading{leg.motion.start, c_.state.last_position_at.value_or(leg.sent_at)};
    settling(leg.axis).reset();  // this leg moves the axis from here on
    last_poll_ = leg.sent_at;
    emit(c_.log, LogLevel::verbose, "sent " + command + " (estimated " + std::to_string(estimate.count()) + " ms)");
    in_flight_ = leg;
    return Status::ok();
}

// A position poll during the leg; an azimuth leg also records the path its readings swept.
Result<AzEl> AxisLegDriver::poll() {
    const std::optional<double> before = c_.wrap.mechanical();
    const std::optional<Clock::time_point> before_at = c_.wrap.reading_at();
    const unsigned readings_before = c_.wrap.readings();
    auto position = c_.reader.ask(query_timeout);
    const auto mech_az = c_.wrap.mechanical();
    if (!in_flight_ || in_flight_->axis != Axis::azimuth || !mech_az || c_.wrap.readings() == readings_before) {
        return position;
    }
    Leg& leg = *in_flight_;
    // Readings that report the branch follow the axis whatever the gap; displayed ones only while
    // the axis cannot have turned half a circle in between.
    const auto t = *c_.wrap.reading_at();
    const double gap_s = before_at ? std::chrono::duration<double>(t - *before_at).count() : 0.0;
    const bool followed = c_.wrap.reports_mechanical() || gap_s * c_.profile.az_speed_dps < path_jump_degrees;
    if (!before || std::fabs(*mech_az - *before) > path_jump_degrees || !followed) {
        leg.path_known = false;
    }
    leg.lowest = std::min(leg.lowest, *mech_az);
    leg.highest = std::max(leg.highest, *mech_az);
    return position;
}

void AxisLegDriver::finish(std::string_view how) {
    if (!in_flight_) {
        return;
    }
    emit(c_.log, LogLevel::verbose, "leg " + std::string(how));
    in_flight_.reset();
}

Status AxisLegDriver::follow() {
    Leg& leg = *in_flight_;
    const auto t = c_.now();
    if (t - last_poll_ < poll_interval) {
        return Status::ok();
    }
    last_poll_ = t;
    const bool over_budget = t - leg.sent_at > leg.budget;
    const auto position = poll();
    if (!position && position.status.code != Errc::protocol) {
        if (position.status.code == Errc::timeout && !over_budget) {
            return Status::ok();  // some consoles answer only once the motor stops
        }
        finish("abandoned: " + position.status.message);
        return position.status;
    }
    if (!position) {
        if (!c_.state.fault_reported && !over_budget) {
            return Status::ok();  // an unusable reply; poll again
        }
        finish("abandoned: " + position.status.message);  // e.g. AZ MOTOR STALLED
        if (c_.state.fault_reported) {
            // The firmware dropped its queued moves (docs/firmware.md 6.3): so do we. The target is
            // forgotten, so the client sending the same P again retries the move.
            pending_.clear();
            firmware_busy_ = {};
            c_.forget_target();
            forget_commands();
        }
        return position.status;
    }
    if (watch_motion_ && leg.from_rest && moves_on_its_own(leg, position.value)) {
        // The firmware runs this leg only after whatever moves the dish now: what the leg would
        // judge from here (stopped short, its start-up delay, the mapping) is wrong. The controller
        // plans the target again once the dish rests.
        finish("dropped: the dish moves on its own");
        pending_.clear();
        forget_commands();
        moved_on_its_own_ = true;
        return Status::ok();
    }
    record_reading(position.value);
    // Azimuth in mechanical degrees: arriving on the display azimuth of the wrong branch is not arriving.
    const auto mech_az = c_.wrap.mechanical();
    const bool azimuth = leg.axis == Axis::azimuth && mech_az;
    if (azimuth) {
        observe_azimuth_leg(leg, false);
    }
    const double seen = azimuth ? *c_.wrap.mechanical() : axis_value(position.value, leg.axis);
    const double goal = azimuth ? leg.expected_end.value_or(leg.mech_az) : axis_value(leg.target, leg.axis);
    const auto error = [&](double from, double to) {
        return azimuth ? std::fabs(to - from) : axis_error(leg.axis, from, to);
    };
    const auto end_leg = [&](std::string_view how) {
        if (!azimuth) {
            finish(how);
            return;
        }
        observe_azimuth_leg(leg, true);
        const bool elsewhere = std::fabs(*c_.wrap.mechanical() - leg.mech_az) > path_jump_degrees;
        finish(how);
        if (elsewhere) {
            replan_after_surprise();
        }
    };
    // Under way: moved from where it stood towards the leg's end (decided before arrival, which
    // needs to know whether the axis was ever seen to move).
    if ((goal - leg.unmoved_ref) * (seen - leg.unmoved_ref) > 0.0 &&
        std::fabs(seen - leg.unmoved_ref) >= leg.under_way_degrees) {
        leg.under_way = true;
    }
    // While the first legs watch for motion of the dish's own, a reading at the leg's end is an
    // arrival only once the next one agrees: a calibration that sweeps the axis through the end
    // (the leg still queued behind it) passes it in one reading.
    const bool passing = watch_motion_ && leg.from_rest && leg.under_way &&
                         (!leg.last_seen || error(*leg.last_seen, seen) > stillness_degrees);
    if (error(seen, goal) <= c_.profile.arrival_tolerance && !passing) {
        if (!leg.under_way) {
            // Arrived before it was seen to move (it was sent within the tolerance): the firmware
            // still runs it, and the next leg waits behind it.
            const auto expected_delay = std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::duration<double>(startup_.delay(leg.axis)));
            firmware_busy_.expected = std::max(firmware_busy_.expected, leg.sent_at + expected_delay + leg.estimate);
            firmware_busy_.at_most =
                std::max(firmware_busy_.at_most, leg.sent_at + (start_allowance(leg) - still_window) + leg.estimate);
        }
        settling(leg.axis) = leg;
        const LegMotion motion = motion_of(leg);
        if (const double step = std::fabs(motion.to - motion.start);
            step >= small_step_min_deg && step <= small_step_max_deg) {
            step_times_.learn(leg.axis, std::chrono::duration<double>(c_.now() - leg.sent_at).count());
        }
        // At the end of a leg of its own the dish ran nothing else: motion from here is no longer
        // a calibration or a braking search the first legs must wait out.
        watch_motion_ = false;
        end_leg("arrived");
        return Status::ok();
    }
    // Readings taken before the axis could have started are not a stall: an axis not yet under way
    // is stopped only once the learnt start-up delay (with margin) is over; one under way, once it
    // has been still for the still window.
    // Not yet under way, the allowance counts from its last motion: a motion that was not this leg's
    // leaves the motor its start-up delay after it.
    const auto unmoved_for = leg.under_way ? still_window : start_allowance(leg);
    if (!leg.last_seen || error(*leg.last_seen, seen) > stillness_degrees) {
        leg.last_seen = seen;
        leg.last_change = t;
    } else if (t - leg.last_change >= still_window && t - leg.sent_at >= unmoved_for &&
               (leg.under_way || t - leg.last_change >= unmoved_for)) {
        emit(c_.log, LogLevel::warning,
             "axis " + axis_text(leg.axis) + " stopped at " + degrees_text(seen) + ", short of " + degrees_text(goal));
        if (!leg.under_way) {
            unstarted_stop_ = leg.axis;
        }
        end_leg("stopped");
        return Status::ok();
    }
    if (t - leg.sent_at > leg.budget) {  // the budget may have grown with what this poll taught
        finish("timed out");
        return Status{Errc::timeout, "axis " + axis_text(leg.axis) + " did not reach " + degrees_text(goal) + " in " +
                                         std::to_string(leg.budget.count()) + " ms"};
    }
    return Status::ok();
}

// The axis moved away from the leg's end (before the leg was under way, from where it stood: the
// elevation only; after, from the nearest it came), or the other axis moved. An azimuth leg's first
// motion away from its end is the firmware's own path as often: a wrap that turns the dish back and
// reaches the target from the other side (docs/firmware.md §2), a mapping not yet learnt.
bool AxisLegDriver::moves_on_its_own(Leg& leg, AzEl position) const {
    const bool azimuth = leg.axis == Axis::azimuth;
    const auto mech_az = c_.wrap.mechanical();
    if (azimuth && !mech_az) {
        return false;
    }
    const double seen = azimuth ? *mech_az : position.el;
    const double goal = azimuth ? leg.mech_az : leg.target.el;
    if (!azimuth && !leg.under_way && (goal - leg.unmoved_ref) * (seen - leg.unmoved_ref) < 0.0 &&
        std::fabs(seen - leg.unmoved_ref) > own_motion_degrees) {
        return true;
    }
    const double off = std::fabs(goal - seen);
    leg.nearest = std::min(leg.nearest.value_or(off), off);
    if (leg.under_way && off > *leg.nearest + own_motion_degrees) {
        return true;
    }
    if (!leg.other_still) {
        return false;
    }
    const Axis other = azimuth ? Axis::elevation : Axis::azimuth;
    return axis_error(other, *leg.other_still, axis_value(position, other)) > own_motion_degrees;
}

// Feeds the mapping learner with an azimuth leg (whole or so far). When the evidence changes, the
// leg's end is where the reading now planned with takes it, and the budget allows for the long way
// round the firmware may be taking.
void AxisLegDriver::observe_azimuth_leg(Leg& leg, bool at_rest) {
    const auto mech_az = c_.wrap.mechanical();
    if (!leg.path_known || !mech_az) {
        return;
    }
    azmap::Learner& learner = c_.wrap.learner();
    const auto learnt =
        learner.observe({leg.target.az, leg.from_mech, leg.lowest, leg.highest, at_rest ? mech_az : std::nullopt});
    if (!learnt) {
        return;
    }
    emit(c_.log, LogLevel::verbose, *learnt);
    const auto point = learner.wrap_point();
    leg.expected_end =
        azmap::predict(learner.planning(), leg.target.az, leg.from_mech, c_.wrap.travel(), point.value_or(0.0));
    const auto whole_travel = estimated_move_time(c_.profile, Axis::azimuth, c_.wrap.window().span());
    leg.budget = std::max(leg.budget, std::chrono::duration_cast<std::chrono::milliseconds>(c_.now() - leg.sent_at) +
                                          whole_travel * 2 + leg_margin);
}

// The dish ended an azimuth leg on another branch than planned (the mapping was not the one planned
// with): the legs queued under that plan are dropped and the current target is put on a branch of
// what is now known, from where the dish is.
void AxisLegDriver::replan_after_surprise() {
    pending_.erase(
        std::remove_if(pending_.begin(), pending_.end(), [](const Leg& leg) { return leg.axis == Axis::azimuth; }),
        pending_.end());
    const auto mech_az = c_.wrap.mechanical();
    const auto& target = c_.state.target;
    if (!target || !mech_az) {
        c_.wrap.set_target_mechanical(std::nullopt);
        return;
    }
    const wrap::Window plan = c_.wrap.plan_window();
    const double mechanical = wrap::choose_branch(target->az, *mech_az, 0, false, plan).mechanical;
    c_.wrap.set_target_mechanical(mechanical);
    emit(c_.log, LogLevel::verbose,
         "azimuth " + degrees_text(target->az) + " re-planned on mechanical " + degrees_text(mechanical) + " from " +
             degrees_text(*mech_az) + " (window " + degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")");
    if (std::fabs(mechanical - *mech_az) < same_angle_degrees) {
        return;
    }
    Leg leg;
    leg.axis = Axis::azimuth;
    leg.target = *target;
    leg.mech_az = leg.final_mech_az = mechanical;
    leg.target.az = c_.wrap.command_value(mechanical);
    pending_.push_front(leg);
}

void AxisLegDriver::record_reading(AzEl position) {
    const auto at = c_.state.last_position_at.value_or(c_.now());
    if (in_flight_) {
        LegMotion& motion = in_flight_->motion;
        const double value = axis_value(position, motion.axis);
        add_reading(motion, AxisReading{value, at});
        // A motion away from the leg's end is not its start (the dish moving on its own).
        const bool towards = signed_difference(motion.axis, motion.start, value) *
                                 signed_difference(motion.axis, motion.start, motion.to) >
                             0.0;
        if (in_flight_->from_rest && towards) {
            motion.pace = paces_.pace(motion.axis, axis_error(motion.axis, motion.start, motion.to));
            if (const auto delay = StartupDelays::observed(c_.profile, motion)) {
                startup_.learn(motion.axis, *delay);
                emit(c_.log, LogLevel::verbose,
                     "axis " + axis_text(motion.axis) + " started " + std::to_string(static_cast<int>(*delay * 1000)) +
                         " ms after its command (learnt " +
                         std::to_string(static_cast<int>(startup_.delay(motion.axis) * 1000)) + " ms)");
            }
        }
        if (const auto pace = observed_pace(c_.profile, motion)) {
            paces_.learn(motion.axis, axis_error(motion.axis, motion.start, motion.to), *pace);
        }
    }
    for (auto& settling : settling_) {
        if (!settling) {
            continue;
        }
        LegMotion& motion = settling->motion;
        const double value = axis_value(position, motion.axis);
        if (axis_error(motion.axis, motion.latest.value, value) < stillness_degrees) {
            settling.reset();  // at rest where read
        } else {
            add_reading(motion, AxisReading{value, at});
        }
    }
}

LegMotion AxisLegDriver::motion_of(const Leg& leg) const {
    LegMotion motion = leg.motion;
    motion.pace = paces_.pace(motion.axis, axis_error(motion.axis, motion.start, motion.to));
    // `a` waits for the moving motor to finish (docs/firmware.md §2): a leg starts after whatever
    // the firmware still runs, then waits out its own start-up delay.
    motion.startup_s = std::chrono::duration<double>(leg.queued_behind).count() + startup_.delay(motion.axis);
    return motion;
}

MovingAxes AxisLegDriver::moving_axes() const {
    MovingAxes moving;
    if (!c_.state.last_position || !c_.state.last_position_at) {
        return moving;
    }
    auto put = [&](const Leg& leg) {
        (leg.axis == Axis::azimuth ? moving.azimuth : moving.elevation) = motion_of(leg);
    };
    // A reading newer than the settling leg's own was taken while no leg polled: it is the truth.
    for (const auto& settling : settling_) {
        if (settling && settling->motion.latest.at == *c_.state.last_position_at) {
            put(*settling);
        }
    }
    if (in_flight_) {
        put(*in_flight_);
    }
    return moving;
}

void AxisLegDriver::take_learning_from(const MoveDriver& before) {
    if (const auto* same = dynamic_cast<const AxisLegDriver*>(&before)) {
        paces_ = same->paces_;
        startup_ = same->startup_;
        step_times_ = same->step_times_;
    }
}

MotorTiming AxisLegDriver::learnt_motor() const {
    return MotorTiming{{startup_.delay(Axis::azimuth), startup_.delay(Axis::elevation)}, paces_};
}

std::optional<double> AxisLegDriver::learnt_step_seconds(Axis axis) const {
    if (!step_times_.learnt(axis)) {
        return std::nullopt;
    }
    return step_times_.delay(axis);
}

}  // namespace birdcage
