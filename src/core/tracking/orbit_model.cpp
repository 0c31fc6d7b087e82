// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/orbit_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "tracking/orbit_geometry.hpp"

namespace birdcage {
using namespace orbit_geometry;
namespace {

// Steps between targets shorter than this (degrees) carry rounding and scatter, not a direction.
constexpr double turn_min_step_deg = 0.3;

}  // namespace

OrbitModel::OrbitModel(OrbitModelSettings settings) : settings_(settings) {
    set_dish_limits(settings.el_floor, settings.el_cap);
}

void OrbitModel::set_dish_limits(double el_floor, double el_cap) {
    settings_.el_floor = el_floor;
    settings_.el_cap = el_cap;
    client_min_el_ = el_floor;
    client_max_el_ = el_cap;
}

OrbitModel::ClientView OrbitModel::client_view() const {
    return {orbit_ ? orbit_->lead_deg : lead_hint_deg_.value_or(0.0), client_min_el_, client_max_el_};
}

void OrbitModel::clear() {
    targets_.clear();
    orbit_.reset();
    client_min_el_ = settings_.el_floor;
    client_max_el_ = settings_.el_cap;
    trusted_ = false;
    residual_ = {};
    lead_fitted_despite_hint_ = false;
    lead_none_despite_hint_ = false;
    no_look_ahead_ = false;
    next_lead_question_ = 0;
    description_ = "no targets";
}

bool OrbitModel::add(double t, AzEl target, std::optional<double> lead_hint_deg) {
    if (!std::isfinite(t) || !std::isfinite(target.az) || !std::isfinite(target.el)) {
        return true;
    }
    lead_hint_deg_ = lead_hint_deg;
    // A target beyond the dish's limits shows a client whose own limits are wider (the backend
    // clamps): its targets below the floor are exact, and its lowest is the horizon.
    if (target.el > same_angle_degrees && target.el < settings_.el_floor - same_angle_degrees) {
        client_min_el_ = 0.0;
    }
    if (target.el > settings_.el_cap + same_angle_degrees) {
        client_max_el_ = 90.0;
    }
    const bool below_horizon = target.el <= client_min_el_ + same_angle_degrees;
    const bool clamped = std::fabs(target.el - client_min_el_) < same_angle_degrees ||
                         std::fabs(target.el - client_max_el_) < same_angle_degrees;
    const Kind kind = below_horizon && target.el <= same_angle_degrees ? Kind::before_rise
                      : clamped                                        ? Kind::clamped
                                                                       : Kind::exact;
    bool expected = true;
    if (trusted_ && kind == Kind::exact) {
        // Within a second of the client's timing: near north the client's plain comparison of
        // azimuths makes its target jump by a whole threshold between one side and the other, and
        // which side the orbit puts the satellite on at the dated time is a matter of tenths of a
        // second (Gpredict at north, docs/gpredict.md).
        double miss = HUGE_VAL;
        for (const double shift : {-1.0, -0.5, 0.0, 0.5, 1.0}) {
            if (const auto where = expected_target(t - settings_.client_send_delay_s + shift)) {
                miss = std::min(miss, angle_deg(unit_vector(*where), unit_vector(target)));
            }
        }
        expected = miss <= std::max(settings_.innovation_gate_deg, settings_.gate_residuals * residual_.rms_deg);
    }
    if (kind == Kind::before_rise) {
        // The client repeats the AOS azimuth while it waits: only the newest of those counts.
        targets_.erase(std::remove_if(targets_.begin(), targets_.end(),
                                      [](const Target& old) { return old.kind == Kind::before_rise; }),
                       targets_.end());
    }
    targets_.push_back({t - settings_.client_send_delay_s, target, kind});
    while (!targets_.empty() && t - targets_.front().t > settings_.window_s) {
        targets_.pop_front();
    }
    if (targets_.size() > settings_.max_targets) {
        // Thin out where the targets are densest (a client sending every cycle), never the newest.
        std::size_t closest = 1;
        double closest_gap = HUGE_VAL;
        for (std::size_t i = 1; i + 2 < targets_.size(); ++i) {
            const double gap = targets_[i + 1].t - targets_[i - 1].t;
            if (gap < closest_gap) {
                closest_gap = gap;
                closest = i;
            }
        }
        targets_.erase(targets_.begin() + static_cast<std::ptrdiff_t>(closest));
    }
    refit(!expected);
    if (!expected && !trusted_) {
        // Not the satellite the model followed: start again from this target.
        const Target newest = targets_.back();
        clear();
        targets_.push_back(newest);
        description_ = "restarted: a target off the fitted orbit";
    }
    return expected;
}

std::optional<OrbitPoint> OrbitModel::predict(double t) const {
    if (!orbit_) {
        return std::nullopt;
    }
    const Evaluator model(*orbit_, earth_at(settings_.latitude_deg));
    constexpr double h = 0.5;
    const AzEl before = model.azel(t - h), now = model.azel(t), after = model.azel(t + h);
    return OrbitPoint{now, azimuth_difference(before.az, after.az) / (2 * h), (after.el - before.el) / (2 * h)};
}

std::optional<AzEl> OrbitModel::expected_target(double t) const {
    if (!orbit_) {
        return std::nullopt;
    }
    const Evaluator model(*orbit_, earth_at(settings_.latitude_deg));
    const ClientView client = client_view();
    return model.look_ahead(t, client.threshold, model.set_after(t), client.min_el, client.max_el);
}

std::optional<double> OrbitModel::altitude_km() const {
    return orbit_ ? std::optional<double>(orbit_->altitude_km) : std::nullopt;
}

std::optional<double> OrbitModel::lead_deg() const {
    return orbit_ ? std::optional<double>(client_view().threshold) : std::nullopt;
}

std::optional<double> OrbitModel::time_below(double t, double el, double within_s) const {
    if (!orbit_) {
        return std::nullopt;
    }
    const Evaluator model(*orbit_, earth_at(settings_.latitude_deg));
    double previous = t;
    for (double s = t; s <= t + within_s; s += 2.0) {
        if (model.azel(s).el < el) {
            double lo = previous, hi = s;
            for (int i = 0; i < 20 && hi > lo; ++i) {
                const double mid = 0.5 * (lo + hi);
                (model.azel(mid).el < el ? hi : lo) = mid;
            }
            return hi;
        }
        previous = s;
    }
    return std::nullopt;
}

std::optional<OrbitModel::PassSpan> OrbitModel::pass_above(double t, double el, double within_s) const {
    if (!orbit_) {
        return std::nullopt;
    }
    const Evaluator model(*orbit_, earth_at(settings_.latitude_deg));
    // One-second steps: near the zenith a LEO satellite's azimuth turns up to ~20 deg/s, still
    // far from the 180 deg a step may turn before its direction is ambiguous.
    constexpr double step_s = 1.0;
    std::optional<PassSpan> span;
    AzEl previous{};
    for (double s = t; s <= t + within_s; s += step_s) {
        const AzEl here = model.azel(s);
        if (!span) {
            if (here.el >= el) {
                span = PassSpan{s, here.az, s, here.el, s, 0.0};
                previous = here;
            }
            continue;
        }
        if (here.el < el) {
            return span;
        }
        span->sweep_deg += azimuth_difference(previous.az, here.az);
        span->end_t = s;
        if (here.el > span->top_el) {
            span->top_t = s;
            span->top_el = here.el;
        }
        previous = here;
    }
    // Still above `el` at the end of the look: the pass's end is not known, nor its room.
    return std::nullopt;
}

std::vector<AzEl> OrbitModel::exact_directions() const {
    std::vector<AzEl> directions;
    for (const auto& target : targets_) {
        if (target.kind == Kind::exact) {
            directions.push_back(target.direction);
        }
    }
    return directions;
}

std::vector<AzEl> OrbitModel::exact_directions_along_track() const {
    // Longer than any look-ahead a client reaches for a target to be worth sending.
    constexpr double longest_look_ahead_s = 300.0;
    const Evaluator model(*orbit_, earth_at(settings_.latitude_deg));
    std::vector<std::pair<double, AzEl>> placed;
    for (const auto& target : targets_) {
        if (target.kind != Kind::exact) {
            continue;
        }
        const Vec wanted = unit_vector(target.direction);
        auto miss = [&](double s) { return angle_deg(model.direction(s), wanted); };
        const double earliest = target.t - settings_.client_send_delay_s - 2.0;
        double best = earliest;
        for (double s = earliest; s <= target.t + longest_look_ahead_s; s += 1.0) {
            if (miss(s) < miss(best)) {
                best = s;
            }
        }
        double lo = best - 1.0, hi = best + 1.0;
        for (int i = 0; i < 20; ++i) {
            const double a = lo + (hi - lo) / 3.0, b = hi - (hi - lo) / 3.0;
            if (miss(a) < miss(b)) {
                hi = b;
            } else {
                lo = a;
            }
        }
        placed.emplace_back(0.5 * (lo + hi), target.direction);
    }
    std::stable_sort(placed.begin(), placed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<AzEl> directions;
    for (const auto& [t, direction] : placed) {
        directions.push_back(direction);
    }
    return directions;
}

void OrbitModel::judge() {
    static const char* const off_orbit = "targets off the orbit";
    trusted_ = false;
    if (!orbit_) {
        if (targets_.size() < 2) {
            description_ = "waiting for a second target";
        }
        return;
    }
    std::size_t exact = 0;
    const Target* first = nullptr;
    const Target* last = nullptr;
    for (const auto& t : targets_) {
        if (t.kind == Kind::exact) {
            ++exact;
            first = first ? first : &t;
            last = &t;
        }
    }
    const double arc = first ? angle_deg(unit_vector(first->direction), unit_vector(last->direction)) : 0.0;
    const double span = first ? last->t - first->t : 0.0;
    // What the fit holds as the client's lead: the caller's hint, none (the targets showed the
    // hint to be the dish's gaps misread), or a lead fitted with the orbit.
    char lead_source[128];
    if (no_look_ahead_) {
        std::snprintf(lead_source, sizeof lead_source, "none: the client sends what Gpredict's rule would not");
    } else if (lead_hint_deg_ && lead_none_despite_hint_) {
        std::snprintf(lead_source, sizeof lead_source, "none: the targets fit it better than the dish's gaps' %.2f",
                      *lead_hint_deg_);
    } else if (lead_hint_deg_ && lead_fitted_despite_hint_) {
        std::snprintf(lead_source, sizeof lead_source, "fitted, +-%.2f; the dish's gaps said %.2f",
                      orbit_->lead_sigma_deg, *lead_hint_deg_);
    } else if (lead_hint_deg_) {
        std::snprintf(lead_source, sizeof lead_source, "learnt from the dish");
    } else {
        std::snprintf(lead_source, sizeof lead_source, "fitted, +-%.2f", orbit_->lead_sigma_deg);
    }
    char checks[64] = "";
    if (residual_.check_count) {
        std::snprintf(checks, sizeof checks, ", %zu clamped at %.1f", residual_.check_count,
                      residual_.check_normalised);
    }
    char text[384];
    std::snprintf(text, sizeof text,
                  "orbit %.0f km, client lead %.2f deg (%s), %zu targets (%zu exact over %.1f deg, %.0f s), RMS %.3f "
                  "deg (%.1f of the expected scatter%s)%s",
                  orbit_->altitude_km, client_view().threshold, lead_source, targets_.size(), exact, arc, span,
                  residual_.rms_deg, residual_.normalised, checks,
                  settings_.latitude_deg ? "" : ", Earth taken as still (no latitude)");
    description_ = text;
    const char* why = nullptr;
    // Two exact targets fit any orbit through them; only the clamped targets test it then.
    const bool checked = exact >= settings_.min_exact_targets_checked && residual_.check_count > 0 &&
                         residual_.check_normalised <= settings_.max_normalised_residual;
    if (exact < settings_.min_exact_targets && !checked) {
        why = "too few targets";
    } else if (arc < settings_.min_arc_deg || span < settings_.min_span_s) {
        why = "targets too close together";
    } else if (sharpest_turn_deg(exact_directions(), turn_min_step_deg) > settings_.max_turn_deg &&
               sharpest_turn_deg(exact_directions_along_track(), turn_min_step_deg) > settings_.max_turn_deg) {
        // In the order sent, a pass's targets can step back along it where a client's look-ahead
        // shrinks (Gpredict's azimuth box towards the zenith: in that order iss-85 at 5 deg is never
        // trusted);
        // in their order along the fitted track they turn as gently as the pass. A scan's
        // serpentine or a user's jogging turns in either order.
        why = "the targets turn as no pass does (manual pointing, a scan)";
    } else if (!lead_hint_deg_ && (orbit_->lead_sigma_deg > settings_.max_lead_sigma_deg ||
                                   exact < settings_.min_exact_targets_fitted_lead)) {
        why = "the client's lead not yet known";
    } else if (residual_.normalised > settings_.max_normalised_residual ||
               residual_.rms_deg > settings_.max_residual_deg) {
        why = off_orbit;
    } else if (orbit_->altitude_km < settings_.min_altitude_km || orbit_->altitude_km > settings_.max_altitude_km) {
        why = "no LEO altitude";
    }
    if (why) {
        description_ += std::string("; not trusted: ") + why;
        // Targets that are not one pass (an earlier pass, manual pointing before it) are let go
        // from the oldest, so the fit can settle on the pass that follows.
        if (why == off_orbit && exact > settings_.min_exact_targets) {
            targets_.pop_front();
        }
        return;
    }
    trusted_ = true;
}

}  // namespace birdcage
