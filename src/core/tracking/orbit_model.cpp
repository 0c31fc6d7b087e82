// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage/tracking/orbit_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace birdcage {
namespace {

using Vec = std::array<double, 3>;
using Orbit = OrbitModel::Orbit;

constexpr double deg = M_PI / 180.0;
constexpr double earth_mu_km3_s2 = 398600.4418;     // WGS-84
constexpr double earth_spin_rad_s = 7.2921159e-5;   // sidereal
constexpr double equatorial_radius_km = 6378.137;
constexpr double polar_radius_km = 6356.752;
constexpr double mean_radius_km = 6371.0;
// Weight of a clamped target's one residual against an exact target's direction.
constexpr double clamped_weight = 0.5;
// The two-point solution's scan of altitudes (km) before bisection.
constexpr double scan_step_km = 10.0;
// Levenberg–Marquardt.
constexpr int initial_iterations = 40;
constexpr int warm_iterations = 10;
// The scatter of a target about the orbit, at least (degrees): a client's tick and I/O loop put up to
// 0.8 s between computing a target and sending it, and Gpredict's search stops within a quarter cycle.
constexpr double target_scatter_deg = 0.1;
constexpr double send_jitter_sd_s = 0.25;
// Steps between targets shorter than this (degrees) carry rounding and scatter, not a direction.
constexpr double turn_min_step_deg = 0.3;
// The largest client lead the fit considers (degrees): Gpredict's threshold setting goes to 10.
constexpr double max_fitted_lead_deg = 10.0;
// Penalty (degrees) for a before-rise target when the model's track never rises in the search.
constexpr double no_rise_penalty_deg = 10.0;
constexpr double rise_search_s = 1800.0;
// The learnt lead is questioned from this many exact targets on, and replaced by the fitted one
// where that misses the targets by less than this share of what the learnt one does (the targets'
// scatter is not all timing: Gpredict's quantised search leaves a systematic part, which a free
// lead would fit as readily as a real difference).
constexpr std::size_t lead_question_min_targets = 4, lead_question_every_target_below = 30;
constexpr double lead_question_gain = 0.8;

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec scaled(const Vec& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
Vec plus(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec minus(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec unit(const Vec& a) { return scaled(a, 1.0 / std::sqrt(dot(a, a))); }

Vec unit_vector(AzEl p) {
    const double az = p.az * deg, el = p.el * deg;
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

AzEl direction_of(const Vec& v) {
    return {normalize_azimuth(std::atan2(v[0], v[1]) / deg), std::atan2(v[2], std::hypot(v[0], v[1])) / deg};
}

double angle_deg(const Vec& a, const Vec& b) {
    return std::atan2(std::sqrt(dot(cross(a, b), cross(a, b))), dot(a, b)) / deg;
}

// Rodrigues: v turned by `angle` about the unit `axis`.
Vec rotated(const Vec& v, const Vec& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return plus(plus(scaled(v, c), scaled(cross(axis, v), s)), scaled(axis, dot(axis, v) * (1.0 - c)));
}

// The Earth as the site sees it: the centre's distance below the site and the spin axis in the
// site's east-north-up frame.
struct Earth {
    double radius_km = mean_radius_km;
    Vec axis{0.0, 0.0, 1.0};
    double spin = 0.0;   // rad/s; 0: a still Earth
};

Earth earth_at(std::optional<double> latitude_deg) {
    Earth earth;
    if (!latitude_deg) {
        return earth;
    }
    const double lat = *latitude_deg * deg;
    const double a = equatorial_radius_km, b = polar_radius_km;
    const double ca = a * std::cos(lat), sb = b * std::sin(lat);
    earth.radius_km = std::sqrt((a * ca * a * ca + b * sb * b * sb) / (ca * ca + sb * sb));
    earth.axis = {0.0, std::cos(lat), std::sin(lat)};
    earth.spin = earth_spin_rad_s;
    return earth;
}

double kepler_rate(double radius_km) { return std::sqrt(earth_mu_km3_s2 / (radius_km * radius_km * radius_km)); }

// The orbit's geometry at its reference time: position direction p0 and in-plane direction of
// motion w (geocentric, site frame), radius and rate.
struct Circle {
    Vec p0, w;
    double radius_km, rate;
};

Circle circle_of(const Orbit& o, const Earth& earth) {
    const Vec p0 = unit({o.x, o.y, 1.0});
    const Vec east{1.0, 0.0, 0.0};
    const Vec e1 = unit(minus(east, scaled(p0, dot(east, p0))));
    const Vec e2 = cross(p0, e1);
    const double radius = earth.radius_km + o.altitude_km;
    return {p0, plus(scaled(e1, std::cos(o.heading)), scaled(e2, std::sin(o.heading))), radius, kepler_rate(radius)};
}

// The satellite seen from the site at time t, as a vector (km).
Vec line_of_sight(const Circle& c, const Earth& earth, double t_ref, double t) {
    const double dt = t - t_ref;
    const double phase = c.rate * dt;
    const Vec inertial = scaled(plus(scaled(c.p0, std::cos(phase)), scaled(c.w, std::sin(phase))), c.radius_km);
    Vec local = earth.spin != 0.0 ? rotated(inertial, earth.axis, -earth.spin * dt) : inertial;
    local[2] -= earth.radius_km;
    return local;
}

struct Evaluator {
    const Orbit& orbit;
    Earth earth;
    Circle circle;
    Evaluator(const Orbit& o, const Earth& e) : orbit(o), earth(e), circle(circle_of(o, e)) {}
    Vec direction(double t) const { return unit(line_of_sight(circle, earth, orbit.t_ref, t)); }
    AzEl azel(double t) const { return direction_of(line_of_sight(circle, earth, orbit.t_ref, t)); }

    // Gpredict's look-ahead from time t (gtk-rot-ctrl.c, docs/tracking.md §5): its target is the
    // current direction clamped to its limits, and when it sends one it searches the furthest time
    // before `set_time` (the pass's end) at which the satellite is still within `threshold` of that
    // on both axes (plain differences), by bisection from the whole remaining pass down to a
    // quarter of its 1 s cycle. Returns where the search ends: the target it sends.
    //
    // Where the satellite is inside the client's limits the box's boundary is found here by secant
    // steps, and the bisection is replayed against it: where it stops differs from the boundary by
    // up to half a second, which at 0.5° is a tenth of the lead. The fit needs residuals that move
    // smoothly with the orbit, so it passes `search_offset`, that difference as it was at the start
    // of its step, and gets the new one back in `new_search_offset`.
    AzEl look_ahead(double t, double threshold, double set_time, double min_el, double max_el,
                    std::optional<double> search_offset = std::nullopt, double* new_search_offset = nullptr) const {
        const AzEl now = azel(t);
        const AzEl set{now.az, std::clamp(now.el, min_el, max_el)};
        if (new_search_offset) {
            *new_search_offset = 0.0;
        }
        if (threshold <= 0.0 || now.el <= 0.0) {
            return set;
        }
        const double remaining = std::max(0.0, set_time - t);
        if (set.el == now.el) {
            auto moved = [&](double tau) {
                const AzEl to = azel(t + tau);
                return std::max(std::fabs(azimuth_difference(set.az, to.az)), std::fabs(to.el - set.el));
            };
            const double per_second = moved(1.0);
            double tau = per_second > 1e-9 ? std::min(threshold / per_second, remaining) : remaining;
            for (int step = 0; step < 4; ++step) {
                const double d = moved(tau);
                if (d < 1e-9) {
                    break;
                }
                tau = std::clamp(tau * threshold / d, 0.0, remaining);
            }
            // Gpredict compares azimuths as plain numbers: where the satellite crosses north
            // (359 to 1) its box ends, however little it moved.
            if (std::fabs(set.az - azel(t + tau).az) > 180.0) {
                double lo = 0.0, hi = tau;
                for (int i = 0; i < 30; ++i) {
                    const double mid = 0.5 * (lo + hi);
                    (std::fabs(set.az - azel(t + mid).az) > 180.0 ? hi : lo) = mid;
                }
                tau = lo;
            }
            const double offset = bisection_end(remaining, tau) - tau;
            if (new_search_offset) {
                *new_search_offset = offset;
            }
            const AzEl end = azel(t + tau + search_offset.value_or(offset));
            return {end.az, std::clamp(end.el, min_el, max_el)};
        }
        // Clamped: the box lies around a point the satellite is not at, and the search ends
        // wherever its steps happen to lead; replayed as it is.
        double delta = remaining;
        double step = std::max(delta / 2.0, 1.0);
        AzEl future = set;
        while (step > 0.25) {
            future = azel(t + delta);
            const bool too_far = future.el < 0.0 || std::fabs(set.az - future.az) > threshold ||
                                 std::fabs(set.el - future.el) > threshold;
            delta += too_far ? -step : step;
            step /= 2.0;
        }
        return {future.az, std::clamp(future.el, min_el, max_el)};
    }

    // Where Gpredict's bisection over [0, remaining] stops when everything up to `boundary` is
    // within its box and nothing after it.
    static double bisection_end(double remaining, double boundary) {
        double delta = remaining;
        double step = std::max(delta / 2.0, 1.0);
        double evaluated = delta;
        while (step > 0.25) {
            evaluated = delta;
            delta += delta > boundary ? -step : step;
            step /= 2.0;
        }
        return evaluated;
    }

    // When the track sets below the horizon after t (or t + rise_search_s).
    double set_after(double t) const {
        double previous = t;
        for (double s = t; s <= t + rise_search_s; s += 10.0) {
            if (azel(s).el < 0.0) {
                double lo = previous, hi = s;
                for (int i = 0; i < 20; ++i) {
                    const double mid = 0.5 * (lo + hi);
                    (azel(mid).el < 0.0 ? hi : lo) = mid;
                }
                return lo;
            }
            previous = s;
        }
        return t + rise_search_s;
    }

    // When the track first rises above the horizon after t.
    std::optional<double> rise_after(double t) const {
        double previous = t;
        if (azel(t).el >= 0.0) {
            return std::nullopt;
        }
        for (double s = t + 5.0; s <= t + rise_search_s; s += 5.0) {
            if (azel(s).el >= 0.0) {
                double lo = previous, hi = s;
                for (int i = 0; i < 30; ++i) {
                    const double mid = 0.5 * (lo + hi);
                    (azel(mid).el >= 0.0 ? hi : lo) = mid;
                }
                return hi;
            }
            previous = s;
        }
        return std::nullopt;
    }
};

// Solves the normal equations A x = b (n ≤ 4) by Gaussian elimination with partial pivoting.
template <std::size_t N>
bool solve(std::array<std::array<double, N>, N> a, std::array<double, N> b, std::array<double, N>& x) {
    for (std::size_t col = 0; col < N; ++col) {
        std::size_t pivot = col;
        for (std::size_t r = col + 1; r < N; ++r) {
            if (std::fabs(a[r][col]) > std::fabs(a[pivot][col])) {
                pivot = r;
            }
        }
        if (std::fabs(a[pivot][col]) < 1e-300) {
            return false;
        }
        std::swap(a[col], a[pivot]);
        std::swap(b[col], b[pivot]);
        for (std::size_t r = col + 1; r < N; ++r) {
            const double f = a[r][col] / a[col][col];
            for (std::size_t c = col; c < N; ++c) {
                a[r][c] -= f * a[col][c];
            }
            b[r] -= f * b[col];
        }
    }
    for (std::size_t i = N; i-- > 0;) {
        double s = b[i];
        for (std::size_t c = i + 1; c < N; ++c) {
            s -= a[i][c] * x[c];
        }
        x[i] = s / a[i][i];
    }
    return true;
}

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
                      : clamped                                           ? Kind::clamped
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

namespace {

struct Residuals {
    std::vector<double> values;
    std::vector<char> smooth;   // per value: from an unclamped target (the lead moves it smoothly)
    double exact_sum = 0.0;
    double normalised_sum = 0.0;   // each exact target's miss over the scatter expected of it
    std::size_t exact_count = 0;
};

// kind: 0 exact, 1 clamped, 2 before rise (OrbitModel::Kind).
// `search_offsets`: per target, where the client's search stopped against its box's boundary
// (Evaluator::look_ahead); empty: found now and stored there.
template <typename Targets>
Residuals residuals_of(const Orbit& orbit, const Earth& earth, const Targets& targets, const OrbitModel::ClientView& client,
                       std::vector<double>& search_offsets, double clamped_threshold) {
    const bool refresh = search_offsets.size() != targets.size();
    if (refresh) {
        search_offsets.assign(targets.size(), 0.0);
    }
    std::size_t index = 0;
    const Evaluator model(orbit, earth);
    Residuals out;
    out.values.reserve(targets.size() * 3);
    // One pass: the search of every target ends at the same set.
    double pass_end = targets.back().t;
    if (model.azel(pass_end).el < 0.0) {
        pass_end = model.rise_after(pass_end).value_or(pass_end);
    }
    pass_end = model.set_after(pass_end);
    for (const auto& target : targets) {
        double& search_offset = search_offsets[index++];
        const Vec seen = unit_vector(target.direction);
        if (target.kind == 2 || (target.kind == 1 && model.azel(target.t).el < 0.0)) {
            // Waiting below the horizon: the track must rise at the target's azimuth.
            const auto rise = model.rise_after(target.t);
            out.values.push_back(rise ? clamped_weight * azimuth_difference(target.direction.az, model.azel(*rise).az)
                                      : no_rise_penalty_deg);
            out.smooth.push_back(0);
            continue;
        }
        // A clamped target is what the client's search gave with the current direction clamped: the
        // same comparison, only its elevation says less (the model's on the limit too).
        // A clamped target's search jumps as the lead changes: it is compared at the lead the
        // fit's step started from, so the cost stays smooth in the lead.
        const double threshold = target.kind == 0 ? client.threshold : clamped_threshold;
        const Vec there = unit_vector(model.look_ahead(target.t, threshold, pass_end, client.min_el, client.max_el,
                                                       refresh ? std::nullopt : std::optional<double>(search_offset),
                                                       refresh ? &search_offset : nullptr));
        const double weight = target.kind == 0 ? 1.0 : clamped_weight;
        for (double component : minus(there, seen)) {
            out.values.push_back(weight * component / deg);
            out.smooth.push_back(target.kind == 0 ? 1 : 0);
        }
        if (target.kind == 0) {
            const double angle = angle_deg(there, seen);
            out.exact_sum += angle * angle;
            // Sent up to 0.8 s after it was computed (uniform: 0.23 s standard deviation) and cut
            // at a quarter cycle: the faster the satellite, the more a target scatters.
            const double sky_rate = angle_deg(model.direction(target.t), model.direction(target.t + 1.0));
            const double scatter = std::hypot(target_scatter_deg, send_jitter_sd_s * sky_rate);
            out.normalised_sum += angle * angle / (scatter * scatter);
            ++out.exact_count;
        }
    }
    return out;
}

}  // namespace

OrbitModel::FitResidual OrbitModel::refine(Orbit& orbit, int iterations) const {
    // The lead the caller learnt from the dish (the gap between a target and the dish it passed)
    // is held; fitted with the orbit, the lead wanders with the targets' timing scatter by more
    // than that learning errs. Without one the targets are all there is (and see question_lead()).
    return refine(orbit, iterations, lead_fitted_despite_hint_ ? std::nullopt : lead_hint_deg_);
}

// The dish's gaps cannot tell a client that leads by L from one that sends the satellite as it is
// each time it moved 2L (both leave a gap of 2L): a client without look-ahead was learnt as leading
// by half its threshold and followed that far ahead of the satellite (tests/core/test_orbit_model.cpp:
// 2.5 deg at 5 deg). The targets can tell: a lead is a time that changes with the satellite's rate,
// which no phase absorbs. So at each new target (from 4 exact ones on; past 30, each time they grew
// by a tenth) both are fitted, and the fitted lead is taken where it fits the targets clearly better.
void OrbitModel::question_lead() {
    if (!orbit_ || !lead_hint_deg_) {
        lead_fitted_despite_hint_ = false;
        return;
    }
    const std::size_t exact = residual_.exact_count;
    if (exact < lead_question_min_targets || (exact >= lead_question_every_target_below && exact < next_lead_question_)) {
        return;
    }
    // With many targets one more changes little: a client that sends every cycle (wide limits)
    // would otherwise double the cost of each of hundreds of refits.
    next_lead_question_ = exact + exact / 10;
    Orbit held = *orbit_, fitted = *orbit_;
    const FitResidual with_hint = refine(held, warm_iterations, lead_hint_deg_);
    const FitResidual free = refine(fitted, warm_iterations, std::nullopt);
    lead_fitted_despite_hint_ = free.normalised < lead_question_gain * with_hint.normalised &&
                                fitted.lead_sigma_deg <= settings_.max_lead_sigma_deg &&
                                std::fabs(fitted.lead_deg - *lead_hint_deg_) > 3.0 * fitted.lead_sigma_deg;
    orbit_ = lead_fitted_despite_hint_ ? fitted : held;
    residual_ = lead_fitted_despite_hint_ ? free : with_hint;
}

OrbitModel::FitResidual OrbitModel::refine(Orbit& orbit, int iterations, std::optional<double> fixed_lead) const {
    struct Flat {
        double t;
        AzEl direction;
        int kind;
    };
    std::vector<Flat> flat;
    flat.reserve(targets_.size());
    for (const auto& t : targets_) {
        flat.push_back({t.t, t.direction, t.kind == Kind::exact ? 0 : t.kind == Kind::clamped ? 1 : 2});
    }
    const Earth earth = earth_at(settings_.latitude_deg);
    // The client's lead is fitted too unless the caller knows it: a phase shift moves every target
    // by the same time, a lead by the time the satellite takes to cover one threshold, which
    // changes along the pass, so targets over a stretch of it tell the two apart.
    const bool fit_lead = !fixed_lead;
    if (!fit_lead) {
        orbit.lead_deg = *fixed_lead;
    }
    constexpr std::size_t n = 5;
    using Params = std::array<double, n>;
    auto params = [](const Orbit& o) { return Params{o.x, o.y, o.heading, o.altitude_km, o.lead_deg}; };
    auto with = [&](const Params& p) {
        Orbit o = orbit;
        o.x = p[0];
        o.y = p[1];
        o.heading = p[2];
        o.altitude_km = std::clamp(p[3], 50.0, 5000.0);
        o.lead_deg = std::clamp(p[4], 0.0, max_fitted_lead_deg);
        return o;
    };
    auto client_for = [&](const Orbit& o) {
        return ClientView{o.lead_deg, client_min_el_, client_max_el_};
    };
    auto sum_sq = [](const Residuals& r) {
        double s = 0.0;
        for (double v : r.values) {
            s += v * v;
        }
        return s;
    };
    const Params steps{1e-6, 1e-6, 1e-6, 1e-2, 1e-4};
    std::vector<double> offsets;
    Residuals current = residuals_of(orbit, earth, flat, client_for(orbit), offsets, orbit.lead_deg);
    double cost = sum_sq(current);
    double lambda = 1e-3;
    std::array<Params, n> last_jtj{};
    for (int iteration = 0; iteration < iterations; ++iteration) {
        // Where each search stopped, as of this orbit, held for the step.
        offsets.clear();
        const double step_lead = orbit.lead_deg;
        current = residuals_of(orbit, earth, flat, client_for(orbit), offsets, step_lead);
        cost = 0.0;
        for (double v : current.values) {
            cost += v * v;
        }
        const auto p = params(orbit);
        std::array<std::vector<double>, n> jacobian;
        for (std::size_t k = 0; k < n; ++k) {
            jacobian[k].assign(current.values.size(), 0.0);
            if (k == 4 && !fit_lead) {
                continue;
            }
            auto q = p;
            q[k] += steps[k];
            const Orbit moved_orbit = with(q);
            const Residuals moved = residuals_of(moved_orbit, earth, flat, client_for(moved_orbit), offsets, step_lead);
            for (std::size_t i = 0; i < current.values.size(); ++i) {
                // A clamped target's search jumps between steps as the lead changes: no slope.
                const bool counts = k != 4 || current.smooth[i];
                jacobian[k][i] = counts ? (moved.values[i] - current.values[i]) / steps[k] : 0.0;
            }
        }
        std::array<Params, n> jtj{};
        Params jtr{};
        for (std::size_t a = 0; a < n; ++a) {
            for (std::size_t i = 0; i < current.values.size(); ++i) {
                jtr[a] -= jacobian[a][i] * current.values[i];
            }
            for (std::size_t b = 0; b < n; ++b) {
                for (std::size_t i = 0; i < current.values.size(); ++i) {
                    jtj[a][b] += jacobian[a][i] * jacobian[b][i];
                }
            }
        }
        last_jtj = jtj;
        bool improved = false;
        for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
            auto damped = jtj;
            for (std::size_t a = 0; a < n; ++a) {
                damped[a][a] += lambda * std::max(jtj[a][a], 1e-12);
            }
            Params delta{};
            if (!solve(damped, jtr, delta)) {
                lambda *= 10.0;
                continue;
            }
            Params q = p;
            for (std::size_t a = 0; a < n; ++a) {
                q[a] += delta[a];
            }
            const Orbit trial = with(q);
            const Residuals r = residuals_of(trial, earth, flat, client_for(trial), offsets, step_lead);
            const double trial_cost = sum_sq(r);
            if (trial_cost < cost) {
                const double gain = cost - trial_cost;
                orbit = trial;
                current = r;
                cost = trial_cost;
                lambda = std::max(lambda * 0.3, 1e-9);
                improved = true;
                if (gain < 1e-10 * std::max(cost, 1e-12)) {
                    iteration = iterations;
                }
            } else {
                lambda *= 10.0;
            }
        }
        if (!improved) {
            break;
        }
    }
    // How well the targets pin the lead down: its standard error from the fit's curvature, with
    // the scatter of the targets at least what a client's timing gives them.
    orbit.lead_sigma_deg = 0.0;
    if (fit_lead) {
        Params unit_lead{};
        unit_lead[4] = 1.0;
        Params column{};
        const std::size_t m = current.values.size();
        const double scatter = std::max(std::sqrt(cost / static_cast<double>(m > n ? m - n : 1)), target_scatter_deg);
        orbit.lead_sigma_deg = solve(last_jtj, unit_lead, column) && column[4] > 0.0
                                   ? std::sqrt(column[4]) * scatter
                                   : HUGE_VAL;
    }
    if (!current.exact_count) {
        return {};
    }
    const double count = static_cast<double>(current.exact_count);
    return {std::sqrt(current.exact_sum / count), std::sqrt(current.normalised_sum / count), current.exact_count};
}

bool OrbitModel::initialise() {
    std::vector<const Target*> exact;
    for (const auto& t : targets_) {
        if (t.kind == Kind::exact) {
            exact.push_back(&t);
        }
    }
    if (exact.size() < 2) {
        return false;
    }
    const Target& first = *exact.front();
    const Target& last = *exact.back();
    const double dt = last.t - first.t;
    const Vec d1 = unit_vector(first.direction), d2 = unit_vector(last.direction);
    if (dt <= 0.0 || angle_deg(d1, d2) < 0.2) {
        return false;
    }
    const Earth earth = earth_at(settings_.latitude_deg);
    // Geocentric position (km) of the point at this altitude along a direction from the site.
    auto geocentric = [&](const Vec& d, double altitude) {
        const double r = earth.radius_km + altitude;
        const double b = earth.radius_km * d[2];
        const double range = -b + std::sqrt(b * b + r * r - earth.radius_km * earth.radius_km);
        Vec g = scaled(d, range);
        g[2] += earth.radius_km;
        return g;
    };
    // The arc between the two points, seen in the frame of the first (the Earth turned meanwhile),
    // minus what the Kepler rate covers in the time between them.
    auto mismatch = [&](double altitude) {
        const Vec g1 = geocentric(d1, altitude);
        Vec g2 = geocentric(d2, altitude);
        if (earth.spin != 0.0) {
            g2 = rotated(g2, earth.axis, earth.spin * dt);
        }
        return angle_deg(g1, g2) * deg - kepler_rate(earth.radius_km + altitude) * dt;
    };
    std::vector<double> roots;
    double previous_alt = settings_.min_altitude_km;
    double previous = mismatch(previous_alt);
    for (double alt = previous_alt + scan_step_km; alt <= settings_.max_altitude_km + 1e-9; alt += scan_step_km) {
        const double value = mismatch(alt);
        if ((value > 0.0) != (previous > 0.0)) {
            double lo = previous_alt, hi = alt, f_lo = previous;
            for (int i = 0; i < 40; ++i) {
                const double mid = 0.5 * (lo + hi);
                const double f_mid = mismatch(mid);
                if ((f_mid > 0.0) == (f_lo > 0.0)) {
                    lo = mid;
                    f_lo = f_mid;
                } else {
                    hi = mid;
                }
            }
            roots.push_back(0.5 * (lo + hi));
        }
        previous = value;
        previous_alt = alt;
    }
    if (roots.empty()) {
        description_ = "no circular orbit between 150 and 2000 km joins the targets";
        return false;
    }
    std::optional<Orbit> best;
    FitResidual best_fit{HUGE_VAL, HUGE_VAL};
    for (double altitude : roots) {
        const Vec g1 = geocentric(d1, altitude);
        Vec g2 = geocentric(d2, altitude);
        if (earth.spin != 0.0) {
            g2 = rotated(g2, earth.axis, earth.spin * dt);
        }
        const Vec p0 = unit(g1);
        const Vec w = unit(minus(unit(g2), scaled(p0, dot(unit(g2), p0))));
        const Vec east{1.0, 0.0, 0.0};
        const Vec e1 = unit(minus(east, scaled(p0, dot(east, p0))));
        const Vec e2 = cross(p0, e1);
        Orbit orbit;
        orbit.t_ref = first.t;
        orbit.x = p0[0] / p0[2];
        orbit.y = p0[1] / p0[2];
        orbit.heading = std::atan2(dot(w, e2), dot(w, e1));
        orbit.altitude_km = altitude;
        const FitResidual fit = refine(orbit, initial_iterations);
        if (fit.normalised < best_fit.normalised) {
            best_fit = fit;
            best = orbit;
        }
    }
    orbit_ = best;
    residual_ = best_fit;
    return true;
}

void OrbitModel::refit(bool from_scratch) {
    if (!orbit_ || from_scratch) {
        orbit_.reset();
        initialise();
    } else {
        Orbit warm = *orbit_;
        const FitResidual fit = refine(warm, warm_iterations);
        if (fit.normalised <= settings_.max_normalised_residual) {
            orbit_ = warm;
            residual_ = fit;
        } else {
            const Orbit kept = *orbit_;
            if (!initialise()) {
                orbit_ = kept;
                residual_ = fit;
            }
        }
    }
    question_lead();
    judge();
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
    char sigma[48];
    std::snprintf(sigma, sizeof sigma, "fitted, +-%.2f", orbit_->lead_sigma_deg);
    char overridden[96] = "";
    if (lead_from_targets()) {
        std::snprintf(overridden, sizeof overridden, "; the dish's gaps said %.2f", *lead_hint_deg_);
    }
    const std::string lead_source =
        lead_hint_deg_ && !lead_from_targets() ? std::string("learnt from the dish") : std::string(sigma) + overridden;
    char text[256];
    std::snprintf(text, sizeof text,
                  "orbit %.0f km, client lead %.2f deg (%s), %zu targets (%zu exact over %.1f deg, %.0f s), RMS %.3f deg (%.1f of the expected scatter)%s",
                  orbit_->altitude_km, client_view().threshold, lead_source.c_str(), targets_.size(), exact,
                  arc, span, residual_.rms_deg, residual_.normalised,
                  settings_.latitude_deg ? "" : ", Earth taken as still (no latitude)");
    description_ = text;
    const char* why = nullptr;
    if (exact < settings_.min_exact_targets) {
        why = "too few targets";
    } else if (arc < settings_.min_arc_deg || span < settings_.min_span_s) {
        why = "targets too close together";
    } else if (sharpest_turn_deg(exact_directions(), turn_min_step_deg) > settings_.max_turn_deg &&
               sharpest_turn_deg(exact_directions_along_track(), turn_min_step_deg) > settings_.max_turn_deg) {
        // In the order sent, a pass's targets can step back along it where a client's look-ahead
        // shrinks (Gpredict's azimuth box towards the zenith: iss-85 at 5 deg was never trusted);
        // in their order along the fitted track they turn as gently as the pass. A scan's
        // serpentine or a user's jogging turns in either order.
        why = "the targets turn as no pass does (manual pointing, a scan)";
    } else if (!lead_hint_deg_ &&
               (orbit_->lead_sigma_deg > settings_.max_lead_sigma_deg || exact < settings_.min_exact_targets_fitted_lead)) {
        why = "the client's lead not yet known";
    } else if (residual_.normalised > settings_.max_normalised_residual || residual_.rms_deg > settings_.max_residual_deg) {
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
