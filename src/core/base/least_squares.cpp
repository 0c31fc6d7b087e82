// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "base/least_squares.hpp"

#include <cmath>

namespace birdcage {
namespace {

using Matrix3 = std::array<std::array<double, 3>, 3>;

double determinant(const Matrix3& a) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

}  // namespace

void QuadraticSums::add(double u_value, double y) {
    double power = 1.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
        u[k] += power;
        if (k < yu.size()) {
            yu[k] += y * power;
        }
        power *= u_value;
    }
}

std::optional<Quadratic> solve_quadratic(const QuadraticSums& s, double min_determinant) {
    // Cramer's rule on the normal equations of y = a + b u + c u^2.
    const Matrix3 m{{{s.u[0], s.u[1], s.u[2]}, {s.u[1], s.u[2], s.u[3]}, {s.u[2], s.u[3], s.u[4]}}};
    const double det = determinant(m);
    if (!(std::fabs(det) > min_determinant)) {
        return std::nullopt;
    }
    const Matrix3 ma{{{s.yu[0], s.u[1], s.u[2]}, {s.yu[1], s.u[2], s.u[3]}, {s.yu[2], s.u[3], s.u[4]}}};
    const Matrix3 mb{{{s.u[0], s.yu[0], s.u[2]}, {s.u[1], s.yu[1], s.u[3]}, {s.u[2], s.yu[2], s.u[4]}}};
    const Matrix3 mc{{{s.u[0], s.u[1], s.yu[0]}, {s.u[1], s.u[2], s.yu[1]}, {s.u[2], s.u[3], s.yu[2]}}};
    return Quadratic{determinant(ma) / det, determinant(mb) / det, determinant(mc) / det};
}

}  // namespace birdcage
