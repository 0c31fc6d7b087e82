// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Position model benchmark (docs/tracking.md §1.5): how far `p` is from the truth between two polls
// when the dish's motor does not move the way the variant table says. The backend's own
// position model (modelled_axis, observed_pace, AxisPaces) is fed what the worker would see: a
// leg sent from rest, readings every 100 ms at a random phase. The motor is the emulator's
// physics (birdcage::sim::Axis) under several speed/acceleration profiles, because the real
// Trav'ler's are unknown (docs/firmware.md 3.4). Deterministic (fixed seed); prints a table and
// asserts nothing.
//
//   position_model_bench [--legs N]
#include <birdcage_sim/motor.hpp>

#include "tracking/position_model.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

namespace {

using birdcage::Axis;
using birdcage::AxisPaces;
using birdcage::AxisReading;
using birdcage::Clock;
using birdcage::LegMotion;

constexpr double poll_period_s = 0.1;  // AxisLegDriver's poll_interval
constexpr int questions_per_leg = 20;  // `p` at random moments of each leg
constexpr double after_leg_s = 0.3;    // and a little after it ends

struct Motor {
    const char* name;
    double speed_dps, accel_dps2;
};

Clock::time_point at(double seconds) {
    return Clock::time_point{} + std::chrono::hours(1) +
           std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double p95(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(0.95 * static_cast<double>(v.size() - 1))];
}

struct Errors {
    std::vector<double> first_leg, learnt, last_reading;
};

// `legs` legs of `length` degrees one after another on the elevation axis, each from rest.
Errors run(const birdcage::FirmwareProfile& dish, const Motor& motor, double length, int legs, std::mt19937& random) {
    const birdcage::sim::AxisParams params{motor.speed_dps, motor.accel_dps2, -1000.0, 1000.0, 0};
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    AxisPaces paces;
    Errors errors;
    double position = 0.0;
    for (int leg_index = 0; leg_index < legs; ++leg_index) {
        const double duration = birdcage::sim::Axis::move_time(params, length);
        const double end = duration + after_leg_s;
        // The truth on a fine grid, from the emulator's motor.
        birdcage::sim::Axis axis(params, position);
        axis.move_to(position + length);
        constexpr double step = 0.001;
        std::vector<double> truth;
        for (double t = 0.0; t <= end + step; t += step) {
            truth.push_back(axis.position());
            axis.advance(step);
        }
        auto true_at = [&](double t) { return truth[std::min(truth.size() - 1, static_cast<std::size_t>(t / step))]; };

        LegMotion leg;
        leg.axis = Axis::elevation;
        leg.start = position;
        leg.to = position + length;
        leg.sent_at = at(0.0);
        leg.latest = AxisReading{position, at(-0.5)};
        leg.pace = paces.pace(Axis::elevation, length);  // as AxisLegDriver::motion_of: 1 until learnt
        std::vector<double> reading_times;
        for (double t = unit(random) * poll_period_s; t <= end; t += poll_period_s) {
            reading_times.push_back(t);
        }
        std::vector<double> questions;
        for (int i = 0; i < questions_per_leg; ++i) {
            questions.push_back(unit(random) * end);
        }
        std::sort(questions.begin(), questions.end());
        std::size_t next_reading = 0;
        for (const double q : questions) {
            while (next_reading < reading_times.size() && reading_times[next_reading] <= q) {
                const double t = reading_times[next_reading++];
                birdcage::add_reading(leg, AxisReading{true_at(t), at(t)});
                if (const auto pace = birdcage::observed_pace(dish, leg)) {
                    paces.learn(Axis::elevation, length, *pace);
                }
            }
            const double error = std::abs(birdcage::modelled_axis(dish, leg, at(q)) - true_at(q));
            (leg_index == 0 ? errors.first_leg : errors.learnt).push_back(error);
            errors.last_reading.push_back(std::abs(leg.latest.value - true_at(q)));
        }
        position += length;
    }
    return errors;
}

}  // namespace

int main(int argc, char** argv) {
    int legs = 30;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--legs") == 0 && i + 1 < argc) {
            legs = std::max(2, std::atoi(argv[++i]));
        } else {
            std::fprintf(stderr, "usage: position_model_bench [--legs N]\n");
            return 2;
        }
    }
    const Motor motors[] = {
        {"emulated Trav'ler (20 deg/s, 2 deg/s^2)", 20.0, 2.0},
        {"brisk (10 deg/s, 20 deg/s^2)", 10.0, 20.0},
        {"sluggish (5 deg/s, 1 deg/s^2)", 5.0, 1.0},
    };
    const double lengths[] = {0.3, 0.5, 1.0, 2.0, 5.0, 20.0};
    const birdcage::FirmwareProfile& dish = birdcage::profile(birdcage::VariantId::travler_hal205);
    std::mt19937 random(20261125);
    std::printf("p against the truth, p95 in degrees (%d legs per row, %d questions per leg, readings every %.0f ms)\n",
                legs, questions_per_leg, poll_period_s * 1000.0);
    std::printf("model: the Trav'ler HAL 2.05 row (time fit, docs/firmware.md 3.4)\n\n");
    std::printf("%-42s %7s | %10s %10s %14s\n", "motor", "leg deg", "first leg", "learnt", "last reading");
    for (const Motor& motor : motors) {
        for (const double length : lengths) {
            const Errors e = run(dish, motor, length, legs, random);
            std::printf("%-42s %7.1f | %10.3f %10.3f %14.3f\n", motor.name, length, p95(e.first_leg), p95(e.learnt),
                        p95(e.last_reading));
        }
    }
    return 0;
}
