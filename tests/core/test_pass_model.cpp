// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// PassModel and TargetPredictor's use of it on the SGP4 passes of bench/passes: a Gpredict-like
// threshold client (docs/tracking.md §3.2, bench/gpredict_client.cpp) sends lead targets to a dish
// that jumps to each (what `pointing=none` does), and the prediction 5, 15 and 30 s past each
// instant is compared with the true pass. Also the fallbacks: a single P, a jump, a stop.
// Pure and deterministic: no threads, no sleeping; every time is built here.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "birdcage/base/azel.hpp"
#include "birdcage/tracking/pass_model.hpp"
#include "birdcage/tracking/pointing.hpp"
#include "error_stats.hpp"

using namespace birdcage;

namespace {

const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1000);

Clock::time_point at(double seconds) {
    return t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

double two_decimals(double x) { return std::round(x * 100.0) / 100.0; }

double sky_angle(AzEl a, AzEl b) {
    const double d = M_PI / 180.0;
    const double c = std::sin(a.el * d) * std::sin(b.el * d) +
                     std::cos(a.el * d) * std::cos(b.el * d) * std::cos((a.az - b.az) * d);
    return std::acos(std::clamp(c, -1.0, 1.0)) / d;
}

// A pass from bench/passes (columns t,az,el; '#' comment lines), interpolated linearly.
struct TruePass {
    std::string name;
    std::vector<double> t, az, el;

    static TruePass load(const std::string& name) {
        TruePass pass;
        pass.name = name;
        std::ifstream in(std::string(BIRDCAGE_SOURCE_DIR) + "/bench/passes/" + name + ".csv");
        REQUIRE(in.good());
        std::string line;
        while (std::getline(in, line)) {
            if (line.empty() || line[0] == '#' || line[0] == 't') {
                continue;
            }
            double t = 0, az = 0, el = 0;
            char comma = 0;
            std::istringstream row(line);
            row >> t >> comma >> az >> comma >> el;
            pass.t.push_back(t);
            pass.az.push_back(az);
            pass.el.push_back(el);
        }
        REQUIRE(pass.t.size() > 100);
        return pass;
    }

    AzEl at(double time) const {
        const auto upper = std::upper_bound(t.begin(), t.end(), time);
        const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(upper - t.begin()), 1, t.size() - 1) - 1;
        const double f = (time - t[i]) / (t[i + 1] - t[i]);
        return {normalize_azimuth(az[i] + f * azimuth_difference(az[i], az[i + 1])), el[i] + f * (el[i + 1] - el[i])};
    }
};

using Errors = birdcage::test::ErrorStats;

constexpr double aheads[] = {5.0, 15.0, 30.0};

struct PassRun {
    int targets = 0;
    int seconds_measured = 0, seconds_on_pass_model = 0;
    std::map<double, Errors> errors;   // by seconds ahead
};

// Gpredict's timer every second (docs/tracking.md §5): when the dish is more than `threshold` off
// on either axis (plain differences), it sends the satellite's position at the edge of the
// threshold ahead (bisection to a quarter cycle), with two decimals; the dish jumps there. From
// the third target on, each second, the predictor's estimate `ahead` seconds later is compared
// with the satellite's position then (while it is above the horizon).
PassRun run_client(const TruePass& pass, double threshold, bool use_pass_model) {
    PredictorSettings settings;
    settings.use_pass_model = use_pass_model;
    TargetPredictor predictor(settings);
    PassRun run;
    AzEl dish{0.0, 0.0};
    const double end = pass.t.back() - 1.0;
    for (double now = pass.t.front(); now < end; now += 1.0) {
        const AzEl sat = pass.at(now);
        const bool off = std::fabs(sat.az - dish.az) > threshold || std::fabs(sat.el - dish.el) > threshold;
        if (sat.el > 0.0 && off) {
            double delta = end - now, step = std::max(delta / 2.0, 1.0);
            AzEl future = sat;
            while (step > 0.25) {
                future = pass.at(now + delta);
                const bool too_far = future.el < 0.0 || std::fabs(sat.az - future.az) > threshold ||
                                     std::fabs(sat.el - future.el) > threshold;
                delta += too_far ? -step : step;
                step /= 2.0;
            }
            const AzEl target{two_decimals(future.az), two_decimals(future.el)};
            predictor.observe(at(now), target, dish);
            dish = target;
            ++run.targets;
        }
        if (run.targets < 3) {
            continue;
        }
        ++run.seconds_measured;
        run.seconds_on_pass_model += predictor.pass_model_in_use() ? 1 : 0;
        for (const double ahead : aheads) {
            if (now + ahead > end || pass.at(now + ahead).el < 0.0) {
                continue;
            }
            const auto predicted = predictor.predict(at(now + ahead));
            REQUIRE(predicted.has_value());
            run.errors[ahead].add(sky_angle(predicted->position, pass.at(now + ahead)));
        }
    }
    return run;
}

const char* const pass_names[] = {"iss-20", "iss-45", "iss-70", "iss-85", "sso-20", "sso-45", "sso-70", "sso-85"};

}  // namespace

TEST_CASE("pass model: Gpredict-like targets on the SGP4 passes are predicted further ahead than by the local estimate") {
    // Measured when written (RMS 30 s ahead, mean of the 8 passes): at 5 deg 4.6 against the local
    // estimate's 7.0. At 0.5 deg a target comes every few seconds, so both stop extrapolating
    // after the same 10 s horizon and 15 or 30 s ahead compare the horizon more than the models;
    // 5 s ahead the local estimate is better on five passes (docs/tracking.md §6).
    struct Bound {
        double threshold;
        double mean_30s_fraction;   // of the local estimate's
    };
    for (const Bound bound : {Bound{5.0, 0.75}, Bound{0.5, 1.0}}) {
        double linear_sum = 0.0, model_sum = 0.0;
        for (const char* name : pass_names) {
            const TruePass pass = TruePass::load(name);
            const PassRun model = run_client(pass, bound.threshold, true);
            const PassRun linear = run_client(pass, bound.threshold, false);
            char line[400];
            std::snprintf(line, sizeof line,
                          "threshold %.1f %-7s targets %3d, on the model %3.0f%% | pass model RMS/max 5 s %.2f/%.2f 15 s %.2f/%.2f 30 s "
                          "%.2f/%.2f | linear 5 s %.2f/%.2f 15 s %.2f/%.2f 30 s %.2f/%.2f",
                          bound.threshold, name, model.targets,
                          100.0 * model.seconds_on_pass_model / std::max(1, model.seconds_measured), model.errors.at(5).rms(), model.errors.at(5).max,
                          model.errors.at(15).rms(), model.errors.at(15).max, model.errors.at(30).rms(),
                          model.errors.at(30).max, linear.errors.at(5).rms(), linear.errors.at(5).max,
                          linear.errors.at(15).rms(), linear.errors.at(15).max, linear.errors.at(30).rms(),
                          linear.errors.at(30).max);
            std::printf("%s\n", line);
            INFO(line);
            // Never worse than the local estimate by more than a hair on any pass.
            CHECK(model.errors.at(30).rms() < linear.errors.at(30).rms() + 0.1);
            CHECK(model.errors.at(15).rms() < linear.errors.at(15).rms() + 0.1);
            linear_sum += linear.errors.at(30).rms();
            model_sum += model.errors.at(30).rms();
        }
        INFO("threshold " << bound.threshold << ": mean 30 s RMS, pass model " << model_sum / 8 << ", linear "
                          << linear_sum / 8);
        CHECK(model_sum < bound.mean_30s_fraction * linear_sum);
    }
}

namespace {

// A straight flyby at 600 km closest distance and 7.5 km/s, as unit vectors: on a great circle
// through the zenith's side, with the rate peaking at t = 0.
AzEl flyby(double t) {
    const double along = std::atan(7.5 * t / 600.0);
    // The circle: tilted 30 deg from the zenith towards the east, running north to south.
    const double d = M_PI / 180.0;
    const double tilt = 30.0 * d;
    const double x = std::cos(along) * std::sin(tilt), y = std::sin(along), z = std::cos(along) * std::cos(tilt);
    return {normalize_azimuth(std::atan2(x, y) / d), std::atan2(z, std::hypot(x, y)) / d};
}

}  // namespace

TEST_CASE("pass model: a flyby's targets are fitted exactly, through the culmination") {
    PassModel model;
    for (double t = -120.0; t <= -40.0; t += 10.0) {
        model.add(t, flyby(t));
    }
    REQUIRE(model.fit(std::nullopt));
    INFO(model.describe());
    for (const double t : {-30.0, 0.0, 30.0, 60.0}) {
        const auto p = model.predict(t);
        REQUIRE(p.has_value());
        CHECK(sky_angle(p->position, flyby(t)) < 0.05);
    }
}

TEST_CASE("pass model: too few or scattered targets are refused") {
    PassModel model;
    SECTION("a single target") {
        model.add(0.0, {120.0, 30.0});
        CHECK_FALSE(model.fit(std::nullopt));
        CHECK_FALSE(model.predict(10.0).has_value());
    }
    SECTION("manual pointing back and forth") {
        const AzEl points[] = {{100, 20}, {140, 40}, {110, 25}, {180, 10}, {90, 60}, {130, 30}};
        double t = 0.0;
        for (const AzEl p : points) {
            model.add(t, p);
            t += 20.0;
        }
        CHECK_FALSE(model.fit(std::nullopt));
        INFO(model.describe());
    }
}

TEST_CASE("pass model: the predictor falls back for a single P, a jump and a stop") {
    PredictorSettings with_pass_model;
    with_pass_model.use_pass_model = true;
    TargetPredictor predictor(with_pass_model);
    // A pass followed by targets every 10 s: the pass model takes over.
    for (double t = -120.0; t <= -40.0; t += 10.0) {
        predictor.observe(at(t), flyby(t), std::nullopt);
    }
    REQUIRE(predictor.pass_model_in_use());
    CHECK(sky_angle(predictor.predict(at(-10.0))->position, flyby(-10.0)) < 0.1);

    SECTION("a jump (another satellite, a manual P) drops the pass model and holds the new target") {
        const AzEl elsewhere{300.0, 10.0};
        predictor.observe(at(-35.0), elsewhere, std::nullopt);
        CHECK_FALSE(predictor.pass_model_in_use());
        const auto p = predictor.predict(at(0.0));
        REQUIRE(p.has_value());
        CHECK_FALSE(p->moving);
        CHECK(sky_angle(p->position, elsewhere) < 0.01);
    }
    SECTION("a stop forgets the pass") {
        predictor.reset();
        CHECK_FALSE(predictor.pass_model_in_use());
        CHECK_FALSE(predictor.predict(at(0.0)).has_value());
        SECTION("and a single P after it is held") {
            predictor.observe(at(1.0), {45.0, 45.0}, std::nullopt);
            const auto p = predictor.predict(at(30.0));
            REQUIRE(p.has_value());
            CHECK_FALSE(p->moving);
            CHECK(sky_angle(p->position, {45.0, 45.0}) < 0.01);
        }
    }
}
