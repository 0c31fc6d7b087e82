// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/wrap_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/least_squares.hpp"
#include "firmware/protocol.hpp"

namespace birdcage {
namespace {

// A reading this far outside 0..360 cannot be a displayed azimuth ("-0.00" and "360.00" can).
constexpr double beyond_display_degrees = 0.5;
// A mechanical reading may overshoot the travel's ends by this much (the motor coasts).
constexpr double travel_slack_degrees = 1.0;
// Readings beyond 0..360 in a row that prove the dish reports mechanical angles (one could be noise).
constexpr int mechanical_proof_readings = 2;
// After a re-initialisation the mechanical estimate is kept if the dish still reads within this.
constexpr double same_branch_recheck_degrees = 1.0;
// A target this far (display azimuth) from the previous one is a new pass or another satellite.
constexpr double new_pass_jump_degrees = 30.0;
// A pass's azimuth turns one way from rise to set, but the direction the caller infers from a
// few targets does not: Gpredict's lead is quantised, so a target can land a few tenths of a
// degree behind the one before, and a momentarily stationary estimate has no direction at all.
// Taken at face value each flip would be a new pass, and the pass-start rule would swing the G2 a
// whole wrap to the other branch and back (iss-45 at a 5 deg threshold: 592 deg of azimuth before
// the pass, 347 without the flips). The opposite direction is believed once the targets have gone
// this far back from the furthest one.
constexpr double reversal_confirm_degrees = 3.0;
// The culmination is passed once a target is this far below the highest one (Gpredict's targets
// wander by a few tenths of a degree with its quantised lead).
constexpr double culmination_drop_degrees = 1.0;
// A pass is only roughly symmetric about its culmination (the Earth turns beneath it), so the
// azimuth still to come is taken as what came before, and an unwind is brought forward only
// where the branch lacks room by more than this; a borderline pass keeps its branch.
constexpr double culmination_slack_degrees = 5.0;
// A target this little beyond the travel's usable end is held at the end instead of unwinding:
// a client leads the satellite by up to its threshold (Gpredict's 5 deg is up to 7 deg of azimuth
// at 45 deg elevation), so the last targets of a pass the travel holds by a degree run past it,
// and a 360 deg unwind for them pointed the Trav'ler 150 deg away for the rest of the pass.
constexpr double hold_at_end_degrees = 10.0;
// Targets within this of the highest one locate the culmination: a parabola of elevation over the
// azimuth travelled has its vertex there. At Gpredict's 5 deg threshold the highest target can
// lie 3 deg of azimuth short of it, which doubled into the estimate of what is still to come
// (sso-70 on the Trav'ler: 54 deg estimated, 62 to go, no unwind until the limit).
constexpr double near_top_degrees = 3.0;

// The travel at the culmination from the targets near it: the vertex of the least-squares
// parabola el(travel), if it is a maximum inside their span; else the highest target's travel.
double culmination_travel(const std::vector<std::pair<double, double>>& points, double fallback) {
    if (points.size() < 3) {
        return fallback;
    }
    double lo = points.front().first, hi = lo, centre = 0.0;
    for (const auto& [x, y] : points) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
        centre += x;
    }
    centre /= static_cast<double>(points.size());
    QuadraticSums sums;
    for (const auto& [x, y] : points) {
        sums.add(x - centre, y);
    }
    const auto fit = solve_quadratic(sums, 1e-12);
    if (!fit || fit->c >= 0.0) {
        return fallback;
    }
    const double vertex = centre - fit->b / (2.0 * fit->c);
    return vertex >= lo && vertex <= hi ? vertex : fallback;
}

std::string degrees_text(double value) {
    return format_degrees(value);
}

}  // namespace

WrapTracker::WrapTracker(azmap::Travel travel, std::optional<azmap::Mapping> stated, LogSink log)
    : travel_(travel), usable_(wrap::usable_window(travel.window)), learner_(travel, stated), log_(std::move(log)) {}

void WrapTracker::note_reading(double reported, Clock::time_point at) {
    reading_at_ = at;
    ++readings_;
    const wrap::Window& window = travel_.window;
    const double display = normalize_azimuth(reported);
    const bool beyond_display = reported < -beyond_display_degrees || reported >= 360.0 + beyond_display_degrees;
    const bool inside_travel =
        reported >= window.min - travel_slack_degrees && reported <= window.max + travel_slack_degrees;
    if (beyond_display && inside_travel) {
        // Only a mechanical report can read like this: it names the branch.
        if (!reports_mechanical_ && ++beyond_display_readings_ >= mechanical_proof_readings) {
            reports_mechanical_ = true;
            emit(log_, LogLevel::verbose,
                 "the dish reports its mechanical azimuth (read " + degrees_text(reported) +
                     "): readings are taken literally");
        }
        mechanical_ = reported;
        recheck_branch_ = false;
        branch_assumed_ = false;
        return;
    }
    if (!beyond_display) {
        beyond_display_readings_ = 0;
    }
    if (reports_mechanical_ && inside_travel) {
        mechanical_ = reported;
        recheck_branch_ = false;
        branch_assumed_ = false;
        return;
    }
    if (recheck_branch_ && mechanical_ &&
        std::fabs(azimuth_difference(*mechanical_, display)) > same_branch_recheck_degrees) {
        emit(log_, LogLevel::verbose,
             "after (re)initialisation the dish reads azimuth " + degrees_text(display) + ", not " +
                 degrees_text(normalize_azimuth(*mechanical_)) + ": it moved, its cable-wrap branch is assumed afresh");
        mechanical_.reset();
    }
    recheck_branch_ = false;
    const bool ambiguous = wrap::branches(display, window).size() > 1;
    if (!mechanical_) {
        mechanical_ = wrap::start_branch(display, window);
        branch_assumed_ = ambiguous;
        if (ambiguous) {
            emit(log_, LogLevel::verbose,
                 "azimuth " + degrees_text(display) + " has two cable-wrap branches; assuming mechanical " +
                     degrees_text(*mechanical_) + " (the one nearest AZ 0)");
        }
        return;
    }
    mechanical_ = wrap::unwrap_reading(display, *mechanical_, window);
    branch_assumed_ = branch_assumed_ && ambiguous;
}

void WrapTracker::judge_branch_at_rest() {
    if (!mechanical_ || !branch_assumed_) {
        return;
    }
    const double display = normalize_azimuth(*mechanical_);
    const double assumed = wrap::start_branch(display, travel_.window);
    if (std::fabs(assumed - *mechanical_) < 1e-6) {
        return;
    }
    emit(log_, LogLevel::verbose,
         "the dish came to rest at azimuth " + degrees_text(display) + ", read in motion on mechanical " +
             degrees_text(*mechanical_) + " from an assumed branch; assuming mechanical " + degrees_text(assumed) +
             " (the one nearest AZ 0)");
    mechanical_ = assumed;
}

// The rule (docs/tracking.md §2.3: no avoidable unwinds; unwind, when unavoidable, away from the
// limit stops; just past its culmination if the pass's start was seen; never for a target a few
// degrees past the end, or once the satellite has set, held at the end instead):
//  - normally the target's branch nearest the previous target (continuity), if it lies inside
//    the wrap window less the margins;
//  - when a pass starts (the caller's rate hint is non-zero and the target is within
//    pass_start_band_deg of el_min, rising), the branch nearest the previous target among those
//    with room for a whole pass (pass_span_deg) ahead in the direction of motion, else the one
//    with the most room ahead: the one unwind a pass that does not fit needs then happens at its
//    end, as late and as low as possible, instead of near its culmination;
//  - when the continuous branch lies outside the window (the limit is reached), the branch with
//    the most room ahead in the direction of motion (the nearest without a rate hint).
// A pass is started once: later targets of the same pass (same direction, no jump) keep
// continuity, so the descent towards el_min at its end never triggers the pass-start rule. Its
// direction holds while the caller knows none and through noise (reversal_confirm_degrees).
//
// Continuity is measured from the branch of the previous target (not the dish's momentary
// position, which may be half-way through a long slew to it), else where the azimuth leg in
// flight ends, else the estimated mechanical azimuth, else the last command.
double WrapTracker::choose_branch(AzEl wanted, const std::optional<AzEl>& previous, double az_rate_dps, double el_min,
                                  std::optional<double> leg_end, std::optional<double> commanded,
                                  const std::optional<wrap::PassAhead>& ahead) {
    int direction = az_rate_dps > 0.0 ? 1 : (az_rate_dps < 0.0 ? -1 : 0);
    const bool jumped = previous && std::fabs(azimuth_difference(previous->az, wanted.az)) > new_pass_jump_degrees;
    if (jumped) {
        pass_direction_.reset();
        pass_ = PassProgress{};
    }
    if (pass_direction_) {
        const double back_from_furthest = azimuth_difference(wanted.az, pass_furthest_az_) * *pass_direction_;
        if (direction == 0 || (direction != *pass_direction_ && back_from_furthest < reversal_confirm_degrees)) {
            direction = *pass_direction_;
        }
    }
    const bool new_pass = direction != 0 && pass_direction_ != direction;
    const bool falling = previous && !jumped && wanted.el < previous->el - same_angle_degrees;
    // With the orbit's view of the pass, its room is known (pass_branch_from_orbit()); the rule of thumb
    // (room for pass_span_deg) would undo that choice.
    const bool pass_starting = new_pass && !falling && wanted.el <= el_min + wrap::pass_start_band_deg && !ahead;
    const double progress = direction != 0 ? azimuth_difference(pass_furthest_az_, wanted.az) * direction : 0.0;
    if (new_pass) {
        pass_furthest_az_ = wanted.az;
        pass_ = PassProgress{};
        pass_.seen_from_start = pass_starting;
    } else if (progress > 0.0) {
        pass_furthest_az_ = wanted.az;
        // Only what the dish follows in its elevation range counts: before AOS and after LOS a
        // client clamps its targets at el_min while their azimuth keeps turning, and counted in,
        // that turn made a pass the Trav'ler's branch holds by 1 deg look 10 deg too long.
        if (wanted.el > el_min + same_angle_degrees) {
            pass_.travelled_deg += progress;
        }
    }
    if (wanted.el > pass_.top_el) {
        pass_.top_el = wanted.el;
        pass_.travelled_at_top_deg = pass_.travelled_deg;
        pass_.near_top.erase(std::remove_if(pass_.near_top.begin(), pass_.near_top.end(),
                                            [&](const auto& p) { return p.second < pass_.top_el - near_top_degrees; }),
                             pass_.near_top.end());
    }
    if (wanted.el > el_min + same_angle_degrees && wanted.el >= pass_.top_el - near_top_degrees) {
        pass_.near_top.emplace_back(pass_.travelled_deg, wanted.el);
    }
    if (direction != 0) {
        pass_direction_ = direction;
    }
    const wrap::Window plan = plan_window();
    std::optional<double> reference = target_mechanical_;
    for (const auto& candidate : {leg_end, mechanical_, commanded}) {
        if (!reference) {
            reference = candidate;
        }
    }
    // Nothing read or commanded yet: continuity from the start assumption (wrap::start_branch()).
    const double from = reference.value_or(std::clamp(0.0, plan.min, plan.max));
    const double continuous = wrap::nearest_branch(wanted.az, from);
    if (ahead) {
        if (const auto branch = pass_branch_from_orbit(wanted, continuous, *ahead, plan)) {
            target_mechanical_ = *branch;
            return *branch;
        }
    } else if (pass_direction_ && pass_.seen_from_start && !pass_.culmination_checked &&
               wanted.el <= pass_.top_el - culmination_drop_degrees) {
        // Once per pass, just past its culmination: the azimuth still to come after the culmination
        // is about what came before it.
        pass_.culmination_checked = true;
        const double at_top = culmination_travel(pass_.near_top, pass_.travelled_at_top_deg);
        const double to_go = std::max(0.0, 2.0 * at_top - pass_.travelled_deg);
        if (const auto branch =
                wrap::culmination_branch(wanted.az, continuous, direction, to_go, plan, culmination_slack_degrees)) {
            emit(log_, LogLevel::verbose,
                 "azimuth " + degrees_text(wanted.az) + ": mechanical " + degrees_text(*branch) + " instead of " +
                     degrees_text(continuous) + " (" + std::string(wrap::reason_text(wrap::Reason::culmination)) +
                     "; about " + degrees_text(to_go) + " deg to go, " +
                     degrees_text(wrap::room_ahead(continuous, direction, plan)) + " of room; window " +
                     degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")");
            target_mechanical_ = *branch;
            return *branch;
        }
    }
    {
        // Past the usable end of the travel, a little (a client's lead), or once the satellite has
        // set (the client holds its targets at el_min while their azimuth keeps turning): held at
        // the end; the next pass chooses its branch afresh.
        const double beyond = std::max(continuous - plan.max, plan.min - continuous);
        const bool set_below_range = wanted.el <= el_min + same_angle_degrees && pass_.top_el > el_min + 1.0;
        // Only while following a pass: a single target (a park at AZ 0 on the Trav'ler, whose
        // usable travel starts at 2) goes to its branch inside the travel, however it turns.
        if (pass_direction_ && beyond > 0.0 && (beyond <= hold_at_end_degrees || set_below_range)) {
            const double held = std::clamp(continuous, plan.min, plan.max);
            if (!target_mechanical_ || std::fabs(*target_mechanical_ - held) > same_angle_degrees) {
                emit(log_, LogLevel::verbose,
                     "azimuth " + degrees_text(wanted.az) + ": held at mechanical " + degrees_text(held) + ", " +
                         degrees_text(beyond) + " deg short of " + degrees_text(continuous) +
                         (set_below_range ? " (the satellite has set)" : " (a client's lead, not worth an unwind)") +
                         "; window " + degrees_text(plan.min) + ".." + degrees_text(plan.max));
            }
            target_mechanical_ = held;
            return held;
        }
    }
    const wrap::Choice choice = wrap::choose_branch(wanted.az, from, direction, pass_starting, plan);
    if (choice.reason != wrap::Reason::continuous) {
        std::string message = "azimuth " + degrees_text(wanted.az) + ": mechanical " + degrees_text(choice.mechanical) +
                              " instead of " + degrees_text(choice.continuous) + " (" +
                              std::string(wrap::reason_text(choice.reason));
        if (direction != 0) {
            message += "; " + degrees_text(wrap::room_ahead(choice.mechanical, direction, plan)) +
                       " deg of room ahead " + (direction > 0 ? "clockwise" : "anticlockwise");
        }
        message += "; window " + degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")";
        emit(log_, LogLevel::verbose, message);
    }
    target_mechanical_ = choice.mechanical;
    return choice.mechanical;
}

// With the orbit, what the rest of the pass needs is known instead of guessed from its start and
// symmetry. Its one unwind, if the current branch cannot hold it, happens where it costs least:
// before the pass rises (the dish only waits then), else just past the culmination (docs/tracking.md
// §2.3: an azimuth error costs least on the sky there). Between the two, the branch is kept, and
// a branch that lacks only a client's lead at the end (culmination_slack_degrees) is kept too.
std::optional<double> WrapTracker::pass_branch_from_orbit(AzEl wanted, double continuous, const wrap::PassAhead& ahead,
                                                          const wrap::Window& plan) {
    const bool before_rise = ahead.rises_in_s > 0.0;
    const bool past_top = !before_rise && ahead.culminates_in_s <= 0.0;
    if (!before_rise && !(past_top && !pass_.culmination_checked)) {
        return std::nullopt;
    }
    if (past_top) {
        pass_.culmination_checked = true;
    }
    const double overflow_here = plan.contains(continuous) ? wrap::pass_overflow(wanted.az, continuous, ahead, plan)
                                                           : std::numeric_limits<double>::infinity();
    if (overflow_here <= culmination_slack_degrees) {
        return std::nullopt;
    }
    const auto branch = wrap::branch_for_pass(wanted.az, continuous, ahead, plan);
    if (!branch || wrap::pass_overflow(wanted.az, *branch, ahead, plan) >= overflow_here - culmination_slack_degrees) {
        return std::nullopt;
    }
    const auto reason = before_rise ? wrap::Reason::orbit_pass : wrap::Reason::culmination;
    emit(log_, LogLevel::verbose,
         "azimuth " + degrees_text(wanted.az) + ": mechanical " + degrees_text(*branch) + " instead of " +
             degrees_text(continuous) + " (" + std::string(wrap::reason_text(reason)) + "; the orbit's pass turns " +
             degrees_text(ahead.sweep_deg) + " deg from azimuth " + degrees_text(ahead.from_az) + "; window " +
             degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")");
    return branch;
}

void WrapTracker::forget_target() {
    target_mechanical_.reset();
    pass_direction_.reset();
    pass_ = PassProgress{};
}

std::string WrapTracker::describe() const {
    const wrap::Window& window = travel_.window;
    if (window.span() <= 360.0) {
        return "azimuth 0..360, no cable-wrap overlap; azimuth mapping " + learner_.describe();
    }
    std::string text = "cable wrap " + degrees_text(window.min) + ".." + degrees_text(window.max) +
                       " (commanded within " + degrees_text(usable_.min) + ".." + degrees_text(usable_.max) + ")";
    if (mechanical_) {
        text += "; mechanical az " + degrees_text(*mechanical_) +
                (reports_mechanical_
                     ? " (reported by the dish)"
                     : " (from 0..360 readings; the branch at start was assumed to be the one nearest AZ 0: "
                       "where the G2 homes, the reading itself on a window starting at 0)");
    } else {
        text += "; mechanical az unknown";
    }
    if (target_mechanical_) {
        text += "; target mechanical az " + degrees_text(*target_mechanical_);
    }
    text += "; azimuth mapping " + learner_.describe();
    return text;
}

}  // namespace birdcage
