// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Least-squares quadratic fits, shared by the target estimator (pointing.cpp: a pass's rate and
// curvature) and the wrap tracker (wrap_tracker.cpp: where a pass culminates between targets).
// Pure arithmetic; the caller centres its abscissa so the sums stay well conditioned.
#pragma once

#include <array>
#include <optional>

namespace birdcage {

// Power sums of the samples: u^0..u^4 and y·u^0..y·u^2.
struct QuadraticSums {
    std::array<double, 5> u{};
    std::array<double, 3> yu{};
    void add(double u_value, double y);
};

// y = a + b·u + c·u².
struct Quadratic {
    double a = 0.0, b = 0.0, c = 0.0;
};

// The least-squares quadratic from the normal equations; nullopt when their determinant is at
// most `min_determinant` in size (too few or too clustered samples).
std::optional<Quadratic> solve_quadratic(const QuadraticSums& sums, double min_determinant);

}  // namespace birdcage
