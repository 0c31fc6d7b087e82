// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/wrap.hpp"

#include <algorithm>
#include <cmath>

#include "base/azel.hpp"

namespace birdcage::wrap {
namespace {

constexpr double epsilon = 1e-9;
constexpr double reading_slack_deg = 1.0;  // a reading may overshoot a limit by this much

bool same(double a, double b) {
    return std::fabs(a - b) < 1e-6;
}

}  // namespace

bool Window::contains(double mechanical) const {
    return mechanical >= min - epsilon && mechanical <= max + epsilon;
}

Window usable_window(Window mechanical, double margin) {
    const double room = std::max(0.0, (mechanical.span() - 360.0) / 2.0);
    const double applied = std::clamp(margin, 0.0, room);
    return {mechanical.min + applied, mechanical.max - applied};
}

double nearest_branch(double display, double reference) {
    return reference + azimuth_difference(reference, display);
}

std::vector<double> branches(double display, Window window) {
    const double base = normalize_azimuth(display);
    std::vector<double> found;
    const auto lowest = static_cast<long>(std::floor((window.min - base) / 360.0)) - 1;
    const auto highest = static_cast<long>(std::ceil((window.max - base) / 360.0)) + 1;
    for (long turn = lowest; turn <= highest; ++turn) {
        const double candidate = base + 360.0 * static_cast<double>(turn);
        if (window.contains(candidate)) {
            found.push_back(candidate);
        }
    }
    return found;
}

double unwrap_reading(double display, double reference, Window mechanical) {
    const auto candidates = branches(display, {mechanical.min - reading_slack_deg, mechanical.max + reading_slack_deg});
    if (candidates.empty()) {
        return nearest_branch(display, reference);
    }
    return *std::min_element(candidates.begin(), candidates.end(),
                             [&](double a, double b) { return std::fabs(a - reference) < std::fabs(b - reference); });
}

double start_branch(double display, Window mechanical) {
    return unwrap_reading(display, std::clamp(0.0, mechanical.min, mechanical.max), mechanical);
}

double room_ahead(double mechanical, int direction, Window window) {
    if (direction > 0) {
        return window.max - mechanical;
    }
    if (direction < 0) {
        return mechanical - window.min;
    }
    return 0.0;
}

std::string_view reason_text(Reason reason) {
    switch (reason) {
        case Reason::continuous:
            return "continuing on the same branch";
        case Reason::pass_start:
            return "a pass is starting and the current branch has too little room ahead for it";
        case Reason::forced_unwind:
            return "continuing would pass the wrap limit (less the margin): unwinding";
        case Reason::no_branch:
            return "no branch inside the wrap window: the nearest edge";
        case Reason::orbit_pass:
            return "the orbit shows the coming pass needs more room than this branch has: moving to the branch "
                   "that holds it before it rises";
        case Reason::culmination:
            return "past its culmination the pass needs more room than this branch has left: unwinding now, "
                   "where it costs least";
    }
    return "?";
}

Choice choose_branch(double display, double reference, int direction, bool pass_starting, Window usable) {
    const double continuous = nearest_branch(display, reference);
    const auto candidates = branches(display, usable);
    if (candidates.empty()) {
        return {std::clamp(continuous, usable.min, usable.max), Reason::no_branch, continuous};
    }
    const auto distance = [&](double candidate) { return std::fabs(candidate - reference); };
    const auto room = [&](double candidate) { return room_ahead(candidate, direction, usable); };
    // Nearest to the reference; on a tie, more room ahead.
    const auto nearer = [&](double a, double b) {
        return distance(a) < distance(b) - 1e-6 || (same(distance(a), distance(b)) && room(a) > room(b));
    };
    // More room ahead; on a tie, nearer.
    const auto roomier = [&](double a, double b) {
        return room(a) > room(b) + 1e-6 || (same(room(a), room(b)) && distance(a) < distance(b));
    };
    const auto pick = [&](auto better) { return *std::min_element(candidates.begin(), candidates.end(), better); };
    const auto choice = [&](double mechanical, Reason reason) {
        return Choice{mechanical, same(mechanical, continuous) ? Reason::continuous : reason, continuous};
    };

    if (pass_starting && direction != 0) {
        std::vector<double> enough;
        std::copy_if(candidates.begin(), candidates.end(), std::back_inserter(enough),
                     [&](double candidate) { return room(candidate) >= pass_span_deg; });
        if (!enough.empty()) {
            return choice(*std::min_element(enough.begin(), enough.end(), nearer), Reason::pass_start);
        }
        return choice(pick(roomier), Reason::pass_start);
    }
    if (usable.contains(continuous)) {
        return {continuous, Reason::continuous, continuous};
    }
    return choice(direction != 0 ? pick(roomier) : pick(nearer), Reason::forced_unwind);
}

std::pair<double, double> pass_travel(double display, double mechanical, const PassAhead& ahead) {
    const double start = mechanical + azimuth_difference(display, ahead.from_az);
    const double end = start + ahead.sweep_deg;
    return {std::min({mechanical, start, end}), std::max({mechanical, start, end})};
}

double pass_overflow(double display, double mechanical, const PassAhead& ahead, Window usable) {
    const auto [lowest, highest] = pass_travel(display, mechanical, ahead);
    return std::max({0.0, usable.min - lowest, highest - usable.max});
}

std::optional<double> branch_for_pass(double display, double reference, const PassAhead& ahead, Window usable) {
    std::optional<double> best;
    double best_overflow = 0.0;
    for (double candidate : branches(display, usable)) {
        const double overflow = pass_overflow(display, candidate, ahead, usable);
        const bool better =
            !best || overflow < best_overflow - 1e-6 ||
            (same(overflow, best_overflow) && std::fabs(candidate - reference) < std::fabs(*best - reference));
        if (better) {
            best = candidate;
            best_overflow = overflow;
        }
    }
    return best;
}

std::optional<double> culmination_branch(double display, double continuous, int direction, double remaining_deg,
                                         Window usable, double slack_deg) {
    if (direction == 0 || room_ahead(continuous, direction, usable) >= remaining_deg - slack_deg) {
        return std::nullopt;
    }
    std::optional<double> best;
    for (double candidate : branches(display, usable)) {
        if (room_ahead(candidate, direction, usable) >= remaining_deg &&
            (!best || std::fabs(candidate - continuous) < std::fabs(*best - continuous))) {
            best = candidate;
        }
    }
    return best;
}

double next_waypoint(double from, double to, double max_leg) {
    const double distance = to - from;
    if (!(max_leg > 0.0) || std::fabs(distance) <= max_leg) {
        return to;
    }
    const double legs = std::ceil(std::fabs(distance) / max_leg - epsilon);
    return from + distance / legs;
}

std::vector<double> waypoints(double from, double to, double max_leg) {
    std::vector<double> steps;
    double at = from;
    for (int guard = 0; guard < 1000; ++guard) {
        at = next_waypoint(at, to, max_leg);
        steps.push_back(at);
        if (at == to) {
            break;
        }
    }
    return steps;
}

}  // namespace birdcage::wrap
