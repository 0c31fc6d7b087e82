// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The orbit model's fit: the two-point circular solution, Levenberg–Marquardt on every target held,
// and the client's lead questioned against the targets (orbit_model.hpp describes the model).
#include "tracking/orbit_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

namespace birdcage {
using namespace orbit_geometry;
namespace {

// Weight of a clamped target's one residual against an exact target's direction.
constexpr double clamped_weight = 0.5;
// The two-point solution's scan of altitudes (km) before bisection.
constexpr double scan_step_km = 10.0;
// Levenberg–Marquardt.
constexpr int initial_iterations = 40;
constexpr int warm_iterations = 10;
constexpr double relative_convergence = 1e-4;
// The scatter of a target about the orbit, at least (degrees): a client's tick and I/O loop put up to
// 0.8 s between computing a target and sending it, and Gpredict's search stops within a quarter cycle.
constexpr double target_scatter_deg = 0.1;
constexpr double send_jitter_sd_s = 0.25;
// The largest client lead the fit considers (degrees): Gpredict's threshold setting goes to 10.
constexpr double max_fitted_lead_deg = 10.0;
// Penalty (degrees) for a before-rise target when the model's track never rises in the search.
constexpr double no_rise_penalty_deg = 10.0;
// The learnt lead is questioned from this many exact targets on, and replaced by the fitted one
// where that misses the targets by less than this share of what the learnt one does (the targets'
// scatter is not all timing: Gpredict's quantised search leaves a systematic part, which a free
// lead would fit as readily as a real difference).
constexpr std::size_t lead_question_min_targets = 4, lead_question_every_target_below = 30;
// No lead at all is put to the targets from three exact ones on: the two leave a fit of three
// targets apart already (a client without look-ahead, learnt as leading by 2.6 deg from the dish's
// gaps, on the held-out pass: 2.0 times the expected scatter with that lead, 0.3 with none). Only
// a hint of at least this (degrees) is questioned: a finer lead is within the few targets' scatter,
// and Gpredict's own 0.5 deg was taken for none on the held-out pass (0.49 deg RMS against 0.29).
constexpr std::size_t lead_none_question_min_targets = 3;
constexpr double lead_none_min_hint_deg = 1.0;
constexpr double lead_question_gain = 0.8;

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

struct Residuals {
    std::vector<double> values;
    std::vector<char> smooth;  // per value: from an unclamped target (the lead moves it smoothly)
    double exact_sum = 0.0;
    double normalised_sum = 0.0;  // each exact target's miss over the scatter expected of it
    std::size_t exact_count = 0;
    double check_sum = 0.0;  // the same for each clamped target above the horizon
    std::size_t check_count = 0;
};

// kind: 0 exact, 1 clamped, 2 before rise (OrbitModel::Kind).
// `search_offsets`: per target, where the client's search stopped against its box's boundary
// (Evaluator::look_ahead); empty: found now and stored there.
template <typename Targets>
Residuals residuals_of(const Orbit& orbit, const Earth& earth, const Targets& targets,
                       const OrbitModel::ClientView& client, std::vector<double>& search_offsets,
                       double clamped_threshold) {
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
        const double angle = angle_deg(there, seen);
        // Sent up to 0.8 s after it was computed (uniform: 0.23 s standard deviation) and cut
        // at a quarter cycle: the faster the satellite, the more a target scatters.
        const double sky_rate = angle_deg(model.direction(target.t), model.direction(target.t + 1.0));
        const double scatter = std::hypot(target_scatter_deg, send_jitter_sd_s * sky_rate);
        if (target.kind == 0) {
            out.exact_sum += angle * angle;
            out.normalised_sum += angle * angle / (scatter * scatter);
            ++out.exact_count;
        } else {
            out.check_sum += angle * angle / (scatter * scatter);
            ++out.check_count;
        }
    }
    return out;
}

}  // namespace

OrbitModel::FitResidual OrbitModel::refine(Orbit& orbit, int iterations) const {
    // The lead the caller learnt from the dish (the gap between a target and the dish it passed)
    // is held; fitted with the orbit, the lead wanders with the targets' timing scatter by more
    // than that learning errs. Without one the targets are all there is (and see question_lead()).
    return refine(orbit, iterations, lead_in_fit());
}

std::optional<double> OrbitModel::lead_in_fit() const {
    if (no_look_ahead_ || (lead_none_despite_hint_ && lead_hint_deg_)) {
        return 0.0;
    }
    return lead_fitted_despite_hint_ ? std::nullopt : lead_hint_deg_;
}

// The dish's gaps cannot tell a client that leads by L from one that sends the satellite as it is
// each time it moved 2L (both leave a gap of 2L): from the gaps alone a client without look-ahead
// is learnt as leading by half its threshold, and the dish follows that far ahead of the satellite
// (2.5 deg at 5 deg, tests/core/test_orbit_model.cpp). The targets can tell: a lead is a time that changes with the satellite's rate,
// which no phase absorbs. So at each new target (from 4 exact ones on; past 30, each time they grew
// by a tenth) both are fitted, and the fitted lead is taken where it fits the targets clearly better.
// Before that, and first, the two readings of the gaps are put to the targets as they are: the
// hinted lead against none. The fitted lead needs many targets to be known to 0.3 deg (the
// held-out pass: 14, at its culmination), while the dish trailed the satellite by the wrong lead.
// None is taken only where the hinted lead misses the targets by more than their expected scatter
// (a track whose rate hardly changes cannot tell a lead from a phase, and keeps the hint), and only
// until the fitted lead can be questioned instead (then a zenith pass's few poorly fitted targets
// would take none for Gpredict's own lead); either reading stays until the other fits clearly
// better (no flapping between them).
void OrbitModel::question_lead() {
    if (!orbit_ || !lead_hint_deg_ || no_look_ahead_) {
        lead_fitted_despite_hint_ = false;
        lead_none_despite_hint_ = false;
        return;
    }
    const std::size_t exact = residual_.exact_count;
    // Two exact targets fit any lead exactly: only a clamped target can tell the two readings apart.
    const bool checked_pair = exact >= settings_.min_exact_targets_checked && residual_.check_count > 0;
    if ((exact < lead_none_question_min_targets && !checked_pair) ||
        (exact >= lead_question_every_target_below && exact < next_lead_question_)) {
        return;
    }
    // With many targets one more changes little: a client that sends every cycle (wide limits)
    // would otherwise double the cost of each of hundreds of refits.
    next_lead_question_ = exact + exact / 10;
    Orbit held = *orbit_, fitted = *orbit_;
    const FitResidual with_hint = refine(held, warm_iterations, lead_hint_deg_);
    if (*lead_hint_deg_ >= lead_none_min_hint_deg) {
        Orbit none = *orbit_;
        const FitResidual without = refine(none, warm_iterations, 0.0);
        // Below three exact targets they fit either lead exactly: the clamped ones decide.
        const bool few = exact < lead_none_question_min_targets;
        const double hint_miss = few ? with_hint.overall() : with_hint.normalised;
        const double none_miss = few ? without.overall() : without.normalised;
        lead_none_despite_hint_ = lead_none_despite_hint_
                                      ? !(hint_miss < lead_question_gain * none_miss)
                                      : exact < settings_.min_exact_targets_fitted_lead && hint_miss > 1.0 &&
                                            none_miss < lead_question_gain * hint_miss;
        if (lead_none_despite_hint_) {
            lead_fitted_despite_hint_ = false;
            orbit_ = none;
            residual_ = without;
            return;
        }
    } else {
        lead_none_despite_hint_ = false;
    }
    if (exact < lead_question_min_targets) {
        orbit_ = held;
        residual_ = with_hint;
        return;
    }
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
    auto client_for = [&](const Orbit& o) { return ClientView{o.lead_deg, client_min_el_, client_max_el_}; };
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
                // Converged: a step that gains a ten-thousandth of the cost moves the orbit by
                // nothing a dish sees. Each new target starts from the last fit, and once that holds
                // many targets it is there after a step or two: the rest of the iterations were most
                // of the backend's CPU (docs/tracking.md §6, "Fitting").
                if (gain < relative_convergence * std::max(cost, 1e-12)) {
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
        orbit.lead_sigma_deg =
            solve(last_jtj, unit_lead, column) && column[4] > 0.0 ? std::sqrt(column[4]) * scatter : HUGE_VAL;
    }
    if (!current.exact_count) {
        return {};
    }
    const double count = static_cast<double>(current.exact_count);
    const double checks = static_cast<double>(current.check_count);
    return {std::sqrt(current.exact_sum / count), std::sqrt(current.normalised_sum / count), current.exact_count,
            current.check_count ? std::sqrt(current.check_sum / checks) : 0.0, current.check_count};
}

double OrbitModel::FitResidual::overall() const {
    const double exact = static_cast<double>(exact_count), checks = static_cast<double>(check_count);
    return exact + checks > 0.0
               ? std::sqrt((normalised * normalised * exact + check_normalised * check_normalised * checks) /
                           (exact + checks))
               : 0.0;
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

void OrbitModel::take_lead_as_none() {
    if (no_look_ahead_) {
        return;
    }
    no_look_ahead_ = true;
    if (orbit_) {
        refit(false);
    }
}

void OrbitModel::relead(std::optional<double> lead_hint_deg) {
    if (lead_hint_deg == lead_hint_deg_) {
        return;
    }
    lead_hint_deg_ = lead_hint_deg;
    if (orbit_ && !trusted_) {
        refit(false);
    }
}

}  // namespace birdcage
