// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "base/clock.hpp"

#include <algorithm>

namespace birdcage {

DishClock DishClock::scaled(double scale) {
    DishClock clock;
    clock.scale_ = scale > 0.0 ? scale : 1.0;
    clock.origin_ = Clock::now();
    return clock;
}

DishClock DishClock::manual(std::function<Clock::time_point()> now) {
    DishClock clock;
    clock.manual_ = std::move(now);
    return clock;
}

Clock::time_point DishClock::now() const {
    if (manual_) {
        return manual_();
    }
    if (scale_ == 1.0) {
        return Clock::now();
    }
    const auto elapsed = std::chrono::duration<double>(Clock::now() - origin_) * scale_;
    return origin_ + std::chrono::duration_cast<Clock::duration>(elapsed);
}

Clock::duration DishClock::to_real(Clock::duration dish) const {
    if (scale_ == 1.0 || dish <= Clock::duration::zero()) {
        return dish;
    }
    const auto real = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dish) / scale_);
    return std::max<Clock::duration>(real, std::chrono::milliseconds{1});
}

}  // namespace birdcage
