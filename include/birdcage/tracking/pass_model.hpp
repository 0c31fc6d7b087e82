// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A model of one satellite pass fitted to the client's targets, for predicting far beyond the
// last target (docs/tracking.md §6).
//
// Why: at Gpredict's default 5° threshold a target comes every 15–40 s, and a local linear or
// curved extrapolation of az/el drifts off within that time. Over a few minutes a LEO pass keeps
// to a circle on the sky, and its rate along that circle follows a flyby's profile: slow at the
// horizon, fastest at culmination. Both are seen in a handful of targets, and the zenith, where
// az/el extrapolation breaks, is an ordinary point on a circle.
//
// What it fits, from the targets of the last `window_s` seconds as unit vectors:
//   * the plane n·x = c closest to them (the smallest eigenvector of their covariance; a great
//     circle, c = 0, when there are too few targets to see the curvature): a small circle, which
//     holds the track of a low pass that a great circle misses by tenths of a degree;
//   * the client's lead removed: a target is where the satellite will be once it has moved the
//     client's threshold (per axis, TargetPredictor learns it), so the satellite at the target's
//     time is that far back along the circle;
//   * the angle around the circle against time, θ(t) = a + k·atan(w·(t − tc)): a straight flyby at
//     constant speed, whose rate peaks at the culmination tc (Levenberg–Marquardt from a grid).
// The fit is refused (good() false) with too few targets, targets off any circle (manual
// pointing) or a time law that does not follow them, or a rate no satellite has; the caller then
// falls back to its local estimate.
//
// Pure and clock-free: times are seconds on the caller's clock.
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <string>

#include "birdcage/base/azel.hpp"

namespace birdcage {

struct PassModelSettings {
    // Targets older than this are not fitted: the sky track bends away from one circle over a
    // whole pass (by up to ~0.9° for the bench passes), while 5 minutes hold it within ~0.1°.
    double window_s = 300.0;
    // The time law has four parameters: one more target than that before it is trusted.
    std::size_t min_targets = 5;
    // RMS distance of the targets from the fitted circle above which they are not one pass.
    double max_cross_track_deg = 0.2;
    // RMS of the along-track residual above which the time law does not follow the targets
    // (Gpredict's lead is quantised to a quarter cycle: ±0.5° of scatter at the culmination).
    double max_along_track_deg = 0.6;
    // Faster than any LEO satellite on the sky (docs/tracking.md §2.1: ≤ 1.2°/s).
    double max_sky_rate_dps = 2.5;
};

struct PassPoint {
    AzEl position;          // azimuth in [0, 360)
    double az_rate = 0.0;   // deg/s
    double el_rate = 0.0;
};

class PassModel {
public:
    explicit PassModel(PassModelSettings settings = {});

    void clear();
    // A client target at time t (seconds); older targets than the window are dropped.
    void add(double t, AzEl target);
    // Refits from the targets held; `lead_threshold_deg`: the client's learned lead (none: the
    // targets are taken as the satellite's position at their time). Returns good().
    bool fit(std::optional<double> lead_threshold_deg);

    bool good() const { return good_; }
    std::size_t targets() const { return samples_.size(); }
    // The satellite at time t; nullopt unless good().
    std::optional<PassPoint> predict(double t) const;
    // For logs: why the fit was refused, or its parameters.
    const std::string& describe() const { return description_; }

private:
    using Vec = std::array<double, 3>;
    struct Sample {
        double t;
        Vec v;
        AzEl target;
    };
    Vec point_at(double theta) const;
    double theta_at(double t) const;

    PassModelSettings settings_;
    std::deque<Sample> samples_;
    bool good_ = false;
    std::string description_ = "no targets";
    // The circle: points c·n + r·(cos θ·u + sin θ·w), θ growing with time.
    Vec n_{}, u_{}, w_{};
    double c_ = 0.0, r_ = 1.0;
    // θ(t) = a + k·atan(w·(t − tc))
    double a_ = 0.0, k_ = 0.0, rate_w_ = 0.0, tc_ = 0.0;
};

}  // namespace birdcage
