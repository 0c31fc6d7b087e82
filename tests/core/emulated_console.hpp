// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator's console engine (sim/include/birdcage_sim/console.hpp, the test oracle) behind the
// core's Transport, in dish time only: no pty, no thread, no wall clock. The console and the
// controller's manual clock advance together, by the test's ticks and while the core waits for a
// reply, so a run is the same on a loaded machine as on an idle one.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "base/clock.hpp"
#include "birdcage_sim/console.hpp"
#include "console/transport.hpp"

namespace birdcage::test {

class EmulatedConsole final : public Transport {
public:
    explicit EmulatedConsole(const sim::Options& options) : console_(options) {}

    // The controller's clock: reads the dish's time.
    DishClock clock() {
        return DishClock::manual([this] { return now_; });
    }

    // Dish time passes: the console's motors and timers run, its output waits to be read.
    void tick(std::chrono::milliseconds span) {
        console_.advance(std::chrono::duration<double>(span).count());
        now_ += span;
        take_output();
    }

    Status write(std::string_view bytes, Deadline) override {
        writes_.push_back({console_.time(), std::string(bytes)});
        console_.feed(bytes);
        take_output();
        return Status::ok();
    }

    // What crossed the line, with the dish's time (seconds) it crossed at: for tests that ask what
    // the core sent after the dish said something, and how soon.
    struct Timed {
        double at;
        std::string bytes;
    };
    const std::vector<Timed>& writes() const { return writes_; }
    const std::vector<Timed>& dish_output() const { return dish_output_; }

    // A read that finds nothing lets one slice of dish time pass first (the line is never idle in
    // dish time while the core waits), then reports a timeout as the contract allows.
    Result<std::size_t> read(char* buf, std::size_t n, Deadline) override {
        if (output_.empty()) {
            tick(read_slice);
        }
        if (output_.empty()) {
            return {0, Status{Errc::timeout, "emulated console: nothing to read"}};
        }
        const std::size_t count = std::min(n, output_.size());
        std::copy_n(output_.data(), count, buf);
        output_.erase(0, count);
        return {count, Status::ok()};
    }

    void discard_input() override { output_.clear(); }

    sim::Console& console() { return console_; }
    const sim::Console& console() const { return console_; }

private:
    void take_output() {
        std::string fresh = console_.take_output();
        if (!fresh.empty()) {
            dish_output_.push_back({console_.time(), fresh});
            output_ += fresh;
        }
    }

    static constexpr std::chrono::milliseconds read_slice{10};
    std::vector<Timed> writes_;
    std::vector<Timed> dish_output_;
    sim::Console console_;
    std::string output_;
    Clock::time_point now_ = Clock::time_point{} + std::chrono::hours(1);
};

}  // namespace birdcage::test
