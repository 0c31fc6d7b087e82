// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A pass through a Gpredict-like client (testbed/gpredict_client.hpp) on a Trav'ler HAL 2.05 whose
// motor meets the documented timings (docs/firmware.md 3.4: about 6 s for 10 deg, 13.5 s for 90 deg)
// but starts moving 2 s after each command: the backend has to learn that delay from the dish's
// readings (docs/tracking.md 1.5) instead of reading the unmoved axis as stopped short and
// re-sending. The same motor is also driven by the oracle client (the true position every cycle),
// the floor of what the backend can do on it; both runs' figures are printed.
#include <catch2/catch.hpp>

#include "gpredict_client.hpp"
#include "harness.hpp"
#include "pass.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

namespace {

constexpr double el_min = 15.0, el_max = 90.0;  // the HAL 2.05's limits
constexpr int hal205_model = 90102;
// Simulated seconds per real second: the pass window below takes ~20 s of real time.
constexpr double time_scale = 10.0;
constexpr double window_s = 200.0;  // around the culmination: the fast part of the pass

struct PassFigures {
    double rms = 0.0, max = 0.0;
    std::size_t motor_starts = 0, stopped_short = 0;
};

bool is_move(const std::string& line) {
    return line.rfind("a ", 0) == 0 && line.find(' ', 2) != std::string::npos;
}

std::size_t occurrences(const std::string& text, const std::string& what) {
    std::size_t count = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) {
        ++count;
    }
    return count;
}

PassFigures run_pass(const bench::Pass& pass, double threshold, bool oracle) {
    const double start = pass.tca() - window_s / 2.0, end = pass.tca() + window_s / 2.0;
    birdcage::sim::Options dish = e2e::dish_options(birdcage::sim::Variant::travler_hal205, pass.at(start).az,
                                                    std::clamp(pass.at(start).el, el_min, el_max), time_scale);
    dish.motor.startup_delay = 2.0;  // --motor-startup-delay 2 --motor-accel 3
    dish.motor.accel = 3.0;
    char scale_conf[48];
    std::snprintf(scale_conf, sizeof scale_conf, "time_scale=%g", time_scale);
    e2e::Rig rig(dish, hal205_model, {"-C", "pointing=predictive", "-C", scale_conf});
    const std::size_t commands_before = rig.dish().received_commands().size();

    bench::ClientSettings settings;
    settings.threshold_deg = threshold;
    settings.true_position_every_cycle = oracle;
    settings.min_el = el_min;
    settings.max_el = el_max;
    bench::GpredictClient client(pass, settings, rig.dish(), time_scale, rig.port(), start);
    client.run_until(end);

    PassFigures figures;
    const std::vector<std::string> commands = rig.dish().received_commands();
    figures.motor_starts = static_cast<std::size_t>(
        std::count_if(commands.begin() + static_cast<std::ptrdiff_t>(commands_before), commands.end(), is_move));
    figures.stopped_short = occurrences(rig.rotctld_log_text(), ", short of ");

    // The error against the dish's true path (the emulator's history, held between samples), on a
    // 0.1 s grid, after the first 20 s in which the dish comes on to the pass.
    std::vector<birdcage::sim::Sample> history = rig.dish().history();
    std::size_t h = 0;
    double sum_squares = 0.0;
    std::size_t n = 0;
    for (double t = start + 20.0; t <= end; t += 0.1) {
        while (h + 1 < history.size() && client.pass_time_of(history[h + 1].t) <= t) {
            ++h;
        }
        const bench::Direction sat = pass.at(t);
        if (sat.el < el_min) {
            continue;
        }
        const double error = bench::angle_between(sat, bench::Direction{history[h].az, history[h].el});
        sum_squares += error * error;
        figures.max = std::max(figures.max, error);
        ++n;
    }
    REQUIRE(n > 0);
    figures.rms = std::sqrt(sum_squares / static_cast<double>(n));
    std::printf(
        "hal205, start-up delay 2 s, accel 3 deg/s^2, %s, threshold %g deg: RMS %.2f deg, max %.2f deg, "
        "%zu motor starts, %zu legs declared stopped short\n",
        oracle ? "oracle" : "Gpredict-like", threshold, figures.rms, figures.max, figures.motor_starts,
        figures.stopped_short);
    return figures;
}

}  // namespace

TEST_CASE("motor dynamics: a 60 deg pass on a motor that starts 2 s late stays on the satellite", "[motor_dynamics]") {
    const bench::Pass pass = bench::Pass::load(std::string(BIRDCAGE_BENCH_PASSES_DIR) + "/iss-60.csv");
    // The oracle posts the true position every cycle: no threshold, so one run serves both.
    const PassFigures oracle = run_pass(pass, 0.0, true);
    CHECK(oracle.stopped_short == 0);
    for (const double threshold : {0.5, 5.0}) {
        const PassFigures client = run_pass(pass, threshold, false);
        INFO("threshold " << threshold);
        // No leg on this motor stops short: every unmoved reading was taken inside the start-up delay.
        CHECK(client.stopped_short == 0);
        // The dish follows instead of falling ever further behind: re-sending on every leg, it
        // ended this window 12-13 deg RMS off; aiming by the learnt delay but not the travel over
        // the leg's length, 5.8-9.2 deg; with both, 3.3-5.3 deg (docs/benchmarks.md, motors that
        // start late). The RMS against the oracle's and the max are printed, not asserted: this
        // runs in real time, and a loaded machine spreads single runs.
        CHECK(client.rms < 8.0);
    }
}

namespace {

// A HAL 2.05 left at its default pointing (none: the variant's first guess) on `motor`, through a
// Gpredict-like client at 0.5 deg for the first 100 s of the window: the log, for what the backend
// made of the dish's motors.
std::string pointing_log(const bench::Pass& pass, const birdcage::sim::MotorDynamics& motor) {
    const double start = pass.tca() - window_s / 2.0, end = start + 100.0;
    birdcage::sim::Options dish = e2e::dish_options(birdcage::sim::Variant::travler_hal205, pass.at(start).az,
                                                    std::clamp(pass.at(start).el, el_min, el_max), time_scale);
    dish.motor = motor;
    char scale_conf[48];
    std::snprintf(scale_conf, sizeof scale_conf, "time_scale=%g", time_scale);
    e2e::Rig rig(dish, hal205_model, {"-C", scale_conf});
    bench::ClientSettings settings;
    settings.threshold_deg = 0.5;
    settings.min_el = el_min;
    settings.max_el = el_max;
    bench::GpredictClient client(pass, settings, rig.dish(), time_scale, rig.port(), start);
    client.run_until(end);
    return rig.rotctld_log_text();
}

}  // namespace

TEST_CASE("motor dynamics: the pointing mode follows the dish's own motors, not its firmware", "[motor_dynamics]") {
    const bench::Pass pass = bench::Pass::load(std::string(BIRDCAGE_BENCH_PASSES_DIR) + "/iss-60.csv");
    SECTION("a HAL 2.05 console on motors as fast as the G2's steers ahead") {
        birdcage::sim::MotorDynamics fast;  // the G2's (sim variants.cpp): 65 deg/s, 400 deg/s^2
        fast.az_velocity = 65.0;
        fast.el_velocity = 65.0;
        fast.accel = 400.0;
        const std::string log = pointing_log(pass, fast);
        CHECK(log.find("predictive from now on") != std::string::npos);
    }
    SECTION("the emulator's documented Trav'ler motor stays at none, steered by the orbit once it is trusted") {
        const std::string log = pointing_log(pass, {});
        CHECK(log.find("predictive from now on") == std::string::npos);
        CHECK(log.find("pointing: the orbit is trusted") != std::string::npos);
    }
}
