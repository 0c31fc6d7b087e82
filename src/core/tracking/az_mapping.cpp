// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/az_mapping.hpp"

#include <algorithm>
#include <cmath>

#include "base/azel.hpp"
#include "firmware/protocol.hpp"

namespace birdcage::azmap {
namespace {

// Readings and arrival are good to a fraction of a degree; readings disagree by whole branches.
constexpr double consistency_tolerance_deg = 5.0;
// A wrap point known within this arc is known well enough to plan with.
constexpr int pinned_arc_deg = 90;

wrap::Window intersect(wrap::Window a, wrap::Window b) {
    return {std::max(a.min, b.min), std::min(a.max, b.max)};
}

std::string whole(double value) {
    return std::to_string(static_cast<long>(std::lround(value)));
}

}  // namespace

std::string_view mapping_name(Mapping mapping) {
    switch (mapping) {
        case Mapping::nearest:
            return "nearest";
        case Mapping::literal:
            return "literal";
        case Mapping::wrap_manager:
            return "wrap_manager";
    }
    return "?";
}

std::optional<Mapping> mapping_from_name(std::string_view name) {
    for (const Mapping mapping : all_mappings) {
        if (mapping_name(mapping) == name) {
            return mapping;
        }
    }
    return std::nullopt;
}

double command_value(double mechanical, const Travel& travel) {
    const double printed = std::round(mechanical * 100.0) / 100.0;
    return travel.negative_is_relative ? normalize_azimuth(printed) : printed;
}

wrap::Window wrap_sector(double wrap_point, const Travel& travel) {
    const double point = normalize_azimuth(wrap_point);
    double best = point + 360.0 * std::floor((travel.window.min - point) / 360.0);
    double best_overlap = -1.0;
    for (double start = best; start < travel.window.max; start += 360.0) {
        const double overlap = std::min(travel.window.max, start + 360.0) - std::max(travel.window.min, start);
        if (overlap > best_overlap + 1e-9) {
            best_overlap = overlap;
            best = start;
        }
    }
    return {best, best + 360.0};
}

double predict(Mapping mapping, double value, double from, const Travel& travel, double wrap_point) {
    const wrap::Window& window = travel.window;
    const auto clamp = [&](double mechanical) { return std::clamp(mechanical, window.min, window.max); };
    switch (mapping) {
        case Mapping::nearest: {
            if ((value < 0.0 || value >= 360.0) && window.contains(value)) {
                return value;
            }
            const auto candidates = wrap::branches(value, window);
            if (candidates.empty()) {
                return clamp(value);
            }
            return *std::min_element(candidates.begin(), candidates.end(),
                                     [&](double a, double b) { return std::fabs(a - from) < std::fabs(b - from); });
        }
        case Mapping::literal:
            if (!window.contains(value) && travel.negative_is_relative && window.contains(value - 360.0)) {
                return value - 360.0;
            }
            return clamp(value);
        case Mapping::wrap_manager: {
            const wrap::Window sector = wrap_sector(wrap_point, travel);
            const double offset = normalize_azimuth(value - wrap_point);
            if (offset < 1e-9) {
                return clamp(std::fabs(from - sector.min) <= std::fabs(from - sector.max) ? sector.min : sector.max);
            }
            return clamp(sector.min + offset);
        }
    }
    return clamp(value);
}

wrap::Window reachable(Mapping mapping, const Travel& travel, double wrap_point) {
    switch (mapping) {
        case Mapping::nearest:
            return travel.window;
        case Mapping::literal:
            // Numbers >= 0 name themselves inside the travel, and the angle 360 below otherwise.
            return travel.negative_is_relative
                       ? wrap::Window{std::max(travel.window.min, travel.window.max - 360.0), travel.window.max}
                       : travel.window;
        case Mapping::wrap_manager:
            return intersect(wrap_sector(wrap_point, travel), travel.window);
    }
    return travel.window;
}

Learner::Learner(Travel travel, std::optional<Mapping> stated) : travel_(travel), stated_(stated) {
    wrap_candidates_.set();
}

bool Learner::consistent(Mapping mapping, const Observation& seen, double wrap_point) const {
    const double expected = predict(mapping, seen.value, seen.from, travel_, wrap_point);
    const double low = std::min(seen.from, expected) - consistency_tolerance_deg;
    const double high = std::max(seen.from, expected) + consistency_tolerance_deg;
    if (seen.lowest < low || seen.highest > high) {
        return false;  // it went where this reading would not take it
    }
    if (mapping == Mapping::wrap_manager) {
        // A wrap manager never lets the axis through its point: one the dish swept past is not it
        // (unless the axis started outside the manager's sector, as a dish may at power-on: the
        // way in may cross it).
        const wrap::Window sector = wrap_sector(wrap_point, travel_);
        const bool started_inside =
            seen.from >= sector.min - consistency_tolerance_deg && seen.from <= sector.max + consistency_tolerance_deg;
        const double inner_low = seen.lowest + consistency_tolerance_deg;
        const double inner_high = seen.highest - consistency_tolerance_deg;
        const double first = wrap_point + 360.0 * std::ceil((inner_low - wrap_point) / 360.0);
        if (started_inside && inner_low < inner_high && first < inner_high) {
            return false;
        }
    }
    return !seen.end || std::fabs(*seen.end - expected) <= consistency_tolerance_deg;
}

std::optional<std::string> Learner::observe(const Observation& seen) {
    std::array<bool, 3> now = possible_;
    std::bitset<360> candidates = wrap_candidates_;
    now[static_cast<int>(Mapping::nearest)] = now[0] && consistent(Mapping::nearest, seen, 0.0);
    now[static_cast<int>(Mapping::literal)] = now[1] && consistent(Mapping::literal, seen, 0.0);
    for (int point = 0; point < 360; ++point) {
        if (candidates[point] && !consistent(Mapping::wrap_manager, seen, point)) {
            candidates.reset(point);
        }
    }
    now[static_cast<int>(Mapping::wrap_manager)] = candidates.any();
    const std::string move = "a 0 " + format_degrees(seen.value) + " from mechanical " + format_degrees(seen.from) +
                             (seen.end ? " ended at " + format_degrees(*seen.end) : std::string(" swept ")) +
                             (seen.end ? "" : format_degrees(seen.lowest) + ".." + format_degrees(seen.highest));

    if (stated_) {
        const auto index = static_cast<std::size_t>(*stated_);
        const bool fits = *stated_ == Mapping::wrap_manager ? candidates.any() : now[index];
        if (fits) {
            if (*stated_ == Mapping::wrap_manager && candidates != wrap_candidates_) {
                const bool was_pinned = wrap_point().has_value();
                wrap_candidates_ = candidates;
                if (!was_pinned && wrap_point()) {
                    return "azimuth mapping: " + move + "; " + describe();
                }
            }
            return std::nullopt;
        }
        ++contradictions_;
        return "azimuth mapping: " + move + ", which az_mapping=" + std::string(mapping_name(*stated_)) +
               " (stated) does not explain; keeping it as stated";
    }
    if (now == possible_ && candidates == wrap_candidates_) {
        return std::nullopt;
    }
    if (!now[0] && !now[1] && !now[2]) {
        possible_ = {true, true, true};
        wrap_candidates_.set();
        ++contradictions_;
        return "azimuth mapping: " + move + ", which no known reading explains; every reading is possible again";
    }
    const Mapping before = planning();
    const bool was_pinned = wrap_point().has_value();
    const bool readings_changed = now != possible_;
    possible_ = now;
    wrap_candidates_ = candidates;
    // Every move that does not pass the wrap point narrows where it can be: worth a line only once
    // that is known well enough to plan with.
    if (!readings_changed && (was_pinned || !wrap_point())) {
        return std::nullopt;
    }
    std::string text = "azimuth mapping: " + move + ": " + describe();
    if (planning() != before) {
        text += " (was planning as " + std::string(mapping_name(before)) + ")";
    }
    return text;
}

bool Learner::possible(Mapping mapping) const {
    if (stated_) {
        return mapping == *stated_;
    }
    return possible_[static_cast<std::size_t>(mapping)];
}

std::optional<Mapping> Learner::known() const {
    if (stated_) {
        return stated_;
    }
    std::optional<Mapping> only;
    for (const Mapping mapping : all_mappings) {
        if (possible(mapping)) {
            if (only) {
                return std::nullopt;
            }
            only = mapping;
        }
    }
    return only;
}

Mapping Learner::planning() const {
    for (const Mapping mapping : all_mappings) {
        if (possible(mapping)) {
            return mapping;
        }
    }
    return Mapping::nearest;
}

std::optional<std::pair<int, int>> Learner::candidate_arc() const {
    if (wrap_candidates_.none()) {
        return std::nullopt;
    }
    // The longest run of excluded points ends where the smallest arc holding the candidates starts.
    int best_gap = 0, best_start = 0, run = 0;
    for (int i = 0; i < 720; ++i) {
        if (!wrap_candidates_[i % 360]) {
            ++run;
            if (run > best_gap && run < 360) {
                best_gap = run;
                best_start = (i + 1) % 360;
            }
        } else {
            run = 0;
        }
    }
    if (best_gap == 0) {
        return std::pair{0, 359};
    }
    return std::pair{best_start, 359 - best_gap};
}

std::optional<double> Learner::wrap_point() const {
    const auto arc = candidate_arc();
    if (!possible(Mapping::wrap_manager) || !arc || arc->second > pinned_arc_deg) {
        return std::nullopt;
    }
    return normalize_azimuth(arc->first + arc->second / 2.0);
}

wrap::Window Learner::plan_window(wrap::Window usable) const {
    wrap::Window window = usable;
    switch (planning()) {
        case Mapping::nearest:
            break;
        case Mapping::literal:
            window = intersect(usable, reachable(Mapping::literal, travel_));
            break;
        case Mapping::wrap_manager: {
            const auto arc = candidate_arc();
            if (arc && arc->second <= pinned_arc_deg) {
                // Safe for every candidate: the sectors' common part.
                for (int k = 0; k <= arc->second; ++k) {
                    window = intersect(window, reachable(Mapping::wrap_manager, travel_, arc->first + k));
                }
            } else if (wrap_candidates_[0]) {
                window = intersect(usable, reachable(Mapping::wrap_manager, travel_, 0.0));
            }
            break;
        }
    }
    return window.span() >= 1.0 ? window : usable;
}

std::string Learner::describe() const {
    std::string text;
    if (stated_) {
        text = std::string(mapping_name(*stated_)) + " (stated";
        if (contradictions_ > 0) {
            text += "; " + std::to_string(contradictions_) + " moves it did not explain";
        }
        text += ")";
    } else if (const auto only = known()) {
        text = "learnt " + std::string(mapping_name(*only));
    } else {
        text = "auto, still possible:";
        for (const Mapping mapping : all_mappings) {
            if (possible(mapping)) {
                text += " " + std::string(mapping_name(mapping));
            }
        }
        text += "; planning as " + std::string(mapping_name(planning()));
    }
    if (possible(Mapping::wrap_manager)) {
        const auto arc = candidate_arc();
        if (arc && arc->second < 359) {
            text +=
                "; wrap point within " + whole(arc->first) + ".." + whole(normalize_azimuth(arc->first + arc->second));
        }
    }
    return text;
}

}  // namespace birdcage::azmap
