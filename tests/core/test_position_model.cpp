// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The position model between polls (position_model.hpp): a leg runs its axis along the variant's
// motion model; the latest reading places it on that curve and two readings time it.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "tracking/position_model.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

const Clock::time_point t0 = Clock::time_point{} + 1h;

LegMotion leg_from(Axis axis, double start, double to, Clock::time_point sent_at) {
    LegMotion leg;
    leg.axis = axis;
    leg.start = start;
    leg.to = to;
    leg.sent_at = sent_at;
    leg.latest = AxisReading{start, sent_at - 1ms};  // read just before it was sent
    return leg;
}

MovingAxes azimuth_only(const LegMotion& leg) {
    return MovingAxes{leg, std::nullopt};
}

}  // namespace

TEST_CASE("position model: no leg in flight, the reading, a leg, from its start to its target") {
    const FirmwareProfile& g2 = profile(VariantId::carryout_g2);
    const AzEl last{100, 30};
    CHECK(modelled_position(g2, last, MovingAxes{}, t0 + 10s).az == Approx(100));

    const auto leg = leg_from(Axis::azimuth, 100.0, 140.0, t0);
    const auto move = estimated_move_time(g2, Axis::azimuth, 40.0);
    REQUIRE(move > 0ms);
    CHECK(modelled_position(g2, last, azimuth_only(leg), t0).az == Approx(100));
    const AzEl half = modelled_position(g2, last, azimuth_only(leg), t0 + move / 2);
    CHECK(half.az == Approx(120).margin(0.1));  // symmetric profile: halfway at half time
    CHECK(half.el == Approx(30));               // the other axis does not move
    const AzEl quarter = modelled_position(g2, last, azimuth_only(leg), t0 + move / 4);
    CHECK(quarter.az < 110.0);  // still accelerating: less than a quarter of the way
    CHECK(modelled_position(g2, last, azimuth_only(leg), t0 + move * 3).az == Approx(140));
}

TEST_CASE("position model: the G2's trapezoid cruises at its table speed") {
    const FirmwareProfile& g2 = profile(VariantId::carryout_g2);
    // 130 deg of azimuth: 65 deg/s reached after 0.1625 s at 400 deg/s^2; one second in, cruising.
    const auto leg = leg_from(Axis::azimuth, 0.0, 130.0, t0);
    const double at_1s = modelled_axis(g2, leg, t0 + 1000ms);
    const double at_1_1s = modelled_axis(g2, leg, t0 + 1100ms);
    CHECK((at_1_1s - at_1s) / 0.1 == Approx(g2.az_speed_dps).epsilon(1e-6));
    CHECK(at_1s == Approx(0.5 * 65.0 * 65.0 / 400.0 + 65.0 * (1.0 - 65.0 / 400.0)).epsilon(1e-6));
}

TEST_CASE("position model: an azimuth leg across north takes the short way and wraps") {
    const FirmwareProfile& g2 = profile(VariantId::carryout_g2);
    const auto leg = leg_from(Axis::azimuth, 350.0, 10.0, t0);
    const auto move = estimated_move_time(g2, Axis::azimuth, 20.0);
    const double halfway = modelled_position(g2, AzEl{350, 30}, azimuth_only(leg), t0 + move / 2).az;
    CHECK(std::fabs(azimuth_difference(0.0, halfway)) < 0.1);  // at north, whichever side of 0/360
    CHECK(modelled_position(g2, AzEl{350, 30}, azimuth_only(leg), t0 + move).az == Approx(10));
}

TEST_CASE("position model: the latest reading places the axis on the leg's curve") {
    const FirmwareProfile& hal = profile(VariantId::travler_hal205);
    auto leg = leg_from(Axis::elevation, 30.0, 40.0, t0);
    const auto move = estimated_move_time(hal, Axis::elevation, 10.0);
    // Read at a quarter of the model's time but already halfway (the axis started early or runs
    // fast): from the reading on, the model runs the second half of the curve, not the first again.
    leg.latest = AxisReading{35.0, t0 + move / 4};
    CHECK(modelled_axis(hal, leg, t0 + move / 4) == Approx(35.0).margin(0.01));
    const double later = modelled_axis(hal, leg, t0 + move / 4 + 200ms);
    LegMotion fresh = leg_from(Axis::elevation, 30.0, 40.0, t0);
    const double model_half_plus = modelled_axis(hal, fresh, t0 + move / 2 + 200ms);
    CHECK(later == Approx(model_half_plus).margin(0.01));
    CHECK(modelled_axis(hal, leg, t0 + move * 2) == Approx(40.0));

    SECTION("a reading that shows no motion yet: the curve starts there") {
        leg.latest = AxisReading{30.0, t0 + 500ms};
        CHECK(modelled_axis(hal, leg, t0 + 500ms) == Approx(30.0));
        CHECK(modelled_axis(hal, leg, t0 + 500ms + move / 2) == Approx(35.0).margin(0.01));
    }
}

TEST_CASE("position model: two readings of one leg time the axis against the model") {
    const FirmwareProfile& hal = profile(VariantId::travler_hal205);
    const auto move = estimated_move_time(hal, Axis::azimuth, 20.0);
    LegMotion model = leg_from(Axis::azimuth, 100.0, 120.0, t0);
    auto model_at = [&](Clock::duration t) { return modelled_axis(hal, model, t0 + t); };
    // A dish that runs the model's curve at two thirds of its pace: readings at model times
    // 0.3 and 0.4 of the move arrive at 0.45 and 0.6 of it.
    LegMotion slow = model;
    slow.first_moving = AxisReading{model_at(move * 3 / 10), t0 + move * 45 / 100};
    slow.latest = AxisReading{model_at(move * 4 / 10), t0 + move * 60 / 100};
    const auto step = move / 10;  // a further 0.15 of real time is 0.1 of model time
    CHECK(modelled_axis(hal, slow, t0 + move * 60 / 100 + step * 3 / 2) == Approx(model_at(move / 2)).margin(0.02));

    SECTION("the last two readings, where far enough apart, give the pace where the axis is now") {
        // Started at the model's pace, slowed to two thirds of it since the previous reading.
        slow.first_moving = AxisReading{model_at(move * 1 / 10), t0 + move * 1 / 10};
        slow.previous = AxisReading{model_at(move * 3 / 10), t0 + move * 45 / 100};
        CHECK(modelled_axis(hal, slow, t0 + move * 60 / 100 + step * 3 / 2) == Approx(model_at(move / 2)).margin(0.02));
    }
    SECTION("an implausible pace is bounded") {
        slow.first_moving->at = t0 + move * 59 / 100;  // a tenth of the model's time for its distance
        const double bounded = modelled_axis(hal, slow, t0 + move * 60 / 100 + step);
        CHECK(bounded == Approx(model_at(move * 8 / 10)).margin(0.02));  // four times the model's pace at most
    }
    SECTION("readings too close together to time the axis leave the model's pace") {
        slow.first_moving = AxisReading{slow.latest.value - 0.05, t0 + move * 59 / 100};
        CHECK(modelled_axis(hal, slow, t0 + move * 60 / 100 + step) == Approx(model_at(move / 2)).margin(0.02));
    }
}

TEST_CASE("position model: both axes at once (one still covering its arrival tolerance)") {
    const FirmwareProfile& hal = profile(VariantId::travler_hal205);
    const auto az = leg_from(Axis::azimuth, 10.0, 12.0, t0);
    const auto el = leg_from(Axis::elevation, 20.0, 20.5, t0 - 1s);
    const AzEl p = modelled_position(hal, AzEl{10.0, 20.0}, MovingAxes{az, el}, t0 + 10s);
    CHECK(p.az == Approx(12.0));
    CHECK(p.el == Approx(20.5));
}

TEST_CASE("position model: a pace learnt on earlier legs times the next leg before its readings do") {
    const FirmwareProfile& hal = profile(VariantId::travler_hal205);
    const auto move = estimated_move_time(hal, Axis::elevation, 2.0);
    LegMotion leg = leg_from(Axis::elevation, 30.0, 32.0, t0);
    const double at_model_pace = modelled_axis(hal, leg, t0 + move / 2);
    CHECK(at_model_pace == Approx(31.0).margin(0.01));
    leg.pace = 0.5;  // this axis ran legs of this length at half the model's pace
    CHECK(modelled_axis(hal, leg, t0 + move) == Approx(31.0).margin(0.01));
    CHECK(observed_pace(hal, leg) == std::nullopt);  // no readings in the leg yet
}

TEST_CASE("position model: paces are learnt per axis and per leg length") {
    AxisPaces paces;
    CHECK(paces.pace(Axis::azimuth, 0.5) == 1.0);
    paces.learn(Axis::azimuth, 0.6, 0.5);
    CHECK(paces.pace(Axis::azimuth, 0.7) == Approx(0.5));  // same length class (0.5..1 deg)
    CHECK(paces.pace(Axis::azimuth, 3.0) == 1.0);          // another length
    CHECK(paces.pace(Axis::elevation, 0.7) == 1.0);        // another axis
    for (int legs = 0; legs < 30; ++legs) {
        paces.learn(Axis::azimuth, 0.6, 0.8);
    }
    CHECK(paces.pace(Axis::azimuth, 0.6) == Approx(0.8).margin(1e-3));  // follows the motor as it changes
}

namespace {

// A motor that starts `delay_s` after a command from rest, then runs a trapezoid (speed, accel):
// degrees covered `t` seconds after the command, on a move of `distance`.
struct DelayedMotor {
    double delay_s, speed, accel;
    double covered(double distance, double t) const {
        const double run = t - delay_s;
        if (run <= 0.0) {
            return 0.0;
        }
        const double ramp = std::min(speed / accel, std::sqrt(distance / accel));
        const double total = ramp * 2.0 + std::max(0.0, distance - accel * ramp * ramp) / speed;
        if (run >= total) {
            return distance;
        }
        if (run <= ramp) {
            return 0.5 * accel * run * run;
        }
        if (total - run <= ramp) {
            return distance - 0.5 * accel * (total - run) * (total - run);
        }
        return 0.5 * accel * ramp * ramp + accel * ramp * (run - ramp);
    }
};

// One leg read every 100 ms from `phase_s` after the send, readings rounded to 0.01 deg plus
// `noise` (deg, alternating sign): the delay the leg shows, if any, through StartupDelays::observed.
std::optional<double> leg_startup(const FirmwareProfile& dish, const DelayedMotor& motor, double distance,
                                  double phase_s, double noise) {
    LegMotion leg = leg_from(Axis::elevation, 20.0, 20.0 + distance, t0);
    std::optional<double> seen;
    for (int i = 0; i < 200 && !seen; ++i) {
        const double t = phase_s + 0.1 * i;
        const double wobble = (i % 2 == 0 ? noise : -noise);
        const double value = std::round((20.0 + motor.covered(distance, t) + wobble) * 100.0) / 100.0;
        add_reading(
            leg,
            AxisReading{value, t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t))});
        seen = StartupDelays::observed(dish, leg);
    }
    return seen;
}

}  // namespace

TEST_CASE("position model: start-up delays converge from a leg's own readings, whatever its length and phase") {
    const FirmwareProfile& hal205 = profile(VariantId::travler_hal205);
    // Motors meeting the documented Trav'ler timings in different ways (docs/firmware.md 3.4).
    const DelayedMotor motor = GENERATE(DelayedMotor{2.0, 8.0, 3.0}, DelayedMotor{0.0, 20.0, 2.0},
                                        DelayedMotor{1.0, 10.0, 20.0}, DelayedMotor{3.5, 12.0, 6.0});
    CAPTURE(motor.delay_s, motor.speed, motor.accel);
    const double latest_start_shown = std::sqrt(2.0 * 0.02 / motor.accel) + 0.1;
    StartupDelays delays;
    CHECK_FALSE(delays.learnt(Axis::elevation));
    CHECK(delays.delay(Axis::elevation, 0.25) == 0.25);  // the initial guess until a leg is timed
    const double distances[] = {0.5, 10.0, 2.0, 30.0, 1.0, 5.0, 0.3, 60.0};
    for (int i = 0; i < 8; ++i) {
        const auto observed = leg_startup(hal205, motor, distances[i], 0.013 * i, 0.0);
        REQUIRE(observed);
        // One leg alone places the start between the last reading that did not show the axis under
        // way and the first that did: up to 100 ms after the true start plus the time the motor
        // takes to cover the 0.02 deg that counts as under way (slow to accelerate, slow to show).
        CHECK(*observed >= motor.delay_s - 0.05);
        CHECK(*observed <= motor.delay_s + latest_start_shown);
        delays.learn(Axis::elevation, *observed);
    }
    CHECK(delays.learnt(Axis::elevation));
    CHECK(delays.delay(Axis::elevation) >= motor.delay_s - 0.05);
    CHECK(delays.delay(Axis::elevation) <= motor.delay_s + latest_start_shown);
    CHECK_FALSE(delays.learnt(Axis::azimuth));  // per axis
}

TEST_CASE("position model: a noisy reading or a late one moves a learnt start-up delay only part of the way") {
    const FirmwareProfile& hal205 = profile(VariantId::travler_hal205);
    const DelayedMotor motor{2.0, 8.0, 3.0};
    StartupDelays delays;
    for (int i = 0; i < 6; ++i) {
        const auto observed = leg_startup(hal205, motor, 10.0, 0.05, 0.004);  // below the 0.02 deg start
        REQUIRE(observed);
        delays.learn(Axis::azimuth, *observed);
    }
    CHECK(delays.delay(Axis::azimuth) == Approx(2.0).margin(0.12));
    // A reading held up for 3 s (a busy line): the leg shows a 5 s start; one such leg does not
    // make the motor a 5 s one, and an absurd one is bounded.
    delays.learn(Axis::azimuth, 5.0);
    CHECK(delays.delay(Axis::azimuth) < 3.2);
    delays.learn(Axis::azimuth, 1e6);
    CHECK(delays.delay(Axis::azimuth) < 6.0);
}

TEST_CASE("position model: readings before the axis started say nothing of the start, the first under way does") {
    const FirmwareProfile& hal205 = profile(VariantId::travler_hal205);
    LegMotion leg = leg_from(Axis::azimuth, 100.0, 110.0, t0);
    for (int i = 1; i <= 15; ++i) {  // 1.5 s of readings at the start position
        add_reading(leg, AxisReading{100.0, t0 + i * 100ms});
        CHECK_FALSE(StartupDelays::observed(hal205, leg));
    }
    add_reading(leg, AxisReading{100.05, t0 + 1600ms});
    const auto observed = StartupDelays::observed(hal205, leg);
    REQUIRE(observed);
    CHECK(*observed >= 1.5);  // not before the last reading that showed it unmoved
    CHECK(*observed <= 1.6);
    add_reading(leg, AxisReading{100.3, t0 + 1700ms});
    CHECK_FALSE(StartupDelays::observed(hal205, leg));  // timed once per leg
}

TEST_CASE("position model: a leg on a motor that starts late stays at its start until the learnt delay is over") {
    const FirmwareProfile& hal205 = profile(VariantId::travler_hal205);
    LegMotion leg = leg_from(Axis::azimuth, 100.0, 110.0, t0);
    const double undelayed_at_1s = modelled_axis(hal205, leg, t0 + 1s);
    CHECK(undelayed_at_1s > 100.1);  // without a delay the model has it moving a second in
    leg.startup_s = 2.0;
    CHECK(modelled_axis(hal205, leg, t0 + 1s) == Approx(100.0));
    CHECK(modelled_axis(hal205, leg, t0 + 3s) == Approx(undelayed_at_1s));
    // A reading still at the start 2.5 s in: the start is no earlier than that reading.
    add_reading(leg, AxisReading{100.0, t0 + 2500ms});
    CHECK(modelled_axis(hal205, leg, t0 + 2500ms) == Approx(100.0));
    CHECK(modelled_axis(hal205, leg, t0 + 3500ms) == Approx(undelayed_at_1s));
}
