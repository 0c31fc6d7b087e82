// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Pointing-error statistics the core tests accumulate (max and RMS of a stream of errors).
#pragma once

#include <algorithm>
#include <cmath>

namespace birdcage::test {

struct ErrorStats {
    double max = 0.0, sum_sq = 0.0;
    int n = 0;
    void add(double e) {
        max = std::max(max, e);
        sum_sq += e * e;
        ++n;
    }
    double rms() const { return n ? std::sqrt(sum_sq / n) : 0.0; }
};

}  // namespace birdcage::test
