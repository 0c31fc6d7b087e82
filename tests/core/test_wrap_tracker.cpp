// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The wrap tracker on its own: no console, no clock (times are passed in).
#include <catch2/catch.hpp>

#include "tracking/wrap_tracker.hpp"

#include <cmath>
#include <vector>

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

const azmap::Travel g2_travel{{-423.33, 23.33}, true};
const azmap::Travel travler_travel{{0.0, 455.0}, false};
const Clock::time_point t0 = Clock::time_point{} + 1h;

}  // namespace

TEST_CASE("wrap tracker: the first displayed reading takes the branch nearest AZ 0, later ones follow the axis") {
    WrapTracker tracker(g2_travel, std::nullopt, {});
    CHECK_FALSE(tracker.mechanical());
    tracker.note_reading(300.0, t0);
    REQUIRE(tracker.mechanical());
    CHECK(*tracker.mechanical() == Approx(-60.0));  // 300 = -60, the branch nearest 0
    tracker.note_reading(200.0, t0 + 1s);
    CHECK(*tracker.mechanical() == Approx(-160.0));
    tracker.note_reading(100.0, t0 + 2s);  // +100 is beyond the travel: -260
    CHECK(*tracker.mechanical() == Approx(-260.0));
    tracker.note_reading(20.0, t0 + 3s);  // -340 is nearer -260 than +20 is
    CHECK(*tracker.mechanical() == Approx(-340.0));
    CHECK(tracker.readings() == 4);
    CHECK_FALSE(tracker.reports_mechanical());
}

TEST_CASE("wrap tracker: two readings beyond 0..360 prove mechanical reports, taken literally after") {
    WrapTracker tracker(g2_travel, std::nullopt, {});
    tracker.note_reading(-100.0, t0);
    CHECK_FALSE(tracker.reports_mechanical());
    tracker.note_reading(-110.0, t0 + 1s);
    CHECK(tracker.reports_mechanical());
    tracker.note_reading(10.0, t0 + 2s);  // a displayed reading would unwrap to -350
    CHECK(*tracker.mechanical() == Approx(10.0));
}

TEST_CASE("wrap tracker: after a re-initialisation the branch is kept only if the dish still reads it") {
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(50.0, t0);
    tracker.note_reading(40.0, t0 + 2s);
    const double before = *tracker.mechanical();
    tracker.recheck_branch();
    tracker.note_reading(40.2, t0 + 3s);
    CHECK(*tracker.mechanical() == Approx(before + 0.2));  // same branch
    tracker.recheck_branch();
    tracker.note_reading(180.0, t0 + 4s);  // it moved: the start assumption again
    CHECK(*tracker.mechanical() == Approx(180.0));
}

TEST_CASE("wrap tracker: branch choice keeps continuity with the previous target and remembers it") {
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(350.0, t0);
    const double first = tracker.choose_branch({355.0, 30.0}, std::nullopt, 0.0, 15.0, std::nullopt, std::nullopt);
    CHECK(first == Approx(355.0));
    // Crossing north clockwise: 5 deg is continued as mechanical 365, not an unwind to 5.
    const double next = tracker.choose_branch({5.0, 30.0}, AzEl{355.0, 30.0}, 0.1, 15.0, std::nullopt, std::nullopt);
    CHECK(next == Approx(365.0));
    REQUIRE(tracker.target_mechanical());
    CHECK(*tracker.target_mechanical() == Approx(365.0));
    tracker.forget_target();
    CHECK_FALSE(tracker.target_mechanical());
}

TEST_CASE("wrap tracker: a pass starting low picks the branch with room for the whole pass") {
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(300.0, t0);
    // Rising at el_min, moving clockwise from 300: 300 has only 155 deg of room ahead, and the
    // branch at -60 does not exist on 0..455, so the pass starts there anyway (most room ahead).
    const double start = tracker.choose_branch({300.0, 16.0}, std::nullopt, 0.5, 15.0, std::nullopt, std::nullopt);
    CHECK(start == Approx(300.0));
    // Anticlockwise from 10, the branch at 370 has room ahead (down to 0); 10 has none.
    WrapTracker other(travler_travel, std::nullopt, {});
    other.note_reading(10.0, t0);
    const double back = other.choose_branch({10.0, 16.0}, std::nullopt, -0.5, 15.0, std::nullopt, std::nullopt);
    CHECK(back == Approx(370.0));
}

TEST_CASE("wrap tracker: a pass keeps its direction through noise and pauses, a reversal needs 3 deg back") {
    // iss-45 on the G2 at a 5 deg threshold (the benchmark's targets): the dish waits at 299.78
    // (mechanical -60.22) and the pass turns clockwise through north, so it starts on the lower
    // branch, which has room for it.
    WrapTracker tracker(g2_travel, std::nullopt, {});
    tracker.note_reading(299.78, t0);
    const double start = tracker.choose_branch({313.05, 18.0}, std::nullopt, 0.001, 18.0, std::nullopt, std::nullopt);
    CHECK(start == Approx(313.05 - 720.0));
    double at = tracker.choose_branch({313.92, 18.18}, AzEl{313.05, 18.0}, 0.14, 18.0, std::nullopt, std::nullopt);
    CHECK(at == Approx(313.92 - 720.0));
    // Gpredict's next target lands 0.16 deg behind (its lead is quantised): read as the pass going
    // back, the pass-start rule swung the dish to the other branch and back.
    at = tracker.choose_branch({313.76, 18.25}, AzEl{313.92, 18.18}, -0.001, 18.0, std::nullopt, std::nullopt);
    CHECK(at == Approx(313.76 - 720.0));
    at = tracker.choose_branch({313.87, 18.32}, AzEl{313.76, 18.25}, 0.0, 18.0, std::nullopt, std::nullopt);
    CHECK(at == Approx(313.87 - 720.0));
    // A real reversal (another pass, anticlockwise, from nearly the same place) goes 3 deg back:
    // the branch with room anticlockwise.
    at = tracker.choose_branch({309.0, 18.5}, AzEl{313.87, 18.32}, -0.1, 18.0, std::nullopt, std::nullopt);
    CHECK(at == Approx(309.0 - 360.0));
}

namespace {

// A pass's targets as (az, el) along a symmetric track: rising from `el_min` at `start_az`, turning
// `span` degrees clockwise through the culmination at `top_el`; returns each target's branch.
std::vector<double> follow_pass(WrapTracker& tracker, double start_az, double span, double el_min, double top_el,
                                int steps) {
    std::vector<double> chosen;
    std::optional<AzEl> previous;
    for (int i = 0; i <= steps; ++i) {
        const double f = static_cast<double>(i) / steps;
        const AzEl target{normalize_azimuth(start_az + span * f), el_min + (top_el - el_min) * std::sin(M_PI * f)};
        chosen.push_back(tracker.choose_branch(target, previous, 0.2, el_min, std::nullopt, std::nullopt));
        previous = target;
    }
    return chosen;
}

}  // namespace

TEST_CASE("wrap tracker: an unwind no branch can spare a pass happens just past its culmination") {
    // iss-60 on the G2 (bench/passes): 257 -> 52 clockwise through north, 155 deg; the branch at
    // -103 has 124 deg of room, the one at -463 is beyond the travel. Unwound at the limit, the
    // dish turned 360 deg with the satellite at 35 deg; at the culmination (60 deg) the same turn
    // costs half as much on the sky.
    WrapTracker tracker(g2_travel, std::nullopt, {});
    tracker.note_reading(257.0, t0);
    const std::vector<double> chosen = follow_pass(tracker, 257.0, 155.0, 18.0, 60.0, 100);
    CHECK(chosen.front() == Approx(-103.0));
    CHECK(chosen[50] == Approx(334.5 - 360.0));  // the culmination, still on the first branch
    // Target 57 is the first a degree below the top (59.0): the other branch, with 396 deg of room
    // for the 88 deg still to come.
    CHECK(chosen[56] == Approx(343.8 - 360.0));
    CHECK(chosen[57] == Approx(345.35 - 720.0));
    CHECK(chosen.back() == Approx(52.0 - 360.0));  // and on it to the end, no second unwind
    for (std::size_t i = 58; i < chosen.size(); ++i) {
        CHECK(chosen[i] - chosen[i - 1] == Approx(1.55).margin(0.01));
    }
}

TEST_CASE("wrap tracker: a pass its branch holds is never unwound at its culmination") {
    // The same pass on the Trav'ler (0..455): the branch at 257 holds it to 412.
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(257.0, t0);
    const std::vector<double> chosen = follow_pass(tracker, 257.0, 155.0, 15.0, 60.0, 100);
    CHECK(chosen.front() == Approx(257.0));
    CHECK(chosen.back() == Approx(412.0));
    // iss-85's shape (300 -> 120, 180 deg): the start branch at 300 has 153 deg of room, so the
    // unwind comes at the culmination; on the branch at -60 there is none (the travel starts at 0).
    WrapTracker keyhole(travler_travel, std::nullopt, {});
    keyhole.note_reading(300.0, t0);
    const std::vector<double> over = follow_pass(keyhole, 300.0, 180.0, 15.0, 85.0, 100);
    CHECK(over.front() == Approx(300.0));
    CHECK(over[55] == Approx(399.0));
    CHECK(over[56] == Approx(400.8 - 360.0));  // the first target a degree below the top (85)
    CHECK(over.back() == Approx(120.0));
}

TEST_CASE("wrap tracker: azimuth turned below el_min does not count towards the culmination unwind") {
    // iss-45 on the Trav'ler (bench/passes): the client holds its targets at el_min from AOS
    // (300) until the satellite reaches 15 deg at 310.8, then 70.4 deg up to the culmination
    // (381.2) and 70.7 down to 451.9, inside the branch's 453 (the travel less its margin).
    // Counted from 300, the first part looked 81 deg long and the branch 5 deg too short.
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(300.0, t0);
    std::optional<AzEl> previous;
    std::vector<double> chosen;
    auto send = [&](AzEl target) {
        chosen.push_back(tracker.choose_branch(target, previous, 0.2, 15.0, std::nullopt, std::nullopt));
        previous = target;
    };
    for (double az = 300.0; az < 310.8; az += 1.0) {
        send({az, 15.0});
    }
    for (int i = 0; i <= 100; ++i) {
        const double f = i / 100.0;
        send({normalize_azimuth(310.8 + 141.1 * f), 15.0 + 30.0 * std::sin(M_PI * f)});
    }
    CHECK(chosen.back() == Approx(451.9));
    for (std::size_t i = 1; i < chosen.size(); ++i) {
        CHECK(chosen[i] - chosen[i - 1] < 3.0);  // never a turn the other way round
        CHECK(chosen[i] > chosen[i - 1]);
    }
}

TEST_CASE("wrap tracker: targets a little past the end, or after the satellite set, are held at the end") {
    // iss-45 on the Trav'ler at Gpredict's 5 deg threshold (the benchmark's targets): the pass
    // ends at 451.9, inside the 453 the backend commands; the client's lead target 93.07 (453.07)
    // was unwound to 93 - a 360 deg turn with the satellite still up, 150 deg of error after it.
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(310.7, t0);
    std::optional<AzEl> previous;
    auto send = [&](AzEl target) {
        const double chosen = tracker.choose_branch(target, previous, 0.3, 15.0, std::nullopt, std::nullopt);
        previous = target;
        return chosen;
    };
    CHECK(send({310.72, 15.0}) == Approx(310.72));
    CHECK(send({20.17, 44.99}) == Approx(380.17));
    CHECK(send({57.65, 38.51}) == Approx(417.65));
    CHECK(send({93.07, 23.39}) == Approx(453.0));  // 0.07 past: held, not unwound
    // The satellite has set: the client holds el_min while the azimuth turns on to LOS (103).
    for (double az = 94.0; az <= 103.0; az += 1.0) {
        CHECK(send({az, 15.0}) == Approx(453.0));
    }
}

TEST_CASE("wrap tracker: between sparse targets the culmination is where their elevations peak") {
    // sso-70 on the Trav'ler at Gpredict's 5 deg threshold, the targets of one benchmark run up to
    // the first a degree below the highest. The highest (75.89) lies 3.3 deg of azimuth before
    // the culmination (72.6): from it, 54 deg seemed still to come against 52 of room, and the
    // unwind waited for the limit (27.7 deg RMS). 62 are to come; the peak of a parabola through
    // the targets near the top puts it there.
    const AzEl targets[] = {{152.12, 19.96}, {148.36, 30.02}, {148.28, 30.20}, {143.04, 40.40}, {142.89, 40.65},
                            {135.11, 50.73}, {134.81, 51.03}, {124.44, 59.08}, {123.90, 59.40}, {123.91, 59.39},
                            {123.36, 59.70}, {122.78, 60.02}, {122.19, 60.34}, {121.59, 60.65}, {110.92, 64.96},
                            {110.03, 65.23}, {109.12, 65.50}, {98.64, 67.89},  {97.47, 68.09},  {96.27, 68.28},
                            {95.06, 68.46},  {93.83, 68.63},  {92.56, 68.80},  {83.01, 69.68},  {81.60, 69.76},
                            {80.18, 69.83},  {78.75, 69.89},  {77.32, 69.93},  {75.89, 69.97},  {65.79, 69.87},
                            {64.37, 69.81},  {62.95, 69.74},  {61.56, 69.65},  {57.73, 69.36},  {53.77, 68.96}};
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(156.8, t0);
    std::optional<AzEl> previous;
    double chosen = 0.0;
    for (const AzEl& target : targets) {
        chosen = tracker.choose_branch(target, previous, -0.3, 15.0, std::nullopt, std::nullopt);
        previous = target;
    }
    CHECK(chosen == Approx(53.77 + 360.0));
}

TEST_CASE("wrap tracker: a single target just outside the usable travel goes to its branch inside it") {
    // K on the Trav'ler parks at AZ 0: mechanical 0 is 2 deg short of the usable 2..453, so the
    // target is 360, not held at 2 (the hold is for a pass's last targets only).
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(180.0, t0);
    CHECK(tracker.choose_branch({0.0, 45.0}, std::nullopt, 0.0, 15.0, std::nullopt, std::nullopt) == Approx(360.0));
    WrapTracker from_low(travler_travel, std::nullopt, {});
    from_low.note_reading(30.0, t0);
    CHECK(from_low.choose_branch({0.0, 45.0}, AzEl{30.0, 45.0}, 0.0, 15.0, std::nullopt, std::nullopt) ==
          Approx(360.0));
}

TEST_CASE("wrap tracker: a reading taken back restores the previous estimate") {
    WrapTracker tracker(g2_travel, std::nullopt, {});
    tracker.note_reading(90.0, t0);
    const auto kept = tracker.mechanical();
    tracker.note_reading(13.0, t0 + 1s);
    tracker.restore_mechanical(kept);
    CHECK(*tracker.mechanical() == Approx(*kept));
    CHECK(tracker.describe().find("mechanical az") != std::string::npos);
}

TEST_CASE("wrap: the travel a pass needs from a branch, and the branch that holds it") {
    const wrap::Window travel = wrap::usable_window({0.0, 455.0});  // the Trav'ler's, 2..453
    // Rising at 100, turning 150 deg clockwise; the target before the rise waits at 100 too.
    const wrap::PassAhead low_pass{100.0, 150.0, 60.0, 300.0};
    const auto [lowest, highest] = wrap::pass_travel(100.0, 100.0, low_pass);
    CHECK(lowest == Approx(100.0));
    CHECK(highest == Approx(250.0));
    CHECK(wrap::pass_overflow(100.0, 100.0, low_pass, travel) == Approx(0.0));
    // From 350, 120 deg clockwise: 470 on the branch at 350 (17 past 453); the branch at -10 does
    // not exist, so none holds it: the least overflow, the branch at 350.
    const wrap::PassAhead across_north{350.0, 120.0, 0.0, 100.0};
    CHECK(wrap::pass_overflow(350.0, 350.0, across_north, travel) == Approx(17.0));
    REQUIRE(wrap::branch_for_pass(350.0, 350.0, across_north, travel));
    CHECK(*wrap::branch_for_pass(350.0, 350.0, across_north, travel) == Approx(350.0));
    // From 20, 90 deg anticlockwise: the branch at 20 reaches -70; the one at 380 holds it (290..380).
    const wrap::PassAhead back_across{20.0, -90.0, 30.0, 200.0};
    CHECK(wrap::pass_overflow(20.0, 20.0, back_across, travel) == Approx(72.0));
    CHECK(*wrap::branch_for_pass(20.0, 20.0, back_across, travel) == Approx(380.0));
    // A target a client's lead ahead of the satellite: the pass still starts where the satellite is.
    const auto [from, to] = wrap::pass_travel(25.0, 385.0, back_across);
    CHECK(from == Approx(290.0));
    CHECK(to == Approx(385.0));
}

TEST_CASE("wrap tracker: with the orbit's view of the pass, its branch is chosen before it rises") {
    // The Trav'ler waits at 20 (mechanical 20) for a pass that turns 90 deg anticlockwise through
    // north. The rule of thumb (180 deg of room ahead) would also move it, but only for a target
    // inside the pass-start band; the orbit says how much is needed, whatever the target.
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(20.0, t0);
    const wrap::PassAhead ahead{20.0, -90.0, 40.0, 240.0};
    CHECK(tracker.choose_branch({20.0, 15.0}, std::nullopt, 0.0, 15.0, std::nullopt, std::nullopt, ahead) ==
          Approx(380.0));
    // Later targets of the pass stay on that branch.
    const wrap::PassAhead later{20.0, -90.0, 10.0, 210.0};
    CHECK(tracker.choose_branch({19.0, 15.0}, AzEl{20.0, 15.0}, -0.2, 15.0, std::nullopt, std::nullopt, later) ==
          Approx(379.0));
    // A pass the branch holds with room to spare keeps it: no unwind for nothing.
    WrapTracker fits(travler_travel, std::nullopt, {});
    fits.note_reading(200.0, t0);
    const wrap::PassAhead short_pass{200.0, -100.0, 30.0, 200.0};
    CHECK(fits.choose_branch({200.0, 15.0}, std::nullopt, 0.0, 15.0, std::nullopt, std::nullopt, short_pass) ==
          Approx(200.0));
}

TEST_CASE("wrap tracker: with the orbit, a pass joined after its rise unwinds at its culmination, not before") {
    // Clockwise through north on the Trav'ler from mechanical 300: 170 deg to go, 153 of room.
    WrapTracker tracker(travler_travel, std::nullopt, {});
    tracker.note_reading(300.0, t0);
    const wrap::PassAhead rising{300.0, 170.0, 0.0, 60.0};
    CHECK(tracker.choose_branch({300.0, 40.0}, std::nullopt, 0.5, 15.0, std::nullopt, std::nullopt, rising) ==
          Approx(300.0));
    const wrap::PassAhead still_rising{330.0, 140.0, 0.0, 5.0};
    CHECK(tracker.choose_branch({330.0, 70.0}, AzEl{300.0, 40.0}, 0.5, 15.0, std::nullopt, std::nullopt,
                                still_rising) == Approx(330.0));
    // Just past the top, 130 deg still to come from 340: the branch at 340 has 113; the one at -20
    // does not exist; no branch holds it, so it stays (and holds or unwinds at the limit later).
    const wrap::PassAhead past_top{340.0, 130.0, 0.0, -1.0};
    CHECK(tracker.choose_branch({340.0, 80.0}, AzEl{330.0, 70.0}, 0.5, 15.0, std::nullopt, std::nullopt, past_top) ==
          Approx(340.0));

    // Anticlockwise from 60 through north to 270: 150 deg to go past the top; the branch at 60 has
    // 58 of room, the one at 420 holds it: the unwind happens now, once.
    WrapTracker high(travler_travel, std::nullopt, {});
    high.note_reading(80.0, t0);
    const wrap::PassAhead before_top{80.0, -170.0, 0.0, 10.0};
    CHECK(high.choose_branch({80.0, 60.0}, std::nullopt, -0.5, 15.0, std::nullopt, std::nullopt, before_top) ==
          Approx(80.0));
    const wrap::PassAhead after_top{60.0, -150.0, 0.0, -0.5};
    CHECK(high.choose_branch({60.0, 84.0}, AzEl{80.0, 60.0}, -2.0, 15.0, std::nullopt, std::nullopt, after_top) ==
          Approx(420.0));
    // Checked once per pass: the next target continues on the new branch.
    const wrap::PassAhead further{40.0, -130.0, 0.0, -3.0};
    CHECK(high.choose_branch({40.0, 80.0}, AzEl{60.0, 84.0}, -2.0, 15.0, std::nullopt, std::nullopt, further) ==
          Approx(400.0));
}
