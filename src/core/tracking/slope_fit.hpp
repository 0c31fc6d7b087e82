// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The local estimate's fit (pointing.cpp): the rate and curvature of one coordinate of the client's
// recent targets at the newest of them, by least squares, and how far the targets lie off it.
// `Samples` is a sequence of values with a time `t` in seconds, oldest first.
#pragma once

#include <cmath>
#include <cstddef>

#include "base/least_squares.hpp"

namespace birdcage::slope_fit {

// Quadratic fits need this many samples over this span; below, a straight line.
constexpr std::size_t quadratic_min_samples = 3;
constexpr double quadratic_min_span_s = 3.0;

struct Fit {
    double rate = 0.0;   // slope at the newest sample
    double accel = 0.0;  // curvature (0 for a straight line)
    bool ok = false;
};

// Mean square of the samples off a fitted curve (its offset the best one for the given rate and
// curvature), each scaled by `scale` (cos(el) turns an azimuth into an angle on the sky).
template <typename Samples, typename Get>
double mean_square_off(const Samples& samples, Get value, const Fit& fit, double scale) {
    const double t_end = samples.back().t;
    auto curve = [&](double u) { return fit.rate * u + 0.5 * fit.accel * u * u; };
    double offset = 0.0;
    for (const auto& s : samples) {
        offset += value(s) - curve(s.t - t_end);
    }
    offset /= static_cast<double>(samples.size());
    double sum = 0.0;
    for (const auto& s : samples) {
        const double off = (value(s) - curve(s.t - t_end) - offset) * scale;
        sum += off * off;
    }
    return sum / static_cast<double>(samples.size());
}

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
    QuadraticSums sums;
    for (const auto& s : samples) {
        sums.add(s.t - t_end, value(s));
    }
    const auto& st = sums.u;
    const auto& sy = sums.yu;
    const double linear_det = st[0] * st[2] - st[1] * st[1];
    if (std::fabs(linear_det) < 1e-12) {
        return {};
    }
    double rate = (st[0] * sy[1] - st[1] * sy[0]) / linear_det;
    double accel = 0.0;
    if (n >= quadratic_min_samples && span >= quadratic_min_span_s) {
        const auto quadratic = solve_quadratic(sums, 1e-9);
        if (quadratic && std::fabs(2.0 * quadratic->c) <= accel_bound) {
            rate = quadratic->b;
            accel = 2.0 * quadratic->c;
        }
    }
    return {rate, accel, true};
}

}  // namespace birdcage::slope_fit
