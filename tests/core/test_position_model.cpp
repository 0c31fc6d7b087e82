// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The position model between polls (position_model.hpp): a leg runs its axis along the variant's
// motion model; the latest reading places it on that curve and two readings time it.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "birdcage/tracking/position_model.hpp"

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
    leg.latest = AxisReading{start, sent_at - 1ms};   // read just before it was sent
    return leg;
}

MovingAxes azimuth_only(const LegMotion& leg) { return MovingAxes{leg, std::nullopt}; }

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
    CHECK(half.az == Approx(120).margin(0.1));   // symmetric profile: halfway at half time
    CHECK(half.el == Approx(30));                 // the other axis does not move
    const AzEl quarter = modelled_position(g2, last, azimuth_only(leg), t0 + move / 4);
    CHECK(quarter.az < 110.0);                    // still accelerating: less than a quarter of the way
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
    CHECK(std::fabs(azimuth_difference(0.0, halfway)) < 0.1);   // at north, whichever side of 0/360
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
    const auto step = move / 10;   // a further 0.15 of real time is 0.1 of model time
    CHECK(modelled_axis(hal, slow, t0 + move * 60 / 100 + step * 3 / 2) == Approx(model_at(move / 2)).margin(0.02));

    SECTION("the last two readings, where far enough apart, give the pace where the axis is now") {
        // Started at the model's pace, slowed to two thirds of it since the previous reading.
        slow.first_moving = AxisReading{model_at(move * 1 / 10), t0 + move * 1 / 10};
        slow.previous = AxisReading{model_at(move * 3 / 10), t0 + move * 45 / 100};
        CHECK(modelled_axis(hal, slow, t0 + move * 60 / 100 + step * 3 / 2) == Approx(model_at(move / 2)).margin(0.02));
    }
    SECTION("an implausible pace is bounded") {
        slow.first_moving->at = t0 + move * 59 / 100;   // a tenth of the model's time for its distance
        const double bounded = modelled_axis(hal, slow, t0 + move * 60 / 100 + step);
        CHECK(bounded == Approx(model_at(move * 8 / 10)).margin(0.02));   // four times the model's pace at most
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
    leg.pace = 0.5;   // this axis ran legs of this length at half the model's pace
    CHECK(modelled_axis(hal, leg, t0 + move) == Approx(31.0).margin(0.01));
    CHECK(observed_pace(hal, leg) == std::nullopt);   // no readings in the leg yet
}

TEST_CASE("position model: paces are learnt per axis and per leg length") {
    AxisPaces paces;
    CHECK(paces.pace(Axis::azimuth, 0.5) == 1.0);
    paces.learn(Axis::azimuth, 0.6, 0.5);
    CHECK(paces.pace(Axis::azimuth, 0.7) == Approx(0.5));     // same length class (0.5..1 deg)
    CHECK(paces.pace(Axis::azimuth, 3.0) == 1.0);             // another length
    CHECK(paces.pace(Axis::elevation, 0.7) == 1.0);           // another axis
    for (int legs = 0; legs < 30; ++legs) {
        paces.learn(Axis::azimuth, 0.6, 0.8);
    }
    CHECK(paces.pace(Axis::azimuth, 0.6) == Approx(0.8).margin(1e-3));   // follows the motor as it changes
}
