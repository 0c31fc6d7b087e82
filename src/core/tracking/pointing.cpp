// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "tracking/pointing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>
#include <vector>

#include "tracking/slope_fit.hpp"

namespace birdcage {
namespace {

constexpr double max_lead_s = 30.0;  // a learned lead longer than this is not a lead
constexpr double max_lead_threshold_deg = 10.0;
constexpr std::size_t lead_observations_kept = 8;
// An observation smaller than this fraction of the learned threshold is a "lead" event (the dish
// ran ahead), which says nothing about the client's threshold.
constexpr double lag_event_fraction = 0.5;
// Bounds on the fitted acceleration (the keyhole's azimuth needs ~1.6 deg/s² at 85°, docs/tracking.md §2.1).
constexpr double max_az_accel = 0.3;
constexpr double max_el_accel = 0.05;
// A target this soon after the previous one is Gpredict re-sending before it read the dish's new
// position (its I/O loop is ~0.8 s): its gap to the dish says nothing about the lead.
constexpr double resend_interval_s = 2.0;
// How far ahead a fitted curvature is trusted (a pass's azimuth acceleration changes sign at the
// culmination).
constexpr double accel_horizon_s = 5.0;
// A dish within this of its elevation floor or cap is held there (lead learning, above).
constexpr double lead_limit_margin_deg = 0.3;
// Weight of a new target's anchor against the running estimate (an alpha filter on position).
constexpr double anchor_gain = 0.5;
// Gpredict compares the satellite as its module last computed it (up to 0.3 s old) with the
// position last read back, on its timer tick, and its I/O loop sends the target up to 0.8 s later
// (docs/tracking.md §5): the satellite it compared lies within this long before the target arrives.
constexpr double client_compare_window_s = 1.1;
// Positions answered are kept this long (a few of Gpredict's 0.8 s I/O loops).
constexpr double reported_kept_s = 5.0;
// A target arriving while the trusted orbit's satellite lay within this share of the lead of every
// position the client may have compared it with, on both axes, was not sent by Gpredict's rule
// (the rest of the lead is the margin for the orbit's error).
constexpr double no_lead_share = 0.8;
// Such targets before the lead is taken for none.
constexpr int no_lead_targets = 3;

using slope_fit::Fit;
using slope_fit::mean_square_off;
using slope_fit::slope_at_end;

}  // namespace

std::optional<PointingMode> pointing_mode_from_name(std::string_view name) {
    if (name == "none") {
        return PointingMode::none;
    }
    if (name == "leapfrog") {
        return PointingMode::leapfrog;
    }
    if (name == "predictive") {
        return PointingMode::predictive;
    }
    return std::nullopt;
}

std::string_view pointing_mode_name(PointingMode mode) {
    switch (mode) {
        case PointingMode::none:
            return "none";
        case PointingMode::leapfrog:
            return "leapfrog";
        case PointingMode::predictive:
            return "predictive";
    }
    return "none";
}

TargetPredictor::TargetPredictor(PredictorSettings settings)
    : settings_(settings),
      orbit_(settings.orbit),
      dish_el_min_(settings.orbit.el_floor),
      dish_el_max_(settings.orbit.el_cap) {}

void TargetPredictor::set_dish_limits(double el_min, double el_max) {
    dish_el_min_ = el_min;
    dish_el_max_ = el_max;
    orbit_.set_dish_limits(el_min, el_max);
}

double TargetPredictor::seconds(Clock::time_point t) const {
    return std::chrono::duration<double>(t - origin_).count();
}

void TargetPredictor::reset() {
    // Everything, the learned lead too: after a stop or a homing the next client may be another
    // program with another threshold (or none).
    lead_threshold_.reset();
    lead_observations_.clear();
    reported_.clear();
    no_lead_evidence_ = 0;
    half_step_.reset();
    half_steps_.clear();
    held_ = false;
    samples_.clear();
    have_rate_ = false;
    az_rate_ = el_rate_ = 0.0;
    last_interval_s_ = 0.0;
    track_targets_ = 0;
    orbit_.clear();
}

void TargetPredictor::restart(double t, AzEl target, bool keep_orbit) {
    samples_.clear();
    samples_.push_back({t, normalize_azimuth(target.az), target.el});
    have_rate_ = false;
    az_rate_ = el_rate_ = 0.0;
    anchor_t_ = t;
    anchor_az_ = samples_.back().az;
    anchor_el_ = target.el;
    last_interval_s_ = 0.0;
    track_targets_ = 1;
    track_start_t_ = t;
    // A new pointing, unless the orbit expected it: an orbit of the old one would pull the
    // prediction back to it.
    if (!keep_orbit) {
        orbit_.clear();
        orbit_.add(t, target, lead_threshold_);
    }
}

std::vector<AzEl> TargetPredictor::sample_directions() const {
    std::vector<AzEl> directions;
    directions.reserve(samples_.size());
    for (const Sample& s : samples_) {
        directions.push_back({s.az, s.el});
    }
    return directions;
}

void TargetPredictor::fit() {
    // Keep at least fit_window of history: two targets sent a cycle apart (Gpredict re-sends
    // before the dish has moved) carry mostly the lead's quantisation, not the rate.
    while (samples_.size() > 2 && samples_.back().t - samples_[1].t >= settings_.fit_window_s) {
        samples_.pop_front();
    }
    const Fit az = slope_at_end(
        samples_, [](const Sample& s) { return s.az; }, max_az_accel);
    const Fit el = slope_at_end(
        samples_, [](const Sample& s) { return s.el; }, max_el_accel);
    have_rate_ = az.ok && el.ok && std::hypot(az.rate, el.rate) >= settings_.stationary_dps;
    if (have_rate_) {
        // Manual pointing moves by steps at whatever pace the user or program likes, and a few
        // steps fit any straight line: only enough targets, on a smooth track, at a satellite's
        // pace are extrapolated (docs/tracking.md §7).
        const double cos_el = std::cos(samples_.back().el * M_PI / 180.0);
        const double sky_rate = std::hypot(az.rate * cos_el, el.rate);
        const double residual = std::sqrt(mean_square_off(
                                              samples_, [](const Sample& s) { return s.az; }, az, cos_el) +
                                          mean_square_off(
                                              samples_, [](const Sample& s) { return s.el; }, el, 1.0));
        have_rate_ =
            track_targets_ >= settings_.min_track_targets && sky_rate <= settings_.max_satellite_sky_rate_dps &&
            residual <= settings_.max_track_residual_deg &&
            sharpest_turn_deg(sample_directions(), settings_.min_turn_step_deg) <= settings_.max_track_turn_deg;
    }
    az_rate_ = have_rate_ ? az.rate : 0.0;
    el_rate_ = have_rate_ ? el.rate : 0.0;
    az_accel_ = have_rate_ ? az.accel : 0.0;
    el_accel_ = have_rate_ ? el.accel : 0.0;
}

void TargetPredictor::observe(Clock::time_point when, AzEl target, std::optional<AzEl> dish) {
    if (!std::isfinite(target.az) || !std::isfinite(target.el)) {
        return;
    }
    if (!has_origin_) {
        origin_ = when;
        has_origin_ = true;
    }
    const double t = seconds(when);
    question_lead_by_send_rule(t);
    // The orbit sees every target first: whether it expected this one decides what a restart of
    // the local estimate below forgets.
    const bool orbit_trusted = settings_.use_pass_model && orbit_.trusted();
    const bool orbit_expected = settings_.use_pass_model && orbit_.add(t, target, lead_threshold_);
    // A restart of the local estimate (a north crossing's jump in azimuth, a target it did not
    // expect) forgets the orbit only when a trusted orbit did not expect the target either: an orbit
    // still gathering targets sorts out on its own what is not one pass (OrbitModel::judge()).
    const bool keep_orbit = !(orbit_trusted && !orbit_expected);
    if (samples_.empty()) {
        restart(t, target, true);
        return;
    }
    const Sample last = samples_.back();
    const double az = last.az + azimuth_difference(last.az, target.az);
    const bool repeated =
        std::fabs(az - last.az) < same_angle_degrees && std::fabs(target.el - last.el) < same_angle_degrees;
    // A target after a held one cannot give a rate: the client only now started moving.
    if (repeated || t - last.t > settings_.max_gap_s || t <= last.t || held_) {
        held_ = repeated;
        restart(t, target, keep_orbit);
        return;
    }
    // Faster than any satellite on the sky, or a jump as large as the restart gate: the client
    // re-pointed the dish (a manual P, park, another satellite), it is not tracking one.
    const double sky_step =
        std::hypot(azimuth_difference(last.az, target.az) * std::cos(target.el * M_PI / 180.0), target.el - last.el);
    if (!have_rate_ &&
        (sky_step > settings_.restart_gate_deg || sky_step / (t - last.t) > settings_.max_sky_rate_dps)) {
        restart(t, target, keep_orbit);
        return;
    }
    if (have_rate_) {
        // Where the client's next target was expected (the satellite plus the learned lead).
        const auto expected = estimate(when, false);
        const double lead_s =
            lead_threshold_
                ? std::min(*lead_threshold_ / std::max(std::fabs(az_rate_), std::fabs(el_rate_)), max_lead_s)
                : 0.0;
        const double expected_az = expected->position.az + az_rate_ * lead_s;
        const double expected_el = expected->position.el + el_rate_ * lead_s;
        const double innovation =
            std::max(std::fabs(azimuth_difference(expected_az, target.az)), std::fabs(target.el - expected_el));
        // A trusted orbit that expected the target vouches for it: the local estimate is what erred.
        if (innovation > settings_.restart_gate_deg && !(orbit_trusted && orbit_expected)) {
            restart(t, target, keep_orbit);
            return;
        }
    }
    held_ = false;
    const std::optional<Prediction> before = have_rate_ ? estimate(when, false) : std::nullopt;
    samples_.push_back({t, az, target.el});
    ++track_targets_;
    if (t - last.t > resend_interval_s) {
        last_interval_s_ = t - last.t;
        // The client's step on its faster axis (plain differences, as a threshold compares them).
        const double half_step = 0.5 * std::max(std::fabs(az - last.az), std::fabs(target.el - last.el));
        if (half_step <= max_lead_threshold_deg) {
            half_steps_.push_back(half_step);
            if (half_steps_.size() > lead_observations_kept) {
                half_steps_.pop_front();
            }
            std::vector<double> sorted(half_steps_.begin(), half_steps_.end());
            std::sort(sorted.begin(), sorted.end());
            half_step_ = sorted[(sorted.size() - 1) / 2];
        }
    }
    fit();
    if (!have_rate_) {
        anchor_t_ = t;
        anchor_az_ = az;
        anchor_el_ = target.el;
        return;
    }
    const double dominant_rate = std::max(std::fabs(az_rate_), std::fabs(el_rate_));
    // A dish held on its elevation floor or cap trails the satellite by whatever lies beyond the
    // limit, not by the client's lead.
    auto on_limit = [this](double el) {
        return el <= dish_el_min_ + lead_limit_margin_deg || el >= dish_el_max_ - lead_limit_margin_deg;
    };
    const bool dish_on_limit = dish && on_limit(dish->el);
    if (dish && !(dish_on_limit && on_limit(target.el)) && t - last.t > resend_interval_s) {
        // Along-track gap between this target and the dish the client compared it with.
        const double gap_az = azimuth_difference(dish->az, target.az);
        const double gap_el = target.el - dish->el;
        const double rate_sq = az_rate_ * az_rate_ + el_rate_ * el_rate_;
        double lead_obs_s = (gap_az * az_rate_ + gap_el * el_rate_) / (2.0 * rate_sq);
        double threshold_obs = lead_obs_s * dominant_rate;
        if (dish_on_limit) {
            // The dish held on its floor or cap while the satellite is inside its range (a client
            // set up wider than the dish) is off the track, so the gap is not along it. Gpredict's
            // rule still holds against the position it was given: it sent this target once the
            // satellite lay more than its threshold L from that position on either axis, and the
            // target is where the satellite will be once it has moved L on its faster axis, L / |v|inf
            // later. On an axis moving away from the dish the gap is then L + |v_axis| L / |v|inf,
            // and the axis that crossed first is the one that gives the largest L.
            threshold_obs = 0.0;
            for (const auto& [gap, rate] : {std::pair{gap_az, az_rate_}, std::pair{gap_el, el_rate_}}) {
                if (gap * rate > 0.0) {
                    threshold_obs = std::max(threshold_obs, std::fabs(gap) / (1.0 + std::fabs(rate) / dominant_rate));
                }
            }
            lead_obs_s = threshold_obs / dominant_rate;
        }
        // A gap wider than two of the largest plausible leads is the dish still slewing (a
        // pre-pass unwind, an acquisition), not a threshold crossing.
        const bool plausible = std::max(std::fabs(gap_az), std::fabs(gap_el)) <= 2.0 * max_lead_threshold_deg &&
                               threshold_obs <= max_lead_threshold_deg;
        if (plausible && lead_obs_s > 0.0 &&
            (!lead_threshold_ || threshold_obs >= lag_event_fraction * *lead_threshold_)) {
            // Low recent observations: a dish that trails for any other reason makes the gap
            // larger than twice the lead, never smaller, and a lead learned too large would keep
            // the dish trailing (the client then re-sends every cycle).
            lead_observations_.push_back(threshold_obs);
            if (lead_observations_.size() > lead_observations_kept) {
                lead_observations_.pop_front();
            }
            // A low quantile rather than the minimum: the minimum of noisy observations is
            // biased low, which would aim the dish ahead of the satellite.
            std::vector<double> sorted(lead_observations_.begin(), lead_observations_.end());
            std::sort(sorted.begin(), sorted.end());
            lead_threshold_ = sorted[(sorted.size() - 1) / 2];
        }
    }
    // Back along the fitted parabola by the lead: the target is where the satellite will be once
    // it has moved `threshold` on its faster axis, so tau solves |v tau - a tau^2 / 2|inf = threshold
    // (v, a at the target's time).
    double lead_s = 0.0;
    if (lead_threshold_) {
        lead_s = std::min(*lead_threshold_ / dominant_rate, max_lead_s);
        for (int refine = 0; refine < 3; ++refine) {
            const double moved = std::max(std::fabs(az_rate_ - 0.5 * az_accel_ * lead_s),
                                          std::fabs(el_rate_ - 0.5 * el_accel_ * lead_s));
            lead_s = moved > settings_.stationary_dps ? std::min(*lead_threshold_ / moved, max_lead_s) : lead_s;
        }
    }
    double new_az = az - az_rate_ * lead_s + 0.5 * az_accel_ * lead_s * lead_s;
    double new_el = target.el - el_rate_ * lead_s + 0.5 * el_accel_ * lead_s * lead_s;
    if (before && lead_threshold_) {
        // Gpredict's lead is quantised (a quarter cycle), so each anchor is noisy by ~0.25 s of
        // motion: blend it with where the previous estimate put the satellite now, unless the
        // two disagree by more than the lead itself (then the new target wins).
        const double prior_az = before->position.az;
        const double prior_el = before->position.el;
        const double d_az = azimuth_difference(prior_az, normalize_azimuth(new_az));
        const double d_el = new_el - prior_el;
        if (std::max(std::fabs(d_az), std::fabs(d_el)) < *lead_threshold_) {
            new_az = az + azimuth_difference(normalize_azimuth(az), normalize_azimuth(prior_az + anchor_gain * d_az));
            new_el = prior_el + anchor_gain * d_el;
        }
    }
    anchor_t_ = t;
    anchor_az_ = new_az;
    anchor_el_ = new_el;
    // The rates at the anchor's time, not the target's.
    az_rate_ -= az_accel_ * lead_s;
    el_rate_ -= el_accel_ * lead_s;
    // The orbit saw this target with the lead learnt before it: with two unclamped targets and a
    // clamped one the lead this target's gap teaches may already decide whether it is followed.
    if (settings_.use_pass_model) {
        orbit_.relead(lead_threshold_);
    }
}

void TargetPredictor::note_reported(Clock::time_point when, AzEl position) {
    if (!has_origin_ || !std::isfinite(position.az) || !std::isfinite(position.el)) {
        return;
    }
    const double t = seconds(when);
    if (!reported_.empty() && t < reported_.back().t) {
        return;
    }
    reported_.push_back({t, position});
    while (reported_.size() > 1 && t - reported_[1].t > reported_kept_s) {
        reported_.pop_front();
    }
}

void TargetPredictor::question_lead_by_send_rule(double t) {
    // A client that leads by L and one without look-ahead that sends the satellite each time it
    // moved 2L leave the same gap, and under 1 deg the targets cannot tell such a lead from none
    // (docs/benchmarks.md). Gpredict's send rule can: it sends only once the satellite is more than
    // its threshold (its lead) off the position last read back on either axis, while a client
    // without look-ahead sends whatever the dish did. The position Gpredict compared with is the
    // last one answered before its timer tick, which fell up to client_compare_window_s before the
    // target arrived: every position that may have been it must show the satellite well within
    // the lead, on both axes, all through that window.
    if (!pass_model_in_use()) {
        return;
    }
    const std::optional<double> lead = orbit_.lead_deg();
    if (!lead || *lead <= same_angle_degrees) {
        return;
    }
    const double earliest_tick = t - client_compare_window_s;
    auto first =
        std::find_if(reported_.rbegin(), reported_.rend(), [&](const Reported& r) { return r.t <= earliest_tick; });
    if (first == reported_.rend()) {
        return;  // what the client compared with is unknown
    }
    // A fitted lead off by its standard error moves the fitted satellite along the track by
    // about twice that (the look-ahead search moves with it).
    const double within = no_lead_share * *lead - 2.0 * orbit_.lead_sigma_deg();
    for (const double compared_at : {earliest_tick, 0.5 * (earliest_tick + t), t}) {
        const auto satellite = orbit_.predict(compared_at);
        if (!satellite || satellite->position.el <= 0.0) {
            return;
        }
        for (auto r = first.base() - 1; r != reported_.end() && r->t < t; ++r) {
            // Gpredict's plain difference of azimuths in 0..360 (across north it sends whatever the
            // satellite's distance), and the satellite unclamped: a client clamping it to limits the
            // position lies within only comes closer to it.
            if (std::fabs(normalize_azimuth(satellite->position.az) - normalize_azimuth(r->position.az)) > within ||
                std::fabs(satellite->position.el - r->position.el) > within) {
                return;
            }
        }
    }
    if (++no_lead_evidence_ < no_lead_targets) {
        return;
    }
    // The gaps stay the client's coarseness (client_coarseness_deg()); the orbit holds no lead.
    orbit_.take_lead_as_none();
}

std::optional<Prediction> TargetPredictor::predict(Clock::time_point when) const {
    return estimate(when, true);
}

std::optional<wrap::PassAhead> TargetPredictor::pass_ahead(Clock::time_point when) const {
    if (!pass_model_in_use()) {
        return std::nullopt;
    }
    // Longer than any LEO pass above a dish's floor, plus a wait for its rise.
    constexpr double look_ahead_s = 1800.0;
    const double t = seconds(when);
    const auto span = orbit_.pass_above(t, dish_el_min_, look_ahead_s);
    if (!span) {
        return std::nullopt;
    }
    return wrap::PassAhead{span->start_az, span->sweep_deg, span->start_t - t, span->top_t - t};
}

std::optional<Prediction> TargetPredictor::estimate(Clock::time_point when, bool hold_at_last_target) const {
    if (samples_.empty()) {
        return std::nullopt;
    }
    Prediction out;
    if (pass_model_in_use()) {
        // The orbit is followed to the end of the pass with no horizon: when the dish tracks well
        // the client sends nothing, and the orbit needs no targets to stay right. Through the
        // zenith too: there it is an ordinary point of the circle.
        const auto point = orbit_.predict(seconds(when));
        out.position = point->position;
        out.moving = point->position.el >= 0.0;
        out.az_rate = out.moving ? point->az_rate : 0.0;
        out.el_rate = out.moving ? point->el_rate : 0.0;
        return out;
    }
    out.position = {normalize_azimuth(anchor_az_), anchor_el_};
    if (!have_rate_) {
        return out;
    }
    const double dt = std::max(0.0, seconds(when) - anchor_t_);
    const double horizon = std::clamp(settings_.extrapolate_intervals * last_interval_s_, settings_.min_extrapolation_s,
                                      settings_.max_extrapolation_s);
    // On a young track the estimate stops at the client's last target, once it gets there (the
    // anchor trails the target by the client's lead). An established track is followed to the
    // horizon and held where the extrapolation ended: a tracking client that is satisfied with
    // the dish sends nothing, so a quiet client is no sign of one that stopped, and returning to
    // its last target would put the dish the whole horizon behind the satellite
    // (docs/tracking.md §7).
    const Sample& last = samples_.back();
    const Prediction at_last_target{{normalize_azimuth(last.az), last.el}, 0.0, 0.0, false};
    const bool young =
        track_targets_ < settings_.established_track_targets || last.t - track_start_t_ < settings_.established_track_s;
    if (hold_at_last_target && young) {
        // Along the track on the sky (cos(el) scales the azimuth), the time the estimate takes
        // from the anchor to the last target.
        const double cos_sq = std::pow(std::cos(anchor_el_ * M_PI / 180.0), 2);
        const double rate_sq = az_rate_ * az_rate_ * cos_sq + el_rate_ * el_rate_;
        const double to_target_s =
            rate_sq > 0.0 ? ((last.az - anchor_az_) * az_rate_ * cos_sq + (last.el - anchor_el_) * el_rate_) / rate_sq
                          : 0.0;
        if (dt >= to_target_s) {
            return at_last_target;
        }
    }
    // Curvature is trusted for accel_horizon_s only, then the motion continues straight.
    auto travel = [&](double rate, double accel, double dt_axis) {
        const double curved = std::min(dt_axis, accel_horizon_s);
        return rate * dt_axis + accel * curved * (0.5 * curved + (dt_axis - curved));
    };
    auto rate_at = [&](double rate, double accel, double dt_axis) {
        return rate + accel * std::min(dt_axis, accel_horizon_s);
    };
    const double dt_el = std::min(dt, horizon);
    const double el = anchor_el_ + travel(el_rate_, el_accel_, dt_el);
    const double az_horizon = std::max(anchor_el_, el) > settings_.zenith_guard_el
                                  ? std::min(horizon, settings_.zenith_extrapolation_s)
                                  : horizon;
    const double dt_az = std::min(dt, az_horizon);
    out.position = {normalize_azimuth(anchor_az_ + travel(az_rate_, az_accel_, dt_az)), el};
    out.az_rate = dt < az_horizon ? rate_at(az_rate_, az_accel_, dt_az) : 0.0;
    out.el_rate = dt < horizon ? rate_at(el_rate_, el_accel_, dt_el) : 0.0;
    out.moving = dt < horizon;
    return out;
}

std::string TargetPredictor::describe() const {
    if (samples_.empty()) {
        return "no target yet";
    }
    if (pass_model_in_use()) {
        return "following the " + orbit_.describe();
    }
    if (!have_rate_) {
        return "holding the last target";
    }
    char text[160];
    char lead[32] = "unknown";
    if (lead_threshold_) {
        std::snprintf(lead, sizeof lead, "%.2f deg", *lead_threshold_);
    }
    std::snprintf(text, sizeof text, "az rate %.3f deg/s, el rate %.3f deg/s, client lead %s", az_rate_, el_rate_,
                  lead);
    if (settings_.use_pass_model && orbit_.targets() >= 2) {
        return std::string(text) + "; " + orbit_.describe();
    }
    return text;
}

}  // namespace birdcage
