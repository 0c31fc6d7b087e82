// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Predictive steering (steering.hpp) without threads or I/O: a TargetPredictor fed with explicit
// times, the G2's profile, and next_aim() called as the worker would.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include "error_stats.hpp"
#include "firmware/variants.hpp"
#include "tracking/steering.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1000);

Clock::time_point at(double seconds) {
    return t0 + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// A satellite crossing at 1 deg/s in azimuth and 0.2 deg/s in elevation, sent every second.
AzEl satellite(double t) {
    return {normalize_azimuth(150.0 + 1.0 * t), 30.0 + 0.2 * t};
}

TargetPredictor fed_until(double last_t) {
    TargetPredictor predictor;
    for (double t = 0.0; t <= last_t + 1e-9; t += 1.0) {
        predictor.observe(at(t), satellite(t), satellite(t));
    }
    return predictor;
}

// A client that sends the satellite as it is every 5 s until `until`, each read back `behind` s
// of the satellite's motion short of it; the local estimate only (no orbit).
TargetPredictor client_every_5s(double until, double behind) {
    PredictorSettings gaps_only;
    gaps_only.use_pass_model = false;
    TargetPredictor predictor(gaps_only);
    for (double t = 0.0; t <= until + 1e-9; t += 5.0) {
        predictor.observe(at(t), satellite(t), satellite(t - behind));
    }
    return predictor;
}

SteeringInput input_at(double t, const TargetPredictor& predictor, std::optional<AzEl> aim) {
    return SteeringInput{at(t), predictor, profile(VariantId::carryout_g2), 18.0, 65.0,         PointingOptions{},
                         0.0,   aim,       satellite(std::floor(t)),        aim,  MotorTiming{}};
}

}  // namespace

TEST_CASE("steering: a moving satellite is aimed a deadband ahead, then left alone until it passes the aim") {
    const TargetPredictor predictor = fed_until(30.0);
    const auto first = next_aim(input_at(30.0, predictor, std::nullopt));
    REQUIRE(first);
    CHECK_FALSE(first->holding);
    CHECK(first->az_rate == Approx(1.0).margin(0.05));
    // Ahead of the satellite in both axes, by about a deadband plus the move's own time.
    CHECK(azimuth_difference(satellite(30.0).az, first->aim.az) > 0.0);
    CHECK(azimuth_difference(satellite(30.0).az, first->aim.az) < 1.0);
    CHECK(first->aim.el > satellite(30.0).el);

    // 50 ms later the satellite has moved 0.05 deg: short of the aim, so nothing new.
    CHECK_FALSE(next_aim(input_at(30.05, predictor, first->aim)));
    // A second later it is well past the aim: a new one, ahead again, with both legs timed.
    const auto later = next_aim(input_at(31.0, predictor, first->aim));
    REQUIRE(later);
    CHECK(azimuth_difference(first->aim.az, later->aim.az) > 0.5);
    CHECK(later->legs >= 1);
    CHECK(later->motion_s > 0.0);
}

TEST_CASE("steering: the deadband grows to a share of the client's own threshold, at most a degree") {
    // A Gpredict-like client at a 5 deg threshold: it re-sends when the dish trails by 5 deg, with
    // a target 5 deg ahead, every few seconds; the estimator learns the 5 deg from the gaps. (The
    // track is a straight line in az/el at a constant rate, on which a lead is only a phase: the
    // orbit cannot tell the gaps' lead from none there, so it is left out.)
    PredictorSettings gaps_only;
    gaps_only.use_pass_model = false;
    TargetPredictor predictor(gaps_only);
    for (double t = 0.0; t <= 30.0 + 1e-9; t += 3.0) {
        predictor.observe(at(t), satellite(t + 5.0), satellite(t - 5.0));
    }
    REQUIRE(predictor.lead_threshold_deg());
    CHECK(*predictor.lead_threshold_deg() == Approx(5.0).margin(0.5));
    auto lead_with = [&](double share) {
        SteeringInput in = input_at(30.0, predictor, std::nullopt);
        in.pointing.client_threshold_share = share;
        in.pointing.start_cost_s = 0.0;  // the same deadband on both axes (the cost per start: below)
        const auto aim = next_aim(in);
        REQUIRE(aim);
        return azimuth_difference(satellite(30.0).az, aim->aim.az);
    };
    const double fixed = lead_with(0.0);
    const double shared = lead_with(0.5);
    // Half of 5 deg is capped at 1 deg (on the sky; in azimuth / cos(el), el ~36 deg here).
    CHECK(shared - fixed ==
          Approx((1.0 - PointingOptions{}.deadband_deg) / std::cos(36.0 * M_PI / 180.0)).margin(0.15));
}

TEST_CASE("steering: a client without look-ahead sets the deadband by its step, not by the gaps' small lead") {
    // A client that sends the satellite as it is each time it has moved 5 deg (no look-ahead, here
    // every 5 s): its steps are 5 deg whatever the dish does. The dish reports 0.76 deg short of
    // each target, so the gaps teach a lead of 0.38 deg (the orbit leading the dish leaves no more):
    // under a fifth of the half step, which then stands for the client's coarseness.
    const TargetPredictor predictor = client_every_5s(40.0, 0.76);
    REQUIRE(predictor.lead_threshold_deg());
    CHECK(*predictor.lead_threshold_deg() == Approx(0.38).margin(0.05));
    REQUIRE(predictor.client_coarseness_deg());
    CHECK(*predictor.client_coarseness_deg() == Approx(2.5).margin(0.05));
    auto lead_with = [&](double share) {
        SteeringInput in = input_at(40.0, predictor, std::nullopt);
        in.pointing.client_threshold_share = share;
        in.pointing.start_cost_s = 0.0;  // the same deadband on both axes (the cost per start: below)
        const auto aim = next_aim(in);
        REQUIRE(aim);
        return azimuth_difference(satellite(40.0).az, aim->aim.az);
    };
    // Half of 2.5 deg is capped at 1 deg (on the sky; in azimuth / cos(el), el 38 deg here); the
    // gaps' 0.38 deg would leave the deadband at its minimum.
    CHECK(lead_with(0.5) - lead_with(0.0) ==
          Approx((1.0 - PointingOptions{}.deadband_deg) / std::cos(38.0 * M_PI / 180.0)).margin(0.15));
}

TEST_CASE("steering: with a cost per start each axis's deadband follows the cube root of its rate") {
    // The client without look-ahead of the test above (5 deg steps, every 5 s): half its
    // coarseness is capped at 1 deg (d0). With a cost per start of C seconds off by d0, an axis at
    // r deg/s on the sky gets d = (3/4 C d0^2 r)^(1/3): the azimuth (1 deg/s, 0.79 on the sky at
    // el 38) 2.07 deg, the elevation (0.2 deg/s) 1.31 deg, both under half the client's 5 deg.
    // A motor told outright as nearly instant leaves the command overhead as the only lead: the
    // aim is a deadband past where the estimate has the satellite then.
    const TargetPredictor predictor = client_every_5s(40.0, 0.76);
    REQUIRE(predictor.client_without_look_ahead());
    auto deadbands_with = [&](double cost, const TargetPredictor& client) {
        SteeringInput in = input_at(40.0, client, std::nullopt);
        in.pointing.start_cost_s = cost;
        in.pointing.known_motor = KnownMotor{0.0, 1e4, 1e6};
        const auto aim = next_aim(in);
        REQUIRE(aim);
        const auto estimate = client.predict(at(40.0 + in.pointing.command_overhead_s));
        REQUIRE(estimate);
        const AzEl then = estimate->position;
        const double cos_el = std::cos(client.predict(at(40.0))->position.el * M_PI / 180.0);
        return std::pair{azimuth_difference(then.az, aim->aim.az) * cos_el, aim->aim.el - then.el};
    };
    const double cos_el = std::cos(38.0 * M_PI / 180.0);
    const auto [az_flat, el_flat] = deadbands_with(0.0, predictor);
    CHECK(az_flat == Approx(1.0).margin(0.02));
    CHECK(el_flat == Approx(1.0).margin(0.02));
    const double cost = PointingOptions{}.start_cost_s;
    REQUIRE(cost == 15.0);
    const auto [az_sky, el] = deadbands_with(cost, predictor);
    CHECK(az_sky == Approx(std::cbrt(0.75 * cost * 1.0 * cos_el)).margin(0.02));
    CHECK(el == Approx(std::cbrt(0.75 * cost * 0.2)).margin(0.02));
    // The ratio of the two is the cube root of the rates' on the sky, whatever the cost.
    CHECK(az_sky / el == Approx(std::cbrt(cos_el / 0.2)).margin(0.02));
    // A cost so high that the rule would step past half the client's threshold stops there.
    const auto [az_capped, el_capped] = deadbands_with(1000.0, predictor);
    CHECK(az_capped == Approx(2.5).margin(0.02));
    CHECK(el_capped == Approx(2.5).margin(0.05));

    // A client that leads (here by 1 deg, stepping by 5) keeps d0, half its lead, on both axes:
    // with Gpredict's look-ahead the coarser steps cost more error than they saved starts.
    const TargetPredictor leading = client_every_5s(40.0, 2.0);
    REQUIRE_FALSE(leading.client_without_look_ahead());
    const auto [az_led, el_led] = deadbands_with(cost, leading);
    CHECK(az_led == Approx(0.5).margin(0.02));
    CHECK(el_led == Approx(0.5).margin(0.02));
}

TEST_CASE("steering: a client that leads by its threshold keeps it as its coarseness, whatever its step") {
    // A client that leads by 1 deg and steps by 5 (half step 2.5): its lead is no share of the
    // step a client without look-ahead shows, so the lead stays the coarseness.
    const TargetPredictor predictor = client_every_5s(40.0, 2.0);
    REQUIRE(predictor.lead_threshold_deg());
    CHECK(*predictor.lead_threshold_deg() == Approx(1.0).margin(0.05));
    REQUIRE(predictor.client_coarseness_deg());
    CHECK(*predictor.client_coarseness_deg() == Approx(1.0).margin(0.05));
}

TEST_CASE("steering: a stationary target is held without lead, once") {
    TargetPredictor predictor;
    for (double t = 0.0; t <= 3.0; t += 1.0) {
        predictor.observe(at(t), {200.0, 40.0}, AzEl{200.0, 40.0});
    }
    const SteeringInput first_input{at(3.5),
                                    predictor,
                                    profile(VariantId::carryout_g2),
                                    18.0,
                                    65.0,
                                    PointingOptions{},
                                    0.0,
                                    std::nullopt,
                                    AzEl{200.0, 40.0},
                                    AzEl{180.0, 30.0},
                                    MotorTiming{}};
    const auto hold = next_aim(first_input);
    REQUIRE(hold);
    CHECK(hold->holding);
    CHECK(hold->aim.az == Approx(200.0));
    CHECK(hold->aim.el == Approx(40.0));
    SteeringInput again = first_input;
    again.aim = hold->aim;
    CHECK_FALSE(next_aim(again));
}

TEST_CASE("steering: above the elevation cap the dish holds the cap and follows the azimuth") {
    TargetPredictor predictor;
    for (double t = 0.0; t <= 10.0; t += 1.0) {
        predictor.observe(at(t), {normalize_azimuth(100.0 + 2.0 * t), 66.0 + 0.3 * t}, std::nullopt);
    }
    const SteeringInput in{at(10.0),     predictor,    profile(VariantId::carryout_g2),
                           18.0,         65.0,         PointingOptions{},
                           0.0,          std::nullopt, AzEl{120.0, 69.0},
                           std::nullopt, MotorTiming{}};
    const auto decision = next_aim(in);
    REQUIRE(decision);
    CHECK(decision->aim.el == Approx(65.0));
    CHECK(azimuth_difference(120.0, decision->aim.az) >= 0.0);
}

TEST_CASE("steering: nothing to steer by before any target") {
    const TargetPredictor predictor;
    const SteeringInput in{at(0.0),      predictor,    profile(VariantId::carryout_g2),
                           18.0,         65.0,         PointingOptions{},
                           0.0,          std::nullopt, std::nullopt,
                           std::nullopt, MotorTiming{}};
    CHECK_FALSE(next_aim(in));
}

TEST_CASE("steering: the wrap direction comes from the estimate, else from the client's small step while waiting low") {
    Prediction moving;
    moving.az_rate = -0.7;
    CHECK(azimuth_direction_hint(moving, AzEl{100, 40}, AzEl{95, 40}, AzEl{90, 40}, 18.0) == -0.7);
    // Waiting at the lowest elevation, the client steps along the track: its sign is the pass's.
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{350, 18}, AzEl{350, 18}, AzEl{5, 20}, 18.0) > 0.0);
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{10, 18}, AzEl{10, 18}, AzEl{0, 20}, 18.0) < 0.0);
    // A large step is a new pointing, and a dish high in the sky is not waiting for a pass.
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{10, 18}, AzEl{10, 18}, AzEl{90, 20}, 18.0) == 0.0);
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{10, 40}, AzEl{10, 40}, AzEl{15, 40}, 18.0) == 0.0);
    CHECK(azimuth_direction_hint(std::nullopt, std::nullopt, AzEl{10, 18}, AzEl{15, 20}, 18.0) == 0.0);
    // The client's first target: the step from where the dish waits (iss-45 on the G2 at a 5 deg
    // threshold, the benchmark's figures: the dish at the AOS azimuth, the first target 13 deg along
    // the track; the next came 68 s later with the satellite at 26 deg, and the branch change then
    // cost 12 deg RMS over the pass).
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{299.78, 18}, std::nullopt, AzEl{313.05, 18}, 18.0) > 0.0);
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{10, 18}, std::nullopt, AzEl{5, 20}, 18.0) < 0.0);
    CHECK(azimuth_direction_hint(std::nullopt, AzEl{10, 18}, std::nullopt, AzEl{90, 20}, 18.0) == 0.0);
}

TEST_CASE("steering: a dish led past the client's target does not read as a pass going back") {
    // Measured on the benchmark (iss-45, G2, predictive): the aim ran 0.09 deg past the client's
    // latest target while the estimate was momentarily stationary; the step from the dish to the
    // target pointed backwards and the pass-start branch choice sent the dish 120 deg the wrong way.
    const AzEl dish{310.09, 18.0};
    const AzEl previous{309.96, 18.0}, target{310.00, 18.0};
    CHECK(azimuth_direction_hint(std::nullopt, dish, previous, target, 18.0) > 0.0);
}

TEST_CASE("steering: aims left ahead when the orbit loses trust are held until the client's targets reach them") {
    // A Trav'ler steered 4.7 deg ahead in azimuth, and below the client's target on a falling
    // elevation, when the orbit lost trust (the flake of the az-mapping e2e test).
    const Prediction pass{{344.88, 56.57}, 0.65, -0.25, true};
    SECTION("the azimuth ahead is held, the elevation ahead is held, until each is reached, then for good") {
        AimsAhead held{349.58, 56.0};
        const AzEl first = hold_aims_ahead(held, {344.88, 56.57}, pass);
        CHECK(first.az == 349.58);
        CHECK(first.el == 56.0);
        const AzEl later = hold_aims_ahead(held, {347.46, 55.9}, pass);
        CHECK(later.az == 349.58);
        CHECK(later.el == Approx(55.9));  // the client's elevation reached the aim: let go
        CHECK_FALSE(held.el);
        const AzEl past = hold_aims_ahead(held, {349.7, 55.6}, pass);
        CHECK(past.az == Approx(349.7));
        CHECK_FALSE(held.az);
        CHECK(hold_aims_ahead(held, {349.0, 55.5}, pass).az == Approx(349.0));  // never taken up again
    }
    SECTION("an aim behind the client's target is let go at once") {
        AimsAhead held{342.0, 58.0};  // behind in azimuth; above a falling elevation is behind too
        const AzEl sent = hold_aims_ahead(held, {344.88, 56.57}, pass);
        CHECK(sent.az == Approx(344.88));
        CHECK(sent.el == Approx(56.57));
        CHECK_FALSE(held.az);
        CHECK_FALSE(held.el);
    }
    SECTION("an aim the pass would take long to reach, or a pass that stopped, is not waited for") {
        AimsAhead far{344.88 + 0.65 * 30.0, std::nullopt};
        CHECK(hold_aims_ahead(far, {344.88, 56.57}, pass).az == Approx(344.88));
        AimsAhead stopped{349.58, std::nullopt};
        const Prediction still{{344.88, 56.57}, 0.0, 0.0, false};
        CHECK(hold_aims_ahead(stopped, {344.88, 56.57}, still).az == Approx(344.88));
        AimsAhead unknown{349.58, std::nullopt};
        CHECK(hold_aims_ahead(unknown, {344.88, 56.57}, std::nullopt).az == Approx(344.88));
    }
    SECTION("across north") {
        AimsAhead held{2.0, std::nullopt};
        CHECK(hold_aims_ahead(held, {358.5, 56.57}, pass).az == 2.0);
        CHECK(hold_aims_ahead(held, {2.5, 56.57}, pass).az == Approx(2.5));
    }
}

TEST_CASE("steering: the measured leg overhead is what a step took beyond its motion, smoothed") {
    const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1);
    LegOverheadMeter meter;
    CHECK_FALSE(meter.overhead_s());
    meter.start(t0, 2, 3.0);
    meter.finished(t0 + 5s);
    CHECK(*meter.overhead_s() == Approx(1.0));
    meter.start(t0 + 10s, 1, 3.0);
    meter.finished(t0 + 13s);  // no slower than the motion: 0 overhead, smoothed in
    CHECK(*meter.overhead_s() == Approx(0.8));
    meter.start(t0 + 20s, 0, 1.0);  // no leg: nothing to learn
    meter.finished(t0 + 29s);
    CHECK(*meter.overhead_s() == Approx(0.8));
    meter.finished(t0 + 40s);  // no step in progress
    CHECK(*meter.overhead_s() == Approx(0.8));
}

TEST_CASE("steering: a step the controller did not run alone is not timed") {
    // The az-mapping e2e test on the G2: a steered step began, the orbit lost trust, and 19 s of the
    // client's targets as sent followed before the dish was idle. Timed, that was 19 s of overhead
    // per leg, and the aims ran 16 deg ahead of the satellite.
    const Clock::time_point t0 = Clock::time_point{} + std::chrono::hours(1);
    LegOverheadMeter meter;
    meter.start(t0, 1, 0.1);
    meter.finished(t0 + 600ms);
    REQUIRE(*meter.overhead_s() == Approx(0.5));
    meter.start(t0 + 1s, 1, 0.09);
    CHECK(meter.timing());
    meter.interrupt();
    CHECK_FALSE(meter.timing());
    meter.finished(t0 + 20s);
    CHECK(*meter.overhead_s() == Approx(0.5));
}

namespace {

// A client that points the dish by single targets (rotctl, a TUI jogging, an MCP server's move_to,
// a sky scan) against a dish that goes to each aim at once; next_aim() is called every 0.1 s as the
// worker would. Records the aims.
struct ManualRun {
    struct Step {
        double t;
        AzEl target;
    };
    std::vector<Step> steps;
    double az_min = 360.0, az_max = -360.0, el_min = 90.0, el_max = 0.0;  // targets sent so far
    double worst_outside_deg = 0.0;     // the aims' furthest excursion outside the targets' box
    std::vector<AzEl> aim_before_step;  // the aim just before each step after the first
    std::optional<AzEl> aim;

    void run(PointingOptions pointing = {}) {
        TargetPredictor predictor(pointing.predictor);
        std::size_t next = 0;
        std::optional<AzEl> last_target;
        const double end = steps.back().t + 120.0;
        for (int tick = 0; tick * 0.1 <= end; ++tick) {
            const double t = tick * 0.1;
            if (next < steps.size() && t + 1e-9 >= steps[next].t) {
                if (next > 0) {
                    aim_before_step.push_back(*aim);
                }
                const AzEl target = steps[next].target;
                predictor.observe(at(t), target, aim);
                // Unwrapped around the first target: these grids do not cross north.
                az_min = std::min(az_min, target.az);
                az_max = std::max(az_max, target.az);
                el_min = std::min(el_min, target.el);
                el_max = std::max(el_max, target.el);
                last_target = target;
                ++next;
            }
            const SteeringInput in{
                at(t), predictor,    profile(VariantId::carryout_g2), 18.0, 65.0, pointing, 0.0, aim, last_target,
                aim,   MotorTiming{}};
            if (const auto decision = next_aim(in)) {
                aim = decision->aim;
                const double outside =
                    std::max({az_min - aim->az, aim->az - az_max, el_min - aim->el, aim->el - el_max, 0.0});
                worst_outside_deg = std::max(worst_outside_deg, outside);
            }
        }
    }
};

void check_ends_at_last_target(const ManualRun& run) {
    REQUIRE(run.aim);
    CHECK(run.aim->az == Approx(run.steps.back().target.az).margin(0.005));
    CHECK(run.aim->el == Approx(run.steps.back().target.el).margin(0.005));
    // Never beyond where the client has pointed: no extrapolation of manual steps.
    CHECK(run.worst_outside_deg < 0.005);
}

}  // namespace

TEST_CASE("steering: manual pointing by single targets ends exactly at the last target") {
    SECTION("P 180 40, then P 185 40 two seconds later (the dish came to rest at 207.4)") {
        ManualRun run;
        run.steps = {{0.0, {180.0, 40.0}}, {2.0, {185.0, 40.0}}};
        run.run();
        check_ends_at_last_target(run);
    }
    SECTION("steps 180 -> 185 -> 190, two to five seconds apart, at 0 to 60 deg elevation") {
        const double interval = GENERATE(2.0, 3.0, 4.0, 5.0);
        const double el = GENERATE(20.0, 40.0, 60.0);
        INFO("every " << interval << " s at el " << el);
        ManualRun run;
        run.steps = {{0.0, {180.0, el}}, {interval, {185.0, el}}, {2 * interval, {190.0, el}}};
        run.run();
        check_ends_at_last_target(run);
        for (std::size_t k = 0; k < run.aim_before_step.size(); ++k) {
            INFO("before step " << k + 1);
            CHECK(run.aim_before_step[k].az == Approx(run.steps[k].target.az).margin(0.005));
        }
    }
    SECTION("a TUI jogging by 1 deg every second, ten times") {
        ManualRun run;
        for (int k = 0; k <= 10; ++k) {
            run.steps.push_back({1.0 * k, {200.0 + k, 35.0}});
        }
        run.run();
        check_ends_at_last_target(run);
    }
    SECTION("a sky scan: a serpentine grid of 1-2 deg steps every few seconds") {
        const double step = GENERATE(1.0, 2.0);
        const double dwell = GENERATE(2.0, 3.0);
        INFO(step << " deg every " << dwell << " s");
        ManualRun run;
        double t = 0.0;
        for (int row = 0; row < 5; ++row) {
            for (int col = 0; col < 6; ++col) {
                const int c = row % 2 == 0 ? col : 5 - col;
                run.steps.push_back({t, {150.0 + step * c, 30.0 + step * row}});
                t += dwell;
            }
        }
        run.run();
        check_ends_at_last_target(run);
        // The dish dwells on each grid point until the next is sent.
        for (std::size_t k = 0; k < run.aim_before_step.size(); ++k) {
            INFO("before grid point " << k + 1);
            CHECK(run.aim_before_step[k].az == Approx(run.steps[k].target.az).margin(0.005));
            CHECK(run.aim_before_step[k].el == Approx(run.steps[k].target.el).margin(0.005));
        }
    }
    SECTION("a single far jump") {
        ManualRun run;
        run.steps = {{0.0, {10.0, 20.0}}, {20.0, {250.0, 60.0}}};
        run.run();
        check_ends_at_last_target(run);
    }
}

TEST_CASE("steering: a Gpredict-like pass after manual moves still gets predictive aims") {
    // Manual moves first, then a client tracking a satellite (1 s cycle, 0.5 deg threshold, a lead
    // to the threshold's edge to a quarter cycle, as testbed/gpredict_client.cpp), against a dish that
    // goes to each aim at once. The same client against a dish that goes to each target as sent
    // (pointing=none) is the baseline: predictive aims must lead the last target and beat it.
    const auto sat = [](double t) { return AzEl{normalize_azimuth(120.0 + 0.6 * t), 25.0 + 0.2 * t}; };
    const double threshold = 0.5;
    struct Result {
        birdcage::test::ErrorStats error;
        int leading = 0;
        int targets = 0;
    };
    auto run = [&](bool predictive) {
        TargetPredictor predictor;
        predictor.observe(at(-20.0), {180.0, 40.0}, std::nullopt);
        predictor.observe(at(-18.0), {185.0, 40.0}, AzEl{180.0, 40.0});
        std::optional<AzEl> aim = AzEl{185.0, 40.0};
        std::optional<AzEl> last_target;
        Result result;
        for (int tick = 0; tick * 0.1 <= 150.0; ++tick) {
            const double t = tick * 0.1;
            const AzEl now = sat(t);
            if (tick % 10 == 0 && (!last_target || std::max(std::fabs(azimuth_difference(aim->az, now.az)),
                                                            std::fabs(aim->el - now.el)) > threshold)) {
                double lead_s = 0.0;
                while (std::max(std::fabs(azimuth_difference(now.az, sat(t + lead_s + 0.25).az)),
                                std::fabs(sat(t + lead_s + 0.25).el - now.el)) <= threshold) {
                    lead_s += 0.25;
                }
                const AzEl ahead = sat(t + lead_s);
                last_target = AzEl{std::round(ahead.az * 100.0) / 100.0, std::round(ahead.el * 100.0) / 100.0};
                predictor.observe(at(t), *last_target, aim);
                ++result.targets;
                if (!predictive) {
                    aim = last_target;
                }
            }
            const SteeringInput in{at(t), predictor,    profile(VariantId::carryout_g2),
                                   18.0,  65.0,         PointingOptions{},
                                   0.0,   aim,          last_target,
                                   aim,   MotorTiming{}};
            if (const auto decision = next_aim(in); decision && predictive) {
                aim = decision->aim;
                result.leading += azimuth_difference(last_target->az, aim->az) > 0.01 ? 1 : 0;
            }
            if (t >= 30.0) {  // past the young track's 20 s
                result.error.add(std::hypot(azimuth_difference(now.az, aim->az) * std::cos(now.el * M_PI / 180.0),
                                            now.el - aim->el));
            }
        }
        return result;
    };
    const Result predictive = run(true);
    const Result as_sent = run(false);
    INFO("predictive: RMS " << predictive.error.rms() << ", max " << predictive.error.max << ", " << predictive.targets
                            << " targets, " << predictive.leading << " aims ahead of the last target; as sent: RMS "
                            << as_sent.error.rms() << ", max " << as_sent.error.max << ", " << as_sent.targets
                            << " targets");
    CHECK(predictive.leading > 10);
    CHECK(predictive.error.rms() < 0.9 * as_sent.error.rms());
    CHECK(predictive.targets < as_sent.targets / 2);
    CHECK(predictive.error.max < 2 * threshold);
}

namespace {

// Where the first aim lands with the dish on the satellite at `t`: the leg ends `lead` seconds
// later, where lead = overhead + start-up + travel(the leg's length), and the length runs from the
// dish to a deadband past the satellite then. Solved by iteration, from the truth.
struct ExpectedAim {
    double lead_s;
    double az;
};

template <typename Travel>
ExpectedAim expected_first_aim(double t, double overhead_s, double deadband_az, Travel travel_s) {
    double lead = 0.0;
    for (int round = 0; round < 50; ++round) {
        const double length = std::fabs(azimuth_difference(satellite(t).az, satellite(t + lead).az) + deadband_az);
        lead = overhead_s + travel_s(length);
    }
    return {lead, normalize_azimuth(satellite(t + lead).az + deadband_az)};
}

}  // namespace

TEST_CASE("steering: a motor that starts late is aimed where the satellite is once its leg ends") {
    const TargetPredictor predictor = fed_until(30.0);
    PointingOptions pointing;
    pointing.deadband_deg = pointing.max_deadband_deg = 0.1;  // no widening: the lead alone is tested
    pointing.client_threshold_share = 0.0;
    const FirmwareProfile& dish = profile(VariantId::carryout_g2);
    SteeringInput in{at(30.0),        predictor,       dish,         18.0, 65.0, pointing, 0.0, std::nullopt,
                     satellite(30.0), satellite(30.0), MotorTiming{}};
    const double deadband_az = 0.1 / std::cos(satellite(30.0).el * M_PI / 180.0);
    auto curve_s = [&](double degrees) {
        return std::chrono::duration<double>(estimated_move_time(dish, Axis::azimuth, degrees)).count();
    };

    const auto prompt = next_aim(in);
    REQUIRE(prompt);
    in.motor.startup_s = {2.0, 2.0};
    const auto late = next_aim(in);
    REQUIRE(late);

    SECTION("the learnt start-up delay, then the variant's curve over the leg's length") {
        const ExpectedAim expected = expected_first_aim(30.0, pointing.command_overhead_s, deadband_az,
                                                        [&](double d) { return 2.0 + curve_s(d); });
        INFO("lead " << expected.lead_s << " s");
        CHECK(expected.lead_s > 2.1);
        CHECK(azimuth_difference(expected.az, late->aim.az) == Approx(0.0).margin(0.05));
        // 2 s of delay at 1 deg/s: 2 deg further ahead than on a motor that starts at once.
        CHECK(azimuth_difference(prompt->aim.az, late->aim.az) == Approx(2.0).margin(0.15));
    }
    SECTION("a learnt pace: twice as fast through the curve on legs that long") {
        for (int i = 0; i < 3; ++i) {
            for (double d : {0.2, 0.4, 1.0, 2.0, 4.0}) {
                in.motor.paces.learn(Axis::azimuth, d, 2.0);
            }
        }
        const auto brisk = next_aim(in);
        REQUIRE(brisk);
        const ExpectedAim expected = expected_first_aim(30.0, pointing.command_overhead_s, deadband_az,
                                                        [&](double d) { return 2.0 + curve_s(d) / 2.0; });
        CHECK(azimuth_difference(expected.az, brisk->aim.az) == Approx(0.0).margin(0.05));
        CHECK(azimuth_difference(brisk->aim.az, late->aim.az) > 0.0);
    }
    SECTION("a motor told outright: its delay, then a trapezoid of its speed and acceleration") {
        in.motor = MotorTiming{};
        in.pointing.known_motor = KnownMotor{2.0, 10.0, 5.0};
        const auto known = next_aim(in);
        REQUIRE(known);
        const ExpectedAim expected = expected_first_aim(30.0, pointing.command_overhead_s, deadband_az, [](double d) {
            return 2.0 + (d < 10.0 * 10.0 / 5.0 ? 2.0 * std::sqrt(d / 5.0) : d / 10.0 + 10.0 / 5.0);
        });
        CHECK(azimuth_difference(expected.az, known->aim.az) == Approx(0.0).margin(0.05));
    }
    SECTION("a re-aim times its legs with their start-up delays") {
        in.aim = late->aim;
        in.dish_position = late->aim;
        in.now = at(36.0);
        const auto again = next_aim(in);
        REQUIRE(again);
        REQUIRE(again->legs >= 1);
        CHECK(again->motion_s >= 2.0 * again->legs);
    }
}
