#include "birdcage/pointing.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace birdcage {
namespace {

constexpr double same_target_degrees = 0.005;  // targets arrive with two decimals
constexpr double max_lead_s = 30.0;            // a learned lead longer than this is not a lead
constexpr double max_lead_threshold_deg = 20.0;
constexpr double lead_learning_rate = 0.3;     // weight of a new lag observation
// An observation smaller than this fraction of the learned threshold is a "lead" event (the dish
// ran ahead), which says nothing about the client's threshold.
constexpr double lag_event_fraction = 0.5;
// Quadratic fits need this many samples over this span; below, a straight line.
constexpr std::size_t quadratic_min_samples = 4;
constexpr double quadratic_min_span_s = 3.0;
// Bounds on the fitted acceleration (the keyhole's azimuth needs ~1.6 deg/s² at 85°, tracking.md §2.1).
constexpr double max_az_accel = 2.0;
constexpr double max_el_accel = 0.2;

struct Fit {
    double rate = 0.0;   // slope at the newest sample
    bool ok = false;
};

// Least squares of value(t), evaluated as a slope at t_end: quadratic when the samples allow it
// (a straight line's slope belongs to the window's centroid, seconds behind the newest target,
// while the azimuth rate of a pass keeps changing), straight line otherwise.
template <typename Samples, typename Get>
Fit slope_at_end(const Samples& samples, Get value, double accel_bound) {
    const std::size_t n = samples.size();
    if (n < 2) {
        return {};
    }
    const double t_end = samples.back().t;
    double span = t_end - samples.front().t;
    if (span <= 0.0) {
        return {};
    }
    // Centre on the newest sample so the slope at t_end is the linear coefficient.
    std::array<double, 5> st{};  // sums of t^0..t^4
    std::array<double, 3> sy{};  // sums of y*t^0..t^2
    for (const auto& s : samples) {
        const double t = s.t - t_end;
        const double y = value(s);
        double power = 1.0;
        for (int k = 0; k < 5; ++k) {
            st[k] += power;
            if (k < 3) {
                sy[k] += y * power;
            }
            power *= t;
        }
    }
    const double linear_det = st[0] * st[2] - st[1] * st[1];
    if (std::fabs(linear_det) < 1e-12) {
        return {};
    }
    double rate = (st[0] * sy[1] - st[1] * sy[0]) / linear_det;
    if (n >= quadratic_min_samples && span >= quadratic_min_span_s) {
        // Normal equations for y = a + b t + c t^2 (Cramer's rule).
        const double m[3][3] = {{st[0], st[1], st[2]}, {st[1], st[2], st[3]}, {st[2], st[3], st[4]}};
        auto det3 = [](const double a[3][3]) {
            return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                   a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        };
        const double det = det3(m);
        if (std::fabs(det) > 1e-9) {
            double mb[3][3] = {{st[0], sy[0], st[2]}, {st[1], sy[1], st[3]}, {st[2], sy[2], st[4]}};
            double mc[3][3] = {{st[0], st[1], sy[0]}, {st[1], st[2], sy[1]}, {st[2], st[3], sy[2]}};
            const double b = det3(mb) / det;
            const double c = det3(mc) / det;
            if (std::fabs(2.0 * c) <= accel_bound) {
                rate = b;
            }
        }
    }
    return {rate, true};
}

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

TargetPredictor::TargetPredictor(PredictorSettings settings) : settings_(settings) {}

double TargetPredictor::seconds(Clock::time_point t) const {
    return std::chrono::duration<double>(t - origin_).count();
}

void TargetPredictor::reset() {
    samples_.clear();
    have_rate_ = false;
    az_rate_ = el_rate_ = 0.0;
    last_interval_s_ = 0.0;
}

void TargetPredictor::restart(double t, AzEl target) {
    samples_.clear();
    samples_.push_back({t, normalize_azimuth(target.az), target.el});
    have_rate_ = false;
    az_rate_ = el_rate_ = 0.0;
    anchor_t_ = t;
    anchor_az_ = samples_.back().az;
    anchor_el_ = target.el;
    last_interval_s_ = 0.0;
}

void TargetPredictor::fit() {
    while (samples_.size() > 2 && samples_.back().t - samples_.front().t > settings_.fit_window_s) {
        samples_.pop_front();
    }
    const Fit az = slope_at_end(samples_, [](const Sample& s) { return s.az; }, max_az_accel);
    const Fit el = slope_at_end(samples_, [](const Sample& s) { return s.el; }, max_el_accel);
    have_rate_ = az.ok && el.ok && std::hypot(az.rate, el.rate) >= settings_.stationary_dps;
    az_rate_ = have_rate_ ? az.rate : 0.0;
    el_rate_ = have_rate_ ? el.rate : 0.0;
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
    if (samples_.empty()) {
        restart(t, target);
        return;
    }
    const Sample last = samples_.back();
    const double az = last.az + azimuth_difference(last.az, target.az);
    const bool repeated = std::fabs(az - last.az) < same_target_degrees && std::fabs(target.el - last.el) < same_target_degrees;
    // A target after a stationary one cannot give a rate: the client only now started moving.
    const bool after_stationary = samples_.size() == 1 && !have_rate_ && t - last.t > settings_.fit_window_s;
    if (repeated || t - last.t > settings_.max_gap_s || t <= last.t || after_stationary) {
        restart(t, target);
        return;
    }
    if (have_rate_) {
        // Where the client's next target was expected (the satellite plus the learned lead).
        const auto expected = predict(when);
        const double lead_s = lead_threshold_ ? std::min(*lead_threshold_ / std::max(std::fabs(az_rate_), std::fabs(el_rate_)), max_lead_s) : 0.0;
        const double expected_az = expected->position.az + az_rate_ * lead_s;
        const double expected_el = expected->position.el + el_rate_ * lead_s;
        const double innovation = std::max(std::fabs(azimuth_difference(expected_az, target.az)), std::fabs(target.el - expected_el));
        if (innovation > settings_.restart_gate_deg) {
            restart(t, target);
            return;
        }
    }
    samples_.push_back({t, az, target.el});
    last_interval_s_ = t - last.t;
    fit();
    if (!have_rate_) {
        anchor_t_ = t;
        anchor_az_ = az;
        anchor_el_ = target.el;
        return;
    }
    const double dominant_rate = std::max(std::fabs(az_rate_), std::fabs(el_rate_));
    if (dish) {
        // Along-track gap between this target and the dish the client compared it with.
        const double gap_az = azimuth_difference(dish->az, target.az);
        const double gap_el = target.el - dish->el;
        const double rate_sq = az_rate_ * az_rate_ + el_rate_ * el_rate_;
        const double lead_obs_s = (gap_az * az_rate_ + gap_el * el_rate_) / (2.0 * rate_sq);
        const double threshold_obs = std::min(lead_obs_s * dominant_rate, max_lead_threshold_deg);
        if (lead_obs_s > 0.0 && (!lead_threshold_ || threshold_obs >= lag_event_fraction * *lead_threshold_)) {
            lead_threshold_ = lead_threshold_ ? (1.0 - lead_learning_rate) * *lead_threshold_ + lead_learning_rate * threshold_obs
                                              : threshold_obs;
        }
    }
    const double lead_s = lead_threshold_ ? std::min(*lead_threshold_ / dominant_rate, max_lead_s) : 0.0;
    anchor_t_ = t;
    anchor_az_ = az - az_rate_ * lead_s;
    anchor_el_ = target.el - el_rate_ * lead_s;
}

std::optional<Prediction> TargetPredictor::predict(Clock::time_point when) const {
    if (samples_.empty()) {
        return std::nullopt;
    }
    Prediction out;
    out.position = {normalize_azimuth(anchor_az_), anchor_el_};
    if (!have_rate_) {
        return out;
    }
    const double dt = std::max(0.0, seconds(when) - anchor_t_);
    const double horizon = std::clamp(settings_.extrapolate_intervals * last_interval_s_, settings_.min_extrapolation_s,
                                      settings_.max_extrapolation_s);
    const double dt_el = std::min(dt, horizon);
    const double el = anchor_el_ + el_rate_ * dt_el;
    const double az_horizon = std::max(anchor_el_, el) > settings_.zenith_guard_el
                                  ? std::min(horizon, settings_.zenith_extrapolation_s)
                                  : horizon;
    const double dt_az = std::min(dt, az_horizon);
    out.position = {normalize_azimuth(anchor_az_ + az_rate_ * dt_az), el};
    out.az_rate = dt < az_horizon ? az_rate_ : 0.0;
    out.el_rate = dt < horizon ? el_rate_ : 0.0;
    out.moving = dt < horizon;
    return out;
}

std::string TargetPredictor::describe() const {
    char text[160];
    if (!have_rate_) {
        std::snprintf(text, sizeof text, "predictive: holding the last target");
    } else {
        std::snprintf(text, sizeof text, "predictive: az rate %.3f deg/s, el rate %.3f deg/s, client lead %s",
                      az_rate_, el_rate_,
                      lead_threshold_ ? (std::to_string(*lead_threshold_).substr(0, 5) + " deg").c_str() : "unknown");
    }
    return text;
}

}  // namespace birdcage
