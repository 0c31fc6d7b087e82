// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The pure cable-wrap logic (wrap.hpp): branches, the branch rule, waypoints.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "base/azel.hpp"
#include "firmware/variants.hpp"
#include "tracking/wrap.hpp"

using namespace birdcage;
using wrap::Reason;
using wrap::Window;

namespace {

Window travel(VariantId id) {
    return {profile(id).az_min, profile(id).az_max};
}

const Window g2 = travel(VariantId::carryout_g2);          // -423.33 .. 23.33
const Window travler = travel(VariantId::travler_hal205);  // 0 .. 455

// A model of the firmware's mapping as the emulator implements it (sim resolve_target): a 0..360
// command goes to the branch inside the travel nearest the axis' current target. ("The shortest
// way round, reversing at the limit" lands on the same branch, so this covers both readings of
// the notes.)
double firmware_resolves(double display, double axis_target, Window mechanical) {
    double best = axis_target;
    double best_distance = -1;
    for (double candidate : wrap::branches(display, mechanical)) {
        if (best_distance < 0 || std::fabs(candidate - axis_target) < best_distance) {
            best = candidate;
            best_distance = std::fabs(candidate - axis_target);
        }
    }
    return best;
}

// Where a nearest-branch firmware ends after the backend sends `mechanical` values as 0..360.
double after_commands(double start, const std::vector<double>& mechanical, Window window) {
    double at = start;
    for (double step : mechanical) {
        at = firmware_resolves(normalize_azimuth(step), at, window);
    }
    return at;
}

struct Followed {
    std::vector<double> mechanical;
    std::vector<Reason> reasons;
};

// Feeds a pass (display azimuths) through choose_branch() the way the controller does: the
// first target may start a pass, the reference is always the previous choice.
Followed follow(const std::vector<double>& azimuths, double start_mechanical, int direction, bool hint_at_start,
                Window mechanical) {
    const Window usable = wrap::usable_window(mechanical);
    Followed out;
    double reference = start_mechanical;
    for (std::size_t i = 0; i < azimuths.size(); ++i) {
        const auto choice = wrap::choose_branch(azimuths[i], reference, direction, hint_at_start && i == 0, usable);
        out.mechanical.push_back(choice.mechanical);
        out.reasons.push_back(choice.reason);
        reference = choice.mechanical;
    }
    return out;
}

std::vector<double> sweep(double from, double to, double step) {
    std::vector<double> out;
    const double span = to - from;
    const int count = static_cast<int>(std::ceil(std::fabs(span) / step));
    for (int i = 0; i <= count; ++i) {
        out.push_back(normalize_azimuth(from + span * i / count));
    }
    return out;
}

// Largest change between consecutive entries.
double largest_step(const std::vector<double>& values) {
    double largest = 0;
    for (std::size_t i = 1; i < values.size(); ++i) {
        largest = std::max(largest, std::fabs(values[i] - values[i - 1]));
    }
    return largest;
}

}  // namespace

TEST_CASE("wrap: the usable window keeps 2 deg from each limit where the travel allows") {
    const Window g2_usable = wrap::usable_window(g2);
    CHECK(g2_usable.min == Approx(-421.33));
    CHECK(g2_usable.max == Approx(21.33));
    const Window travler_usable = wrap::usable_window(travler);
    CHECK(travler_usable.min == Approx(2));
    CHECK(travler_usable.max == Approx(453));
    // 0..360 (Carryout): no margin, or north would become unreachable.
    const Window carryout = wrap::usable_window(travel(VariantId::carryout2003));
    CHECK(carryout.min == Approx(0));
    CHECK(carryout.max == Approx(360));
    // A 363-deg travel: 1.5 deg each side keeps every azimuth reachable.
    const Window narrow = wrap::usable_window({0, 363});
    CHECK(narrow.min == Approx(1.5));
    CHECK(narrow.max == Approx(361.5));
}

TEST_CASE("wrap: branches, nearest branch, unwrapped readings and the start assumption") {
    CHECK(wrap::branches(10, g2) == std::vector<double>{-350, 10});
    CHECK(wrap::branches(180, g2) == std::vector<double>{-180});
    CHECK(wrap::branches(300, g2) == std::vector<double>{-420, -60});
    CHECK(wrap::branches(50, travler) == std::vector<double>{50, 410});
    CHECK(wrap::branches(200, travler) == std::vector<double>{200});

    CHECK(wrap::nearest_branch(10, 400) == Approx(370));
    CHECK(wrap::nearest_branch(350, 5) == Approx(-10));
    CHECK(wrap::nearest_branch(-90, 400) == Approx(270));  // -180..180 input
    CHECK(wrap::nearest_branch(270, 400) == Approx(270));

    // Readings unwrap to the in-travel branch nearest the estimate.
    CHECK(wrap::unwrap_reading(12, -350, g2) == Approx(-348));
    CHECK(wrap::unwrap_reading(12, 10, g2) == Approx(12));
    CHECK(wrap::unwrap_reading(50, 400, travler) == Approx(410));
    CHECK(wrap::unwrap_reading(50, 200, travler) == Approx(50));
    CHECK(wrap::unwrap_reading(100, 0, g2) == Approx(-260));  // the only branch, however far
    CHECK(wrap::unwrap_reading(24, 20, g2) == Approx(24));    // 1 deg of overshoot past the limit

    // Start: the branch nearest AZ 0 (G2 homes there); the reading itself on the Trav'ler.
    CHECK(wrap::start_branch(10, g2) == Approx(10));
    CHECK(wrap::start_branch(350, g2) == Approx(-10));
    CHECK(wrap::start_branch(180, g2) == Approx(-180));
    CHECK(wrap::start_branch(50, travler) == Approx(50));
    CHECK(wrap::start_branch(300, travler) == Approx(300));
}

TEST_CASE("wrap: the -180..180 azimuth mode picks the same branch as 0..360") {
    const Window usable = wrap::usable_window(g2);
    for (double az : {-179.0, -120.0, -60.0, -10.0, -0.5}) {
        INFO(az);
        const auto negative = wrap::choose_branch(az, -300, 0, false, usable);
        const auto positive = wrap::choose_branch(az + 360.0, -300, 0, false, usable);
        CHECK(negative.mechanical == Approx(positive.mechanical));
        CHECK(negative.reason == positive.reason);
    }
}

TEST_CASE("wrap: a clockwise pass across north on the G2 starts on the branch with room for it") {
    // 300 -> 60 clockwise: 120 deg across north. The G2 starts at 300 = mechanical -60, where only
    // 81 deg are left before +21.33: the pass-start rule moves it to -420 first.
    const auto pass = sweep(300, 420, 2);
    const auto followed = follow(pass, wrap::start_branch(300, g2), +1, true, g2);
    CHECK(followed.mechanical.front() == Approx(-420));
    CHECK(followed.reasons.front() == Reason::pass_start);
    CHECK(followed.mechanical.back() == Approx(-300));
    CHECK(largest_step({followed.mechanical.begin(), followed.mechanical.end()}) <= 2.0 + 1e-9);
    for (std::size_t i = 1; i < followed.reasons.size(); ++i) {
        CHECK(followed.reasons[i] == Reason::continuous);
    }

    SECTION("without a rate hint it unwinds once, at the margin, not at the limit stop") {
        const auto blind = follow(pass, -60, 0, false, g2);
        int unwinds = 0;
        for (std::size_t i = 0; i < blind.reasons.size(); ++i) {
            if (blind.reasons[i] == Reason::forced_unwind) {
                ++unwinds;
                CHECK(blind.mechanical[i - 1] <= 21.33 + 1e-9);
                CHECK(blind.mechanical[i - 1] > 21.33 - 2.0 - 1e-9);  // it went as far as the margin allows
                CHECK(blind.mechanical[i] == Approx(blind.mechanical[i - 1] + 2.0 - 360.0));
            }
        }
        CHECK(unwinds == 1);
    }
}

TEST_CASE("wrap: an anticlockwise pass across north on the G2 fits by continuity") {
    // 60 -> 300 anticlockwise: 60 is only -300 on the G2, and the pass ends at -420, inside.
    const auto pass = sweep(60, -60, 2);
    const auto followed = follow(pass, wrap::start_branch(60, g2), -1, true, g2);
    CHECK(followed.mechanical.front() == Approx(-300));
    CHECK(followed.mechanical.back() == Approx(-420));
    CHECK(largest_step(followed.mechanical) <= 2.0 + 1e-9);
    for (Reason reason : followed.reasons) {
        CHECK(reason == Reason::continuous);
    }
}

TEST_CASE("wrap: passes across north on the Trav'ler's 0..455") {
    SECTION("clockwise 300 -> 60 continues past 360 to 420") {
        const auto followed = follow(sweep(300, 420, 2), 300, +1, true, travler);
        CHECK(followed.mechanical.front() == Approx(300));
        CHECK(followed.mechanical.back() == Approx(420));
        CHECK(largest_step(followed.mechanical) <= 2.0 + 1e-9);
    }
    SECTION("clockwise without a hint: continuity alone fits it") {
        const auto followed = follow(sweep(300, 420, 2), 300, 0, false, travler);
        CHECK(followed.mechanical.back() == Approx(420));
        CHECK(largest_step(followed.mechanical) <= 2.0 + 1e-9);
    }
    SECTION("anticlockwise 60 -> 300 starts on 420, not 60 (58 deg from the stop)") {
        const auto followed = follow(sweep(60, -60, 2), 60, -1, true, travler);
        CHECK(followed.mechanical.front() == Approx(420));
        CHECK(followed.reasons.front() == Reason::pass_start);
        CHECK(followed.mechanical.back() == Approx(300));
        CHECK(largest_step({followed.mechanical.begin() + 1, followed.mechanical.end()}) <= 2.0 + 1e-9);
    }
    SECTION("a pass start keeps the nearest branch when it has room for a whole pass") {
        const auto choice = wrap::choose_branch(50, 50, +1, true, wrap::usable_window(travler));
        CHECK(choice.mechanical == Approx(50));
        CHECK(choice.reason == Reason::continuous);
    }
    SECTION("a pass start leaves a branch with little room ahead for one with enough") {
        const auto choice = wrap::choose_branch(20, 20, -1, true, wrap::usable_window(travler));
        CHECK(choice.mechanical == Approx(380));  // 20 has 18 deg left anticlockwise, 380 has 378
        CHECK(choice.reason == Reason::pass_start);
    }
    SECTION("a pass start with no branch that has 180 deg ahead takes the one with the most room") {
        // G2, 60 anticlockwise: -300 is the only branch, 121.33 deg from -421.33.
        const auto choice = wrap::choose_branch(60, -300, -1, true, wrap::usable_window(g2));
        CHECK(choice.mechanical == Approx(-300));
        CHECK(choice.reason == Reason::continuous);
    }
}

TEST_CASE("wrap: forced unwinds go to the branch with the most room ahead") {
    const Window usable = wrap::usable_window(travler);
    SECTION("clockwise past 453 on the Trav'ler") {
        const auto choice = wrap::choose_branch(94, 453, +1, false, usable);
        CHECK(choice.reason == Reason::forced_unwind);
        CHECK(choice.mechanical == Approx(94));
        CHECK(choice.continuous == Approx(454));
    }
    SECTION("anticlockwise below 2 on the Trav'ler") {
        const auto choice = wrap::choose_branch(1, 3, -1, false, usable);
        CHECK(choice.reason == Reason::forced_unwind);
        CHECK(choice.mechanical == Approx(361));
    }
    SECTION("no hint: the nearest branch inside the window") {
        const auto choice = wrap::choose_branch(25, 20, 0, false, wrap::usable_window(g2));
        CHECK(choice.reason == Reason::forced_unwind);
        CHECK(choice.mechanical == Approx(-335));
    }
    SECTION("never outside the usable window, whatever the reference") {
        for (const Window travel_window : {g2, travler}) {
            const Window inside = wrap::usable_window(travel_window);
            for (double reference = travel_window.min - 50; reference <= travel_window.max + 50; reference += 7.3) {
                for (double az = 0; az < 360; az += 3.7) {
                    for (int direction : {-1, 0, 1}) {
                        for (bool starting : {false, true}) {
                            const double chosen =
                                wrap::choose_branch(az, reference, direction, starting, inside).mechanical;
                            REQUIRE(inside.contains(chosen));
                            REQUIRE(normalize_azimuth(chosen) == Approx(az).margin(1e-9));
                        }
                    }
                }
            }
        }
    }
}

TEST_CASE("wrap: waypoints steer a nearest-branch firmware onto the intended branch") {
    SECTION("G2 pass start -60 -> -420") {
        const auto steps = wrap::waypoints(-60, -420);
        CHECK(steps == std::vector<double>{-180, -300, -420});
        CHECK(after_commands(-60, steps, g2) == Approx(-420));
        // Sent directly, 300 would resolve to where the dish already is.
        CHECK(after_commands(-60, {-420}, g2) == Approx(-60));
    }
    SECTION("Trav'ler pass start 60 -> 420") {
        const auto steps = wrap::waypoints(60, 420);
        CHECK(steps == std::vector<double>{180, 300, 420});
        CHECK(after_commands(60, steps, travler) == Approx(420));
        CHECK(after_commands(60, {420}, travler) == Approx(60));
    }
    SECTION("short moves are a single leg") {
        CHECK(wrap::waypoints(10, 170) == std::vector<double>{170});
        CHECK(wrap::next_waypoint(-20, -190) == Approx(-190));
        CHECK(wrap::next_waypoint(0, 171) == Approx(85.5));
    }
    SECTION("every pair of points in both travels: legs of at most 170 that end on the intended branch") {
        for (const Window travel_window : {g2, travler}) {
            const Window inside = wrap::usable_window(travel_window);
            for (double from = inside.min; from <= inside.max; from += 9.7) {
                for (double to = inside.min; to <= inside.max; to += 11.3) {
                    const auto steps = wrap::waypoints(from, to);
                    REQUIRE(!steps.empty());
                    REQUIRE(steps.back() == to);
                    double at = from;
                    for (double step : steps) {
                        REQUIRE(std::fabs(step - at) <= wrap::max_leg_deg + 1e-9);
                        REQUIRE(inside.contains(step));
                        at = step;
                    }
                    INFO("from " << from << " to " << to);
                    REQUIRE(after_commands(from, steps, travel_window) == Approx(to).margin(1e-9));
                }
            }
        }
    }
}
