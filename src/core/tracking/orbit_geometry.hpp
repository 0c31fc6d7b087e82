// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The orbit model's geometry: the Earth as the site sees it, a circular orbit's track on the sky, and
// the client's look-ahead replayed against it. Shared by the fit (orbit_fit.cpp: the two-point
// solution, Levenberg–Marquardt, the client's lead) and by the model's predictions and trust
// judgement (orbit_model.cpp). Not installed: internal to the core.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "base/azel.hpp"
#include "tracking/orbit_model.hpp"

namespace birdcage::orbit_geometry {

using Vec = std::array<double, 3>;
using Orbit = OrbitModel::Orbit;

constexpr double deg = M_PI / 180.0;
constexpr double earth_mu_km3_s2 = 398600.4418;    // WGS-84
constexpr double earth_spin_rad_s = 7.2921159e-5;  // sidereal
constexpr double equatorial_radius_km = 6378.137;
constexpr double polar_radius_km = 6356.752;
constexpr double mean_radius_km = 6371.0;
// How far ahead the track is searched for its rise and set (seconds).
constexpr double rise_search_s = 1800.0;

inline double dot(const Vec& a, const Vec& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline Vec scaled(const Vec& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
inline Vec plus(const Vec& a, const Vec& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec minus(const Vec& a, const Vec& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec unit(const Vec& a) {
    return scaled(a, 1.0 / std::sqrt(dot(a, a)));
}

inline Vec unit_vector(AzEl p) {
    const double az = p.az * deg, el = p.el * deg;
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

inline AzEl direction_of(const Vec& v) {
    return {normalize_azimuth(std::atan2(v[0], v[1]) / deg), std::atan2(v[2], std::hypot(v[0], v[1])) / deg};
}

inline double angle_deg(const Vec& a, const Vec& b) {
    return std::atan2(std::sqrt(dot(cross(a, b), cross(a, b))), dot(a, b)) / deg;
}

// Rodrigues: v turned by `angle` about the unit `axis`.
inline Vec rotated(const Vec& v, const Vec& axis, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return plus(plus(scaled(v, c), scaled(cross(axis, v), s)), scaled(axis, dot(axis, v) * (1.0 - c)));
}

// The Earth as the site sees it: the centre's distance below the site and the spin axis in the
// site's east-north-up frame.
struct Earth {
    double radius_km = mean_radius_km;
    Vec axis{0.0, 0.0, 1.0};
    double spin = 0.0;  // rad/s; 0: a still Earth
};

inline Earth earth_at(std::optional<double> latitude_deg) {
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

inline double kepler_rate(double radius_km) {
    return std::sqrt(earth_mu_km3_s2 / (radius_km * radius_km * radius_km));
}

// The orbit's geometry at its reference time: position direction p0 and in-plane direction of
// motion w (geocentric, site frame), radius and rate.
struct Circle {
    Vec p0, w;
    double radius_km, rate;
};

inline Circle circle_of(const Orbit& o, const Earth& earth) {
    const Vec p0 = unit({o.x, o.y, 1.0});
    const Vec east{1.0, 0.0, 0.0};
    const Vec e1 = unit(minus(east, scaled(p0, dot(east, p0))));
    const Vec e2 = cross(p0, e1);
    const double radius = earth.radius_km + o.altitude_km;
    return {p0, plus(scaled(e1, std::cos(o.heading)), scaled(e2, std::sin(o.heading))), radius, kepler_rate(radius)};
}

// The satellite seen from the site at time t, as a vector (km).
inline Vec line_of_sight(const Circle& c, const Earth& earth, double t_ref, double t) {
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
    // up to a second either way (its last step evaluated is a whole cycle), a fifth of the lead at
    // 0.5° where the satellite covers 0.1°/s. The fit needs residuals that move
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

}  // namespace birdcage::orbit_geometry
