// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The core's one time source.
//
// Everything the core reckons about motion and the console (leg budgets, poll periods, boot
// waits, the position model) is in the dish's time. Against real hardware that is the steady
// clock; against the emulator run with `birdcage-sim --time-scale k` the dish lives k times faster
// than real time, and tests may drive time by hand. Real waits (poll() on the serial line, a
// worker's sleep) convert a dish duration with to_real(), so one setting (the preload build's conf
// key time_scale) changes every timing at once and no loop mixes the two clocks.
#pragma once

#include <chrono>
#include <functional>
#include <memory>

#include "base/option_range.hpp"
#include "base/plain_types.hpp"

namespace birdcage {

class DishClock {
public:
    // How much faster than real time a scaled clock may run (emulator runs; 1 = real hardware).
    static constexpr OptionRange scale_range{1.0, 1000.0, 0.1};

    // The steady clock: real hardware.
    DishClock() = default;
    // Dish time runs `scale` times faster than real time, from now on.
    static DishClock scaled(double scale);
    // Time under a test's control: `now` is read on every call; real waits are not shortened
    // (scale 1), so a test that advances `now` by hand never sleeps on dish time.
    static DishClock manual(std::function<Clock::time_point()> now);

    Clock::time_point now() const;
    double scale() const { return scale_; }
    // How long a span of dish time lasts in real time (at least 1 ms when `dish` is positive, so
    // a scaled period never becomes a busy loop).
    Clock::duration to_real(Clock::duration dish) const;

private:
    double scale_ = 1.0;
    Clock::time_point origin_{};
    std::function<Clock::time_point()> manual_;
};

}  // namespace birdcage
