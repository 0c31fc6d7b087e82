// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage/tracking/pass_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace birdcage {
namespace {

using Vec = std::array<double, 3>;
using Mat = std::array<Vec, 3>;

constexpr double deg = M_PI / 180.0;

Vec unit_vector(AzEl p) {
    const double az = p.az * deg, el = p.el * deg;
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

AzEl direction_of(const Vec& v) {
    return {normalize_azimuth(std::atan2(v[0], v[1]) / deg), std::atan2(v[2], std::hypot(v[0], v[1])) / deg};
}

double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

Vec cross(const Vec& a, const Vec& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::optional<Vec> normalized(const Vec& a) {
    const double length = std::sqrt(dot(a, a));
    if (length < 1e-12) {
        return std::nullopt;
    }
    return Vec{a[0] / length, a[1] / length, a[2] / length};
}

// Eigenvector of the smallest eigenvalue of a symmetric 3×3 matrix (cyclic Jacobi rotations).
// Power iteration would not do: for targets spread along a short arc the two largest
// eigenvalues are nearly equal and their mixture never settles.
Vec smallest_eigenvector(Mat a) {
    Mat v{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        if (off < 1e-30) {
            break;
        }
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (std::fabs(a[p][q]) < 1e-300) {
                    continue;
                }
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::fabs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
        }
    }
    int smallest = 0;
    for (int i = 1; i < 3; ++i) {
        if (a[i][i] < a[smallest][smallest]) {
            smallest = i;
        }
    }
    return {v[0][smallest], v[1][smallest], v[2][smallest]};
}

// Per-axis distance, as the client's threshold box measures it.
double box_distance(AzEl a, AzEl b) {
    return std::max(std::fabs(azimuth_difference(a.az, b.az)), std::fabs(a.el - b.el));
}

struct TimeLaw {
    double a = 0.0, k = 0.0, w = 0.0, tc = 0.0;
    double at(double t) const { return a + k * std::atan(w * (t - tc)); }
    double rate(double t) const {
        const double x = w * (t - tc);
        return k * w / (1.0 + x * x);
    }
};

double squared_residual(const TimeLaw& law, const std::vector<double>& ts, const std::vector<double>& thetas) {
    double sum = 0.0;
    for (std::size_t i = 0; i < ts.size(); ++i) {
        const double r = thetas[i] - law.at(ts[i]);
        sum += r * r;
    }
    return sum;
}

// Solves the n×n system in place (Gaussian elimination, partial pivoting); false if singular.
template <std::size_t N>
bool solve(std::array<std::array<double, N + 1>, N>& m) {
    for (std::size_t i = 0; i < N; ++i) {
        std::size_t pivot = i;
        for (std::size_t r = i + 1; r < N; ++r) {
            if (std::fabs(m[r][i]) > std::fabs(m[pivot][i])) {
                pivot = r;
            }
        }
        std::swap(m[i], m[pivot]);
        if (std::fabs(m[i][i]) < 1e-300) {
            return false;
        }
        for (std::size_t r = 0; r < N; ++r) {
            if (r == i) {
                continue;
            }
            const double f = m[r][i] / m[i][i];
            for (std::size_t j = i; j <= N; ++j) {
                m[r][j] -= f * m[i][j];
            }
        }
    }
    for (std::size_t i = 0; i < N; ++i) {
        m[i][N] /= m[i][i];
    }
    return true;
}

// θ(t) = a + k·atan(w·(t − tc)): a and k are linear, so a grid over (w, tc) solves them exactly
// and the best cell starts Levenberg–Marquardt over all four.
std::optional<TimeLaw> fit_time_law(const std::vector<double>& ts, const std::vector<double>& thetas) {
    // The grid sees at most this many targets (a 0.5° client sends hundreds in the window): it
    // only has to find the right basin.
    constexpr std::size_t grid_targets = 40;
    const std::size_t stride = (ts.size() + grid_targets - 1) / grid_targets;
    std::vector<double> grid_ts, grid_thetas;
    for (std::size_t i = ts.size(); i-- > 0;) {
        if ((ts.size() - 1 - i) % stride == 0) {
            grid_ts.push_back(ts[i]);
            grid_thetas.push_back(thetas[i]);
        }
    }
    const double n = static_cast<double>(grid_ts.size());
    std::optional<TimeLaw> best;
    double best_cost = 0.0;
    // Culmination within ±10 min of the newest target; w = on-sky rate over distance, from a
    // distant low pass (~0.003 rad/s) to an overhead one (~0.02 rad/s) and beyond.
    for (double dt = -600.0; dt <= 600.0; dt += 20.0) {
        for (double w = 0.003; w < 0.6; w *= 1.2) {
            const double tc = ts.back() + dt;
            double sg = 0, sy = 0, sgg = 0, sgy = 0;
            for (std::size_t i = 0; i < grid_ts.size(); ++i) {
                const double g = std::atan(w * (grid_ts[i] - tc));
                sg += g;
                sy += grid_thetas[i];
                sgg += g * g;
                sgy += g * grid_thetas[i];
            }
            const double det = n * sgg - sg * sg;
            if (std::fabs(det) < 1e-12) {
                continue;
            }
            TimeLaw law;
            law.k = (n * sgy - sg * sy) / det;
            law.a = (sy - law.k * sg) / n;
            law.w = w;
            law.tc = tc;
            const double cost = squared_residual(law, grid_ts, grid_thetas);
            if (!best || cost < best_cost) {
                best = law;
                best_cost = cost;
            }
        }
    }
    if (!best) {
        return std::nullopt;
    }
    TimeLaw law = *best;
    best_cost = squared_residual(law, ts, thetas);
    double lambda = 1e-3;
    for (int iteration = 0; iteration < 200; ++iteration) {
        std::array<std::array<double, 5>, 4> m{};
        for (std::size_t i = 0; i < ts.size(); ++i) {
            const double x = law.w * (ts[i] - law.tc);
            const double d = 1.0 / (1.0 + x * x);
            const std::array<double, 4> j{1.0, std::atan(x), law.k * (ts[i] - law.tc) * d, -law.k * law.w * d};
            const double r = thetas[i] - law.at(ts[i]);
            for (int p = 0; p < 4; ++p) {
                for (int q = 0; q < 4; ++q) {
                    m[p][q] += j[p] * j[q];
                }
                m[p][4] += j[p] * r;
            }
        }
        for (int p = 0; p < 4; ++p) {
            m[p][p] *= 1.0 + lambda;
        }
        if (!solve<4>(m)) {
            break;
        }
        const TimeLaw trial{law.a + m[0][4], law.k + m[1][4], law.w + m[2][4], law.tc + m[3][4]};
        const double cost = trial.w > 0.0 ? squared_residual(trial, ts, thetas) : best_cost + 1.0;
        if (cost < best_cost) {
            const bool converged = best_cost - cost < 1e-10 * best_cost;
            law = trial;
            best_cost = cost;
            lambda *= 0.3;
            if (converged) {
                break;
            }
        } else {
            lambda *= 10.0;
            if (lambda > 1e10) {
                break;
            }
        }
    }
    return law;
}

}  // namespace

PassModel::PassModel(PassModelSettings settings) : settings_(settings) {}

void PassModel::clear() {
    samples_.clear();
    good_ = false;
    description_ = "no targets";
}

void PassModel::add(double t, AzEl target) {
    samples_.push_back({t, unit_vector(target), target});
    while (!samples_.empty() && samples_.back().t - samples_.front().t > settings_.window_s) {
        samples_.pop_front();
    }
    good_ = false;
}

PassModel::Vec PassModel::point_at(double theta) const {
    Vec p;
    for (int i = 0; i < 3; ++i) {
        p[i] = c_ * n_[i] + r_ * (std::cos(theta) * u_[i] + std::sin(theta) * w_[i]);
    }
    return p;
}

bool PassModel::fit(std::optional<double> lead_threshold_deg) {
    good_ = false;
    auto refuse = [this](const char* why) {
        description_ = why;
        return false;
    };
    const std::size_t count = samples_.size();
    if (count < settings_.min_targets) {
        return refuse("too few targets for a pass model");
    }
    // The plane: through the mean of the targets (a small circle) when four or more show its
    // curvature, through the centre of the sphere (a great circle) otherwise.
    Vec mean{};
    for (const auto& s : samples_) {
        for (int i = 0; i < 3; ++i) {
            mean[i] += s.v[i] / static_cast<double>(count);
        }
    }
    Mat scatter{};
    for (const auto& s : samples_) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                scatter[i][j] += (s.v[i] - mean[i]) * (s.v[j] - mean[j]);
            }
        }
    }
    n_ = smallest_eigenvector(scatter);
    c_ = dot(n_, mean);
    r_ = std::sqrt(std::max(0.0, 1.0 - c_ * c_));
    double cross_sq = 0.0;
    for (const auto& s : samples_) {
        const double off = (dot(n_, s.v) - c_) / deg;
        cross_sq += off * off;
    }
    const double cross_rms = std::sqrt(cross_sq / static_cast<double>(count));
    if (cross_rms > settings_.max_cross_track_deg) {
        return refuse("targets off any circle: not one pass");
    }
    // A small circle of the sky whose radius is tiny is a point, not a track.
    if (r_ < 0.2) {
        return refuse("targets around one point: not a pass");
    }
    auto basis_from = [this](const Vec& reference) {
        Vec in_plane;
        const double along_n = dot(reference, n_);
        for (int i = 0; i < 3; ++i) {
            in_plane[i] = reference[i] - along_n * n_[i];
        }
        const auto u = normalized(in_plane);
        if (!u) {
            return false;
        }
        u_ = *u;
        w_ = cross(n_, u_);
        return true;
    };
    if (!basis_from(samples_.back().v)) {
        return refuse("degenerate circle");
    }
    auto angles = [this] {
        std::vector<double> thetas;
        for (const auto& s : samples_) {
            const double raw = std::atan2(dot(s.v, w_), dot(s.v, u_));
            thetas.push_back(thetas.empty() ? raw : thetas.back() + std::remainder(raw - thetas.back(), 2.0 * M_PI));
        }
        return thetas;
    };
    std::vector<double> thetas = angles();
    if (thetas.back() < thetas.front()) {
        // Orient the circle so that θ grows with time.
        for (auto& x : n_) {
            x = -x;
        }
        c_ = -c_;
        basis_from(samples_.back().v);
        thetas = angles();
    }
    // Targets that go back and forth are manual pointing, not a pass (a client re-sending the
    // same lead point may step back by its quantisation, a fraction of a degree).
    for (std::size_t i = 1; i < count; ++i) {
        if ((thetas[i] - thetas[i - 1]) * r_ < -1.0 * deg) {
            return refuse("targets go back and forth: not a pass");
        }
    }
    // Remove the lead: the satellite is back along the circle by the threshold (per axis).
    if (lead_threshold_deg && *lead_threshold_deg > 0.0) {
        for (std::size_t i = 0; i < count; ++i) {
            double lo = 0.0, hi = std::min(M_PI / 2.0, 30.0 * deg / r_);
            for (int step = 0; step < 40; ++step) {
                const double mid = 0.5 * (lo + hi);
                if (box_distance(direction_of(point_at(thetas[i] - mid)), samples_[i].target) > *lead_threshold_deg) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            thetas[i] -= lo;
        }
    }
    std::vector<double> ts;
    for (const auto& s : samples_) {
        ts.push_back(s.t);
    }
    if (ts.back() - ts.front() <= 0.0) {
        return refuse("targets without a time span");
    }
    const auto law = fit_time_law(ts, thetas);
    if (!law) {
        return refuse("no time law fits the targets");
    }
    const double along_rms = std::sqrt(squared_residual(*law, ts, thetas) / static_cast<double>(count)) * r_ / deg;
    if (along_rms > settings_.max_along_track_deg) {
        return refuse("the targets do not follow a pass's time law");
    }
    if (law->k <= 0.0) {
        return refuse("a time law that turns back");
    }
    const double peak_rate_dps = law->k * law->w * r_ / deg;
    if (peak_rate_dps > settings_.max_sky_rate_dps) {
        return refuse("a rate no satellite has");
    }
    a_ = law->a;
    k_ = law->k;
    rate_w_ = law->w;
    tc_ = law->tc;
    good_ = true;
    char text[200];
    std::snprintf(text, sizeof text,
                  "pass model: %zu targets, circle radius %.1f deg (off by %.3f deg), culmination at %+.0f s, "
                  "peak %.2f deg/s, along-track residual %.2f deg",
                  count, std::asin(r_) / deg, cross_rms, tc_ - ts.back(), peak_rate_dps, along_rms);
    description_ = text;
    return true;
}

double PassModel::theta_at(double t) const { return a_ + k_ * std::atan(rate_w_ * (t - tc_)); }

std::optional<PassPoint> PassModel::predict(double t) const {
    if (!good_) {
        return std::nullopt;
    }
    // Rates by a central difference: the azimuth rate near the zenith is the circle's business,
    // not a formula of its own.
    constexpr double half_step_s = 0.25;
    const AzEl here = direction_of(point_at(theta_at(t)));
    const AzEl before = direction_of(point_at(theta_at(t - half_step_s)));
    const AzEl after = direction_of(point_at(theta_at(t + half_step_s)));
    PassPoint out;
    out.position = here;
    out.az_rate = azimuth_difference(before.az, after.az) / (2.0 * half_step_s);
    out.el_rate = (after.el - before.el) / (2.0 * half_step_s);
    return out;
}

}  // namespace birdcage
