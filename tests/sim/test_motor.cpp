// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Motor physics on advance(dt) alone: no pty, no thread, no clock.
#include <catch2/catch.hpp>

#include <cmath>

#include "birdcage_sim/motor.hpp"

using namespace birdcage::sim;

namespace {

constexpr AxisParams g2_az{65.0, 400.0, -423.33, 23.33, 40000};
constexpr AxisParams g2_el{45.0, 400.0, 0.0, 90.0, 24960};
constexpr AxisParams none{1.0, 1.0, 0.0, 0.0, 0};

double time_to_rest(Axis& axis, double dt = 1e-3) {
    double t = 0.0;
    while (axis.moving() && t < 100.0) {
        const double leftover = axis.advance(dt);
        t += dt - leftover;
    }
    return t;
}

}  // namespace

TEST_CASE("G2 slew times match the trapezoid table of docs/tracking.md 1.4", "[motor]") {
    struct Row {
        AxisParams params;
        double distance;
        double seconds;
    };
    const Row rows[] = {
        {g2_az, 1.0, 0.100},  {g2_az, 10.0, 0.316}, {g2_az, 90.0, 1.55},  {g2_az, 180.0, 2.93},
        {g2_az, 360.0, 5.70}, {g2_el, 1.0, 0.100},  {g2_el, 10.0, 0.335}, {g2_el, 47.0, 1.16},
    };
    for (const Row& row : rows) {
        CAPTURE(row.distance, row.params.max_velocity);
        const double start = row.params.min + 1.0;
        Axis axis(AxisParams{row.params.max_velocity, row.params.max_accel, start - 1.0, start + 400.0, 0}, start);
        axis.move_to(start + row.distance);
        CHECK(time_to_rest(axis) == Approx(row.seconds).epsilon(0.03));
        CHECK(axis.position() == Approx(start + row.distance));
        CHECK(Axis::move_time(row.params, row.distance) == Approx(row.seconds).epsilon(0.03));
    }
}

TEST_CASE("integration does not depend on the step size", "[motor]") {
    Axis coarse(g2_az, -200.0);
    Axis fine(g2_az, -200.0);
    coarse.move_to(0.0);
    fine.move_to(0.0);
    for (int i = 0; i < 7; ++i)
        coarse.advance(0.25);
    for (int i = 0; i < 1750; ++i)
        fine.advance(0.001);
    CHECK(coarse.position() == Approx(fine.position()).margin(1e-6));
    CHECK(coarse.velocity() == Approx(fine.velocity()).margin(1e-6));
}

TEST_CASE("azimuth and elevation never move at the same time", "[motor]") {
    MotorModel motors(g2_az, g2_el, none, -180.0, 45.0);
    motors.enqueue(axis_az, -90.0);
    motors.enqueue(axis_el, 20.0);
    REQUIRE(motors.moving());
    double t = 0.0;
    bool el_started_before_az_done = false;
    while (motors.moving() && t < 10.0) {
        motors.advance(0.001);
        t += 0.001;
        if (motors.axis(axis_az).moving() && motors.axis(axis_el).position() != 45.0)
            el_started_before_az_done = true;
        CHECK_FALSE((motors.axis(axis_az).moving() && motors.axis(axis_el).moving()));
    }
    CHECK_FALSE(el_started_before_az_done);
    CHECK(t == Approx(Axis::move_time(g2_az, 90.0) + Axis::move_time(g2_el, 25.0)).margin(0.003));
    CHECK(motors.axis(axis_az).position() == Approx(-90.0));
    CHECK(motors.axis(axis_el).position() == Approx(20.0).margin(0.01));
}

TEST_CASE("a queued move for the other axis starts exactly when the first ends", "[motor]") {
    MotorModel motors(g2_az, g2_el, none, 0.0, 45.0);
    motors.enqueue(axis_az, -90.0);
    motors.enqueue(axis_el, 20.0);
    motors.advance(10.0);  // one big step
    CHECK_FALSE(motors.moving());
    CHECK(motors.axis(axis_el).position() == Approx(20.0).margin(0.01));
}

TEST_CASE("targets are clamped into the mechanical travel", "[motor]") {
    Axis axis(g2_az, 0.0);
    axis.move_to(100.0);
    CHECK(axis.target() == Approx(23.33).margin(0.01));
    axis.move_to(-500.0);
    CHECK(axis.target() == Approx(-423.33).margin(0.01));
}

TEST_CASE("targets snap to whole motor steps", "[motor]") {
    Axis el(g2_el, 45.0);
    el.move_to(45.004);
    el.advance(5.0);
    const double step = 360.0 / 24960;
    CHECK(std::abs(el.position() / step - std::round(el.position() / step)) < 1e-6);
    CHECK(el.position() == Approx(45.0).margin(step));
    CHECK(quantize_to_steps(180.0, 40000) == 180.0);
    CHECK(quantize_to_steps(0.004, 40000) == 0.0);
    CHECK(quantize_to_steps(0.005, 40000) == Approx(0.009));
    CHECK(quantize_to_steps(12.3456, 0) == 12.3456);
}

TEST_CASE("a 0..360 azimuth maps to the wrap branch nearest the dish", "[motor]") {
    // G2 window -423.33..+23.33 (docs/firmware.md §6.4)
    CHECK(nearest_wrap_branch(180.0, 0.0, -423.33, 23.33) == Approx(-180.0));
    CHECK(nearest_wrap_branch(10.0, 0.0, -423.33, 23.33) == Approx(10.0));
    CHECK(nearest_wrap_branch(10.0, -340.0, -423.33, 23.33) == Approx(-350.0));
    CHECK(nearest_wrap_branch(350.0, -100.0, -423.33, 23.33) == Approx(-10.0));
    CHECK(nearest_wrap_branch(-10.0, 0.0, -423.33, 23.33) == Approx(-10.0));
    // Trav'ler 0..455 (§3.4)
    CHECK(nearest_wrap_branch(30.0, 400.0, 0.0, 455.0) == Approx(390.0));
    CHECK(nearest_wrap_branch(30.0, 100.0, 0.0, 455.0) == Approx(30.0));
    CHECK(nearest_wrap_branch(200.0, 400.0, 0.0, 455.0) == Approx(200.0));
    CHECK(normalize_360(-180.0) == Approx(180.0));
    CHECK(normalize_360(720.0) == Approx(0.0));
}

TEST_CASE("stop ramps down and halts short of the target", "[motor]") {
    Axis axis(g2_az, -400.0);
    axis.move_to(0.0);
    axis.advance(1.0);
    REQUIRE(axis.velocity() == Approx(65.0));
    const double at_stop = axis.position();
    axis.stop();
    const double t = time_to_rest(axis);
    CHECK(t == Approx(65.0 / 400.0).margin(0.002));
    CHECK(axis.position() == Approx(at_stop + 65.0 * 65.0 / 800.0).margin(0.01));
    CHECK(axis.position() < -1.0);
}

TEST_CASE("retargeting while moving reverses smoothly to the new target", "[motor]") {
    Axis axis(g2_el, 20.0);
    axis.move_to(65.0);
    axis.advance(0.3);
    axis.move_to(18.0);
    const double t = time_to_rest(axis);
    CHECK(t < 3.0);
    CHECK(axis.position() == Approx(18.0).margin(0.015));
    CHECK(axis.velocity() == 0.0);
}

TEST_CASE("Trav'ler motion is in the range of the empirical time fit", "[motor]") {
    // §3.4: 90 deg ~13.5 s, 180 deg ~15.7 s, i.e. 6-11 deg/s average for big moves.
    const AxisParams travler{20.0, 2.0, 0.0, 455.0, 0};
    CHECK(Axis::move_time(travler, 90.0) == Approx(13.5).epsilon(0.05));
    const double average_180 = 180.0 / Axis::move_time(travler, 180.0);
    CHECK(average_180 > 6.0);
    CHECK(average_180 < 11.0);
}

TEST_CASE("A motor with a start-up delay holds still and then runs its trapezoid", "[motor]") {
    // A brisker motor that starts 2 s late meets the documented timings (docs/firmware.md §3.4:
    // about 6 s for 10 degrees, 13.5 s for 90), which is why the delay is a parameter of its own.
    AxisParams late{20.0, 3.0, 0.0, 455.0, 0};
    late.startup_delay = 2.0;
    Axis axis(late, 100.0);
    axis.move_to(190.0);
    CHECK(axis.advance(1.9) == 0.0);
    CHECK(axis.position() == 100.0);
    CHECK(axis.moving());
    axis.advance(0.2);
    CHECK(axis.position() > 100.0);
    CHECK(axis.position() < 100.1);
    const double total = 2.1 + time_to_rest(axis);
    CHECK(total == Approx(Axis::move_time(late, 90.0)).margin(0.003));
    CHECK(Axis::move_time(late, 90.0) == Approx(13.5).epsilon(0.05));
    CHECK(Axis::move_time(late, 10.0) == Approx(6.0).epsilon(0.1));
    CHECK(axis.position() == Approx(190.0).margin(1e-9));

    SECTION("a new target while under way does not wait again") {
        axis.move_to(250.0);
        axis.advance(2.5);
        const double under_way = axis.position();
        CHECK(under_way > 190.0);
        axis.move_to(260.0);
        axis.advance(0.1);
        CHECK(axis.position() > under_way);
    }
    SECTION("a stop before the first motion leaves the axis where it was") {
        axis.move_to(250.0);
        axis.advance(1.0);
        axis.stop();
        CHECK_FALSE(axis.moving());
        CHECK(axis.position() == Approx(190.0));
    }
}
