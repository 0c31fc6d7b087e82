// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// TargetPredictor (predictive pointing) on synthetic target streams with explicit times: steady and
// curved motion, Gpredict-like lead targets, stops, restarts, the azimuth wrap and bad input.
// Pure and deterministic: no threads, no sleeping, every time is a Clock::time_point built here.
// Over 500 lines: one case per kind of target stream the estimator must survive, each self-contained.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "base/azel.hpp"
#include "error_stats.hpp"
#include "tracking/pointing.hpp"

using namespace birdcage;

namespace {

// An arbitrary origin well away from the clock's epoch.
const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1000);

Clock::time_point at(double seconds) {
    return t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// These streams move linearly in az/el, which no satellite pass does: they test the local estimate
// on its own. The pass model is tested on SGP4 passes (test_pass_model.cpp).
PredictorSettings local_only() {
    PredictorSettings settings;
    settings.use_pass_model = false;
    return settings;
}

// For the cases about the extrapolation itself (the restart gate, the north crossing): no wait
// for an established track (a young one stops at its last target, tested in test_steering.cpp).
PredictorSettings extrapolating_at_once() {
    PredictorSettings settings = local_only();
    settings.established_track_targets = 0;
    settings.established_track_s = 0.0;
    return settings;
}

// Targets go over the wire as "P %.2f %.2f".
double two_decimals(double x) {
    return std::round(x * 100.0) / 100.0;
}

double az_error(double a, double b) {
    return std::fabs(azimuth_difference(a, b));
}

// Per-axis error (Gpredict's threshold box is per axis).
double box_error(AzEl a, AzEl b) {
    return std::max(az_error(a.az, b.az), std::fabs(a.el - b.el));
}

struct Linear {
    double az0, el0, az_rate, el_rate;
    AzEl at(double t) const { return {normalize_azimuth(az0 + az_rate * t), el0 + el_rate * t}; }
};

Prediction must_predict(const TargetPredictor& predictor, double t) {
    const auto p = predictor.predict(at(t));
    REQUIRE(p.has_value());
    return *p;
}

// A Gpredict-like client (gtk-rot-ctrl.c, testbed/gpredict_client.cpp) in closed loop with a naive
// dish that jumps to each target: every `cycle_s` it compares the satellite with the dish it reads
// back and, when either axis is more than `threshold` off, sends the satellite's position at the
// edge of the threshold ahead (a binary search down to a quarter cycle), rounded to two decimals.
struct GpredictRun {
    std::function<AzEl(double)> satellite;
    double threshold = 5.0;
    double cycle_s = 1.0;
    double start_s = 0.3;
    AzEl dish{0.0, 0.0};  // parked away from the satellite: the first tick fires
    // The dish's elevation floor: a client set up wider than the dish reads a dish held there.
    double dish_el_min = -90.0;
    std::vector<double> sent_at;
    AzEl last_target{};

    AzEl lead_target(double now) const {
        const AzEl current = satellite(now);
        double time_delta = 120.0;  // search horizon (Gpredict: until LOS)
        double step = std::max(time_delta / 2.0, cycle_s);
        AzEl future = current;
        while (step > cycle_s / 4.0) {
            future = satellite(now + time_delta);
            const bool too_far =
                az_error(current.az, future.az) > threshold || std::fabs(current.el - future.el) > threshold;
            time_delta += too_far ? -step : step;
            step /= 2.0;
        }
        return future;
    }

    // One timer tick at `now`: returns true when a target went out (and the dish jumped to it).
    bool tick(double now, TargetPredictor& predictor) {
        const AzEl sat = satellite(now);
        if (az_error(sat.az, dish.az) <= threshold && std::fabs(sat.el - dish.el) <= threshold) {
            return false;
        }
        const AzEl ahead = lead_target(now);
        const AzEl target{two_decimals(ahead.az), two_decimals(ahead.el)};
        predictor.observe(at(now), target, dish);
        dish = {target.az, std::max(target.el, dish_el_min)};
        last_target = target;
        sent_at.push_back(now);
        return true;
    }
};

using Errors = birdcage::test::ErrorStats;

}  // namespace

TEST_CASE("pointing: steady linear motion without a lead is extrapolated with the right rates") {
    const Linear sat{100.0, 20.0, 0.5, 0.3};
    TargetPredictor predictor(local_only());
    const bool with_dish = GENERATE(false, true);
    INFO((with_dish ? "dish reported on the satellite" : "no dish reported"));
    for (int k = 0; k <= 20; ++k) {
        const double t = k;
        // A dish that tracks perfectly shows no gap, so no client lead can be inferred.
        predictor.observe(at(t), sat.at(t), with_dish ? std::optional<AzEl>(sat.at(t)) : std::nullopt);
    }
    CHECK_FALSE(predictor.lead_threshold_deg().has_value());

    for (const double ahead : {0.0, 1.5, 3.0, 5.0}) {
        INFO("seconds past the last target: " << ahead);
        const double t = 20.0 + ahead;
        const Prediction p = must_predict(predictor, t);
        CHECK(p.moving);
        CHECK(p.position.az == Approx(sat.at(t).az).margin(0.01));
        CHECK(p.position.el == Approx(sat.at(t).el).margin(0.01));
        CHECK(p.az_rate == Approx(0.5).margin(0.002));
        CHECK(p.el_rate == Approx(0.3).margin(0.002));
    }
}

TEST_CASE("pointing: two-decimal targets from a regular client still give the rates") {
    // Rates that are not multiples of 0.01 deg/s, so every target carries rounding noise.
    const Linear sat{250.0, 62.0, -0.737, -0.213};
    TargetPredictor predictor(local_only());
    for (int k = 0; k <= 30; ++k) {
        const AzEl s = sat.at(k);
        predictor.observe(at(k), {two_decimals(s.az), two_decimals(s.el)}, std::nullopt);
    }
    const Prediction p = must_predict(predictor, 33.0);
    CHECK(p.moving);
    CHECK(p.az_rate == Approx(-0.737).margin(0.005));
    CHECK(p.el_rate == Approx(-0.213).margin(0.005));
    CHECK(az_error(p.position.az, sat.at(33.0).az) < 0.03);
    CHECK(std::fabs(p.position.el - sat.at(33.0).el) < 0.03);
}

TEST_CASE("pointing: Gpredict-like lead targets: the lead is learned and the prediction sits on the satellite") {
    struct Case {
        const char* legend;
        Linear sat;
        double threshold;
        // Required gain: predicted RMS below this fraction of the last target's RMS, and the
        // predicted max below this fraction of the threshold.
        double rms_fraction;
        double max_fraction;
    };
    const Case cases[] = {
        {"default 5 deg threshold, rising", {100.0, 15.0, 0.5, 0.15}, 5.0, 0.15, 0.1},
        {"2 deg threshold, rising", {100.0, 15.0, 0.5, 0.15}, 2.0, 0.15, 0.1},
        {"2 deg threshold, crossing north", {340.0, 20.0, 0.4, 0.1}, 2.0, 0.15, 0.1},
        {"1 deg threshold, elevation-led, falling", {30.0, 60.0, -0.12, -0.2}, 1.0, 0.2, 0.15},
        // A threshold of barely three cycles of motion: the client fires only on its 1 s ticks,
        // so every firing interval is 3 s (2.5 s of lead and threshold, rounded up) and its lead
        // search stops at 0.94 s (0.375 deg). The lead learned from the interval (0.6 deg, 1.5 s)
        // is then 0.56 s too long and the estimate trails by ~0.22 deg: better than the last
        // target, not by much (docs/tracking.md 3.3 finding 5: little to gain at 0.5 deg).
        {"0.5 deg threshold, three cycles of motion, crossing north", {340.0, 20.0, 0.4, 0.1}, 0.5, 0.7, 0.6},
    };
    for (const auto& c : cases) {
        INFO(c.legend);
        TargetPredictor predictor(local_only());
        GpredictRun client;
        client.satellite = [&](double t) { return c.sat.at(t); };
        client.threshold = c.threshold;
        Errors predicted, naive;
        const double end_s = 300.0;
        for (double t = client.start_s; t < end_s; t += client.cycle_s) {
            client.tick(t, predictor);
            if (t < 120.0) {
                continue;  // let the estimator converge
            }
            // Compare at four instants per cycle, as a dish steered from the estimate would see it.
            for (double dt = 0.0; dt < client.cycle_s; dt += 0.25) {
                const AzEl truth = c.sat.at(t + dt);
                const Prediction p = must_predict(predictor, t + dt);
                CHECK(p.moving);
                predicted.add(box_error(p.position, truth));
                naive.add(box_error(client.last_target, truth));
            }
        }
        INFO("targets sent: " << client.sent_at.size() << "; learned threshold "
                              << predictor.lead_threshold_deg().value_or(-1.0) << "; predicted RMS " << predicted.rms()
                              << " max " << predicted.max << "; last-target RMS " << naive.rms() << " max "
                              << naive.max);
        // The client really is a threshold client: the naive error sweeps up to the threshold.
        REQUIRE(client.sent_at.size() >= 8);
        REQUIRE(naive.max > 0.9 * c.threshold);

        REQUIRE(predictor.lead_threshold_deg().has_value());
        CHECK(*predictor.lead_threshold_deg() == Approx(c.threshold).epsilon(0.3));
        CHECK(predicted.rms() < c.rms_fraction * naive.rms());
        CHECK(predicted.max < c.max_fraction * c.threshold);
        const Prediction p = must_predict(predictor, end_s);
        const double dominant = std::max(std::fabs(c.sat.az_rate), std::fabs(c.sat.el_rate));
        CHECK(std::max(std::fabs(p.az_rate - c.sat.az_rate), std::fabs(p.el_rate - c.sat.el_rate)) < 0.05 * dominant);
    }
}

TEST_CASE("pointing: a dish held on its floor: the lead is read from the client's rule against the floor") {
    // Gpredict with limits 0-90 and a dish whose floor is 18 deg (the real loop's iss-45 at 5 deg,
    // docs/tracking.md §5): while the satellite climbs from 8 to 13 deg it sends a target every
    // cycle, below the floor; then the dish, held at 18, is within the threshold on both axes and it
    // is silent for a minute, until the azimuth has moved 5 deg past the dish. That first target
    // after the silence is 10 deg in azimuth and 8 in elevation from the dish on its floor: the
    // client's rule gives its lead of 5 from it, the dish being off the track.
    const Linear sat{300.0, 8.0, 0.16, 0.14};
    TargetPredictor predictor(local_only());
    predictor.set_dish_limits(18.0, 65.0);
    GpredictRun client;
    client.satellite = [&](double t) { return sat.at(t); };
    client.dish = {300.0, 18.0};
    client.dish_el_min = 18.0;
    double resumed_at = -1.0;
    for (double t = client.start_s; t < 120.0 && resumed_at < 0.0; t += client.cycle_s) {
        const bool silent = !client.sent_at.empty() && t - client.sent_at.back() > 1.5 * client.cycle_s;
        if (client.tick(t, predictor) && silent) {
            resumed_at = t;
        }
        if (resumed_at < 0.0) {
            // Below the floor and on it, nothing tells the lead.
            REQUIRE_FALSE(predictor.lead_threshold_deg().has_value());
        }
    }
    INFO("first target after the silence at " << resumed_at << " s: " << client.last_target.az << ", "
                                              << client.last_target.el);
    REQUIRE(resumed_at > 90.0);
    REQUIRE(client.last_target.el > 20.0);
    REQUIRE(predictor.lead_threshold_deg().has_value());
    CHECK(*predictor.lead_threshold_deg() == Approx(5.0).margin(0.3));
}

TEST_CASE("pointing: a curved azimuth is followed better than a straight line through the last two targets") {
    auto az_of = [](double t) { return 100.0 + 0.3 * t + 0.01 * t * t; };
    auto el_of = [](double t) { return 40.0 + 0.1 * t; };
    TargetPredictor predictor(local_only());
    for (int k = 0; k <= 20; ++k) {
        predictor.observe(at(k), {az_of(k), el_of(k)}, std::nullopt);
    }
    const double t = 23.0;
    const Prediction p = must_predict(predictor, t);
    const double line = az_of(20) + (az_of(20) - az_of(19)) * (t - 20.0);
    const double line_error = std::fabs(line - az_of(t));
    const double predicted_error = az_error(p.position.az, az_of(t));
    INFO("predicted error " << predicted_error << ", straight-line error " << line_error);
    REQUIRE(line_error > 0.1);  // the curvature is large enough to tell the two apart
    CHECK(predicted_error < 0.25 * line_error);
    CHECK(p.az_rate == Approx(0.3 + 0.02 * t).margin(0.01));  // d/dt of the parabola at t
    CHECK(p.el_rate == Approx(0.1).margin(0.002));
    CHECK(p.position.el == Approx(el_of(t)).margin(0.01));
}

TEST_CASE("pointing: repeated identical targets hold, with no overshoot") {
    const Linear sat{150.0, 30.0, 0.5, 0.3};
    TargetPredictor predictor(local_only());

    SECTION("a moving stream that stops") {
        // 20 s of targets: an established track (a shorter one stops at its last target anyway).
        for (int k = 0; k <= 20; ++k) {
            predictor.observe(at(k), sat.at(k), std::nullopt);
        }
        REQUIRE(must_predict(predictor, 20.5).moving);
        const AzEl last = sat.at(20);
        for (int k = 21; k <= 24; ++k) {
            predictor.observe(at(k), last, std::nullopt);
            for (const double t : {double(k), k + 0.5, k + 30.0}) {
                INFO("repeat at " << k << " s, predicted at " << t << " s");
                const Prediction p = must_predict(predictor, t);
                CHECK_FALSE(p.moving);
                CHECK(p.position.az == Approx(last.az).margin(1e-9));
                CHECK(p.position.el == Approx(last.el).margin(1e-9));
                CHECK(p.az_rate == 0.0);
                CHECK(p.el_rate == 0.0);
            }
        }
    }
    SECTION("a client that only ever sends one position") {
        const AzEl park{210.25, 45.5};
        for (int k = 0; k < 5; ++k) {
            predictor.observe(at(k), park, park);
        }
        for (const double t : {4.0, 10.0, 1000.0}) {
            const Prediction p = must_predict(predictor, t);
            CHECK_FALSE(p.moving);
            CHECK(p.position.az == Approx(park.az).margin(1e-9));
            CHECK(p.position.el == Approx(park.el).margin(1e-9));
        }
    }
    SECTION("a held target followed by a new motion starts a fresh estimate") {
        const AzEl park{210.0, 45.0};
        predictor.observe(at(0), park, std::nullopt);
        predictor.observe(at(1), park, std::nullopt);
        // The client starts moving again, from the held position.
        for (int k = 2; k <= 24; ++k) {
            predictor.observe(at(k), {park.az + 0.4 * (k - 1), park.el}, std::nullopt);
        }
        const Prediction p = must_predict(predictor, 26.0);
        CHECK(p.moving);
        CHECK(p.az_rate == Approx(0.4).margin(0.005));
        CHECK(p.position.az == Approx(park.az + 0.4 * 25).margin(0.02));
    }
}

TEST_CASE("pointing: the extrapolation stops at the horizon after the last moving target") {
    // Slow in elevation, so that 330 s of it stays below the zenith guard.
    const Linear sat{150.0, 30.0, 0.5, 0.05};
    struct Case {
        double interval_s;
        double horizon_s;  // extrapolate_intervals x interval, clamped to [min, max]
    };
    const PredictorSettings defaults = local_only();
    // 1 s: 3 s, clamped up to the 10 s minimum; 5 s: 15 s; 40 s: 120 s, clamped down to 90 s.
    const Case cases[] = {{1.0, defaults.min_extrapolation_s}, {5.0, 15.0}, {40.0, defaults.max_extrapolation_s}};
    for (const auto& c : cases) {
        INFO("targets every " << c.interval_s << " s");
        TargetPredictor predictor(local_only());
        double last = 0.0;
        // An established track: at least four targets over at least 20 s.
        const int targets = std::max(6, static_cast<int>(std::ceil(local_only().established_track_s / c.interval_s)));
        for (int k = 0; k <= targets; ++k) {
            last = k * c.interval_s;
            predictor.observe(at(last), sat.at(last), std::nullopt);
        }
        const Prediction before = must_predict(predictor, last + c.horizon_s - 0.5);
        CHECK(before.moving);
        CHECK(before.position.az == Approx(sat.at(last + c.horizon_s - 0.5).az).margin(0.01));

        const Prediction expired = must_predict(predictor, last + c.horizon_s + 0.5);
        const Prediction much_later = must_predict(predictor, last + c.horizon_s + 500.0);
        CHECK_FALSE(expired.moving);
        CHECK_FALSE(much_later.moving);
        CHECK(expired.az_rate == 0.0);
        CHECK(expired.el_rate == 0.0);
        // Held where the extrapolation ended, not carried on and not snapped back.
        CHECK(expired.position.az == Approx(sat.at(last + c.horizon_s).az).margin(0.01));
        CHECK(expired.position.el == Approx(sat.at(last + c.horizon_s).el).margin(0.01));
        CHECK(much_later.position.az == expired.position.az);
        CHECK(much_later.position.el == expired.position.el);
    }
}

TEST_CASE("pointing: a target far from the prediction restarts the estimate") {
    const Linear sat{150.0, 30.0, 0.5, 0.3};
    const PredictorSettings settings = extrapolating_at_once();
    TargetPredictor predictor(settings);
    for (int k = 0; k <= 10; ++k) {
        predictor.observe(at(k), sat.at(k), std::nullopt);
    }
    REQUIRE(must_predict(predictor, 11.0).moving);

    SECTION("the client parks far away") {
        const AzEl park{0.0, 90.0};
        predictor.observe(at(11), park, std::nullopt);
        for (const double t : {11.0, 12.0, 60.0}) {
            const Prediction p = must_predict(predictor, t);
            CHECK_FALSE(p.moving);
            CHECK(p.position.az == Approx(park.az).margin(1e-9));
            CHECK(p.position.el == Approx(park.el).margin(1e-9));
        }
    }
    SECTION("the client switches satellite: only the new one's targets shape the estimate") {
        const Linear other{40.0, 50.0, -0.2, 0.1};
        // Just past the gate on azimuth alone (the prediction at 11 s is 155.5).
        const Linear next{sat.at(11).az + settings.restart_gate_deg + 5.0, sat.at(11).el, 0.0, 0.0};
        SECTION("far on both axes") {
            predictor.observe(at(11), other.at(11), std::nullopt);
            Prediction p = must_predict(predictor, 11.5);
            CHECK_FALSE(p.moving);
            CHECK(p.position.az == Approx(other.at(11).az).margin(1e-9));
            CHECK(p.position.el == Approx(other.at(11).el).margin(1e-9));
            for (int k = 12; k <= 16; ++k) {
                predictor.observe(at(k), other.at(k), std::nullopt);
            }
            p = must_predict(predictor, 18.0);
            CHECK(p.moving);
            CHECK(p.az_rate == Approx(-0.2).margin(0.002));
            CHECK(p.el_rate == Approx(0.1).margin(0.002));
            CHECK(p.position.az == Approx(other.at(18).az).margin(0.01));
            CHECK(p.position.el == Approx(other.at(18).el).margin(0.01));
        }
        SECTION("far on azimuth only") {
            predictor.observe(at(11), next.at(0), std::nullopt);
            const Prediction p = must_predict(predictor, 13.0);
            CHECK_FALSE(p.moving);
            CHECK(p.position.az == Approx(next.at(0).az).margin(1e-9));
            CHECK(p.position.el == Approx(next.at(0).el).margin(1e-9));
        }
    }
    SECTION("a target off by less than the gate does not restart") {
        predictor.observe(at(11), {sat.at(11).az + 3.0, sat.at(11).el}, std::nullopt);
        const Prediction p = must_predict(predictor, 11.5);
        CHECK(p.moving);
        CHECK(p.az_rate > 0.3);
    }
}

TEST_CASE("pointing: azimuth crossing north keeps a continuous, positive rate") {
    TargetPredictor predictor(extrapolating_at_once());
    SECTION("clockwise through 0, extrapolated across 0") {
        // 356, 356.5, ..., 359.5: the extrapolation crosses north on its own.
        for (int k = 0; k <= 7; ++k) {
            predictor.observe(at(k), {356.0 + 0.5 * k, 40.0}, std::nullopt);
        }
        double previous = must_predict(predictor, 7.0).position.az;
        for (double t = 7.1; t < 12.0; t += 0.1) {
            const Prediction p = must_predict(predictor, t);
            INFO("t = " << t << " az " << p.position.az);
            CHECK(p.position.az >= 0.0);
            CHECK(p.position.az < 360.0);
            CHECK(p.az_rate == Approx(0.5).margin(0.002));
            const double step = azimuth_difference(previous, p.position.az);
            CHECK(step == Approx(0.05).margin(0.002));
            previous = p.position.az;
        }
        CHECK(must_predict(predictor, 9.0).position.az == Approx(0.5).margin(0.01));
    }
    SECTION("clockwise targets through 0 (358, 358.5, ..., 0, 0.5, ...)") {
        for (int k = 0; k <= 10; ++k) {
            predictor.observe(at(k), {normalize_azimuth(358.0 + 0.5 * k), 40.0}, std::nullopt);
        }
        // The last target is 3.0.
        const Prediction p = must_predict(predictor, 13.0);
        CHECK(p.az_rate == Approx(0.5).margin(0.002));
        CHECK(p.position.az == Approx(4.5).margin(0.01));
    }
    SECTION("a 0..360 client that sends 360.00 on the way") {
        for (int k = 0; k <= 8; ++k) {
            const double az = 358.0 + 0.5 * k;  // 358 ... 360.0 ... 362 sent as 0 ... 2
            predictor.observe(at(k), {az > 360.0 ? az - 360.0 : az, 40.0}, std::nullopt);
        }
        const Prediction p = must_predict(predictor, 10.0);
        CHECK(p.az_rate == Approx(0.5).margin(0.002));
        CHECK(p.position.az == Approx(3.0).margin(0.01));
    }
    SECTION("counter-clockwise through 0") {
        for (int k = 0; k <= 10; ++k) {
            predictor.observe(at(k), {normalize_azimuth(2.0 - 0.5 * k), 40.0}, std::nullopt);
        }
        // The last target is 357.0.
        const Prediction p = must_predict(predictor, 13.0);
        CHECK(p.az_rate == Approx(-0.5).margin(0.002));
        CHECK(p.position.az == Approx(355.5).margin(0.01));
        CHECK(p.position.az < 360.0);
    }
    SECTION("a -180..180 client crossing south") {
        // 178, 178.5, ..., 180, -179.5, ..., -177
        for (int k = 0; k <= 10; ++k) {
            const double az = 178.0 + 0.5 * k;
            predictor.observe(at(k), {az > 180.0 ? az - 360.0 : az, 40.0}, std::nullopt);
        }
        const Prediction p = must_predict(predictor, 12.0);
        CHECK(p.az_rate == Approx(0.5).margin(0.002));
        CHECK(p.position.az == Approx(184.0).margin(0.01));
    }
}

TEST_CASE("pointing: above the zenith guard the azimuth is extrapolated briefly, the elevation on") {
    const PredictorSettings settings = extrapolating_at_once();
    TargetPredictor predictor(settings);
    const Linear sat{200.0, 80.0, 3.0, 0.2};  // a keyhole pass: fast azimuth high up
    for (int k = 0; k <= 5; ++k) {
        predictor.observe(at(k), sat.at(k), std::nullopt);
    }
    const double guard = settings.zenith_extrapolation_s;
    const Prediction early = must_predict(predictor, 5.0 + 0.5 * guard);
    CHECK(early.position.az == Approx(sat.at(5.0 + 0.5 * guard).az).margin(0.01));
    CHECK(early.az_rate == Approx(3.0).margin(0.01));
    const Prediction late = must_predict(predictor, 5.0 + guard + 3.0);
    CHECK(late.moving);
    CHECK(late.az_rate == 0.0);
    CHECK(late.position.az == Approx(sat.at(5.0 + guard).az).margin(0.01));
    CHECK(late.position.el == Approx(sat.at(5.0 + guard + 3.0).el).margin(0.01));
    CHECK(late.el_rate == Approx(0.2).margin(0.002));
}

TEST_CASE("pointing: non-finite targets are ignored") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const AzEl garbage[] = {{nan, 30.0}, {100.0, nan}, {inf, 30.0}, {100.0, -inf}, {nan, nan}};
    TargetPredictor predictor(extrapolating_at_once());

    SECTION("before any target: still nothing to predict") {
        for (const auto& g : garbage) {
            predictor.observe(at(0), g, std::nullopt);
        }
        CHECK_FALSE(predictor.predict(at(1)).has_value());
        // The first real target is then taken as it is.
        predictor.observe(at(2), {123.0, 45.0}, std::nullopt);
        const Prediction p = must_predict(predictor, 3.0);
        CHECK(p.position.az == 123.0);
        CHECK(p.position.el == 45.0);
    }
    SECTION("in a moving stream: the prediction is unchanged and the stream goes on") {
        const Linear sat{100.0, 20.0, 0.5, 0.3};
        for (int k = 0; k <= 10; ++k) {
            predictor.observe(at(k), sat.at(k), std::nullopt);
        }
        const Prediction before = must_predict(predictor, 11.5);
        for (const auto& g : garbage) {
            predictor.observe(at(11), g, AzEl{nan, nan});
        }
        const Prediction after = must_predict(predictor, 11.5);
        CHECK(after.moving == before.moving);
        CHECK(after.position.az == before.position.az);
        CHECK(after.position.el == before.position.el);
        CHECK(after.az_rate == before.az_rate);
        CHECK(after.el_rate == before.el_rate);
        CHECK_FALSE(predictor.lead_threshold_deg().has_value());
        predictor.observe(at(12), sat.at(12), std::nullopt);
        const Prediction later = must_predict(predictor, 14.0);
        CHECK(later.moving);
        CHECK(later.position.az == Approx(sat.at(14).az).margin(0.01));
        CHECK(later.az_rate == Approx(0.5).margin(0.002));
    }
}

TEST_CASE("pointing: reset() forgets the stream") {
    const Linear sat{100.0, 20.0, 0.5, 0.3};
    TargetPredictor predictor(extrapolating_at_once());
    for (int k = 0; k <= 10; ++k) {
        predictor.observe(at(k), sat.at(k), std::nullopt);
    }
    REQUIRE(predictor.predict(at(11)).has_value());
    predictor.reset();
    CHECK_FALSE(predictor.predict(at(11)).has_value());
    CHECK_FALSE(predictor.predict(at(1000)).has_value());
    CHECK(predictor.describe() == "no target yet");

    // A new stream elsewhere: the first two targets hold (two steps are no track yet), the third
    // gives a rate of its own.
    const Linear other{300.0, 50.0, -0.25, -0.1};
    predictor.observe(at(20), other.at(20), std::nullopt);
    Prediction p = must_predict(predictor, 21.0);
    CHECK_FALSE(p.moving);
    CHECK(p.position.az == Approx(other.at(20).az).margin(1e-9));
    predictor.observe(at(21), other.at(21), std::nullopt);
    CHECK_FALSE(must_predict(predictor, 21.5).moving);
    predictor.observe(at(22), other.at(22), std::nullopt);
    p = must_predict(predictor, 23.0);
    CHECK(p.moving);
    CHECK(p.az_rate == Approx(-0.25).margin(0.002));
    CHECK(p.position.az == Approx(other.at(23).az).margin(0.01));
}

TEST_CASE("pointing: reset() forgets the learned lead and a held stop") {
    // Regression: reset() once cleared the samples and rates but kept the learned lead and the
    // held flag, so a lead-free client after a stop was tracked a whole lead behind.
    TargetPredictor predictor(extrapolating_at_once());
    SECTION("the learned lead") {
        const Linear sat{100.0, 15.0, 0.5, 0.15};
        GpredictRun client;
        client.satellite = [&](double t) { return sat.at(t); };
        client.threshold = 2.0;
        for (double t = client.start_s; t < 120.0; t += client.cycle_s) {
            client.tick(t, predictor);
        }
        REQUIRE(predictor.lead_threshold_deg().has_value());
        predictor.reset();
        CHECK_FALSE(predictor.lead_threshold_deg().has_value());
        // A new client without a lead (SatDump-like, a target every second, the dish on it):
        // a stale 2 deg lead would put the estimate 2 deg behind every target.
        const Linear other{200.0, 30.0, 0.5, 0.1};
        for (int k = 200; k <= 210; ++k) {
            predictor.observe(at(k), other.at(k), other.at(k));
        }
        const Prediction p = must_predict(predictor, 210.0);
        CHECK(p.position.az == Approx(other.at(210).az).margin(0.05));
    }
    SECTION("a held stop") {
        const AzEl park{210.0, 45.0};
        predictor.observe(at(0), park, std::nullopt);
        predictor.observe(at(1), park, std::nullopt);  // held
        predictor.reset();
        // After a reset three targets of a new motion give its rate, as on a fresh predictor.
        predictor.observe(at(10), {100.0, 20.0}, std::nullopt);
        predictor.observe(at(11), {100.5, 20.3}, std::nullopt);
        predictor.observe(at(12), {101.0, 20.6}, std::nullopt);
        const Prediction p = must_predict(predictor, 13.0);
        CHECK(p.moving);
        CHECK(p.az_rate == Approx(0.5).margin(0.002));
    }
}

TEST_CASE("pointing: mode names round-trip and unknown names are rejected") {
    for (const PointingMode mode : {PointingMode::none, PointingMode::leapfrog, PointingMode::predictive}) {
        const auto name = pointing_mode_name(mode);
        INFO(std::string(name));
        const auto back = pointing_mode_from_name(name);
        REQUIRE(back.has_value());
        CHECK(*back == mode);
    }
    CHECK(pointing_mode_name(PointingMode::none) == "none");
    CHECK(pointing_mode_name(PointingMode::leapfrog) == "leapfrog");
    CHECK(pointing_mode_name(PointingMode::predictive) == "predictive");
    for (const char* bad : {"", "Predictive", "PREDICTIVE", "predictive ", " none", "predict", "off", "leap-frog"}) {
        INFO("'" << bad << "'");
        CHECK_FALSE(pointing_mode_from_name(bad).has_value());
    }
}

TEST_CASE("pointing: two manual pointings a few seconds apart are not a satellite") {
    // Regression (the demo): P 180 45, then P 230 25 2.5 s later gave a "rate" of 20 deg/s and
    // the dish overshot the second target in elevation.
    TargetPredictor predictor(local_only());
    const auto t0 = Clock::time_point{} + std::chrono::seconds(100);
    predictor.observe(t0, {180.0, 45.0}, AzEl{180.0, 45.0});
    predictor.observe(t0 + std::chrono::milliseconds(2500), {230.0, 25.0}, AzEl{180.0, 45.0});
    for (int s : {3, 5, 20}) {
        const auto p = predictor.predict(t0 + std::chrono::seconds(s));
        REQUIRE(p.has_value());
        CHECK_FALSE(p->moving);
        CHECK(p->position.az == Approx(230.0).margin(1e-9));
        CHECK(p->position.el == Approx(25.0).margin(1e-9));
    }
    // A small manual nudge is not caught by the gate, but is too fast for a satellite.
    predictor.observe(t0 + std::chrono::seconds(4), {236.0, 25.0}, AzEl{230.0, 25.0});  // 5.4 deg in 1.5 s
    const auto nudged = predictor.predict(t0 + std::chrono::seconds(10));
    CHECK_FALSE(nudged->moving);
    CHECK(nudged->position.az == Approx(236.0).margin(1e-9));
}
