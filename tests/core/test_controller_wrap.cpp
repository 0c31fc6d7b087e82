// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The controller's cable-wrap handling against a scripted dish that maps 0..360 commands onto its
// wrap window the way the emulator does (nearest branch to the axis' target), with either
// azimuth report (displayed 0..360 or mechanical).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "fake_transport.hpp"
#include "tracking/wrap.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;
using Commands = std::vector<std::string>;

namespace {

struct FakeClock {
    Clock::time_point now = Clock::time_point{} + 1h;
};

std::string two_decimals(double value) {
    char text[64];
    std::snprintf(text, sizeof text, "%.2f", value);
    return text;
}

double approach(double from, double to, double step) {
    return std::fabs(to - from) <= step ? to : from + (to > from ? step : -step);
}

// A G2 (TRK>/MOT>, `Angle[n] =`) or Trav'ler HAL 2.05 (no prompt, `AZ = .. EL = ..`) console whose
// azimuth has a cable-wrap window. Axes move `step` degrees per position query.
struct WrapDish {
    bool g2 = true;
    wrap::Window window;
    bool report_mechanical = false;
    double mech = 0, el = 45, target_mech = 0, target_el = 45;
    double step = 30.0;
    std::string menu = "TRK";
    std::vector<double> resolved;    // the mechanical target of every azimuth command
    std::vector<double> sent;        // the value of every azimuth command as sent
    std::vector<double> trajectory;  // the mechanical azimuth at every query

    // sim resolve_target(): 0..360 goes to the branch nearest the axis' target; a value outside
    // 0..360 but inside the window is taken literally.
    double resolve(double value) const {
        if (value < 0.0 || value >= 360.0) {
            return std::clamp(value, window.min, window.max);
        }
        double best = target_mech;
        double best_distance = -1;
        for (double candidate : wrap::branches(value, window)) {
            if (best_distance < 0 || std::fabs(candidate - target_mech) < best_distance) {
                best = candidate;
                best_distance = std::fabs(candidate - target_mech);
            }
        }
        return best;
    }

    std::vector<std::string> respond(const std::string& command) {
        std::istringstream in(command);
        std::vector<std::string> words;
        for (std::string word; in >> word;) {
            words.push_back(word);
        }
        std::string out = command + "\r\n";
        const bool motor_menu = !g2 || menu == "MOT";
        if (g2 && !words.empty() && words[0] == "mot") {
            menu = "MOT";
        } else if (g2 && !words.empty() && words[0] == "q") {
            menu = "TRK";
        } else if (words.size() == 1 && words[0] == "?") {
            out += "a - position\r\nq - quit\r\n";  // a live console lists its menu
        } else if (motor_menu && words.size() == 1 && words[0] == "a") {
            mech = approach(mech, target_mech, step);
            el = approach(el, target_el, step);
            trajectory.push_back(mech);
            const double az = report_mechanical ? mech : normalize_azimuth(mech);
            out += g2 ? "Angle[0] = " + two_decimals(az) + "\r\nAngle[1] = " + two_decimals(el) + "\r\n"
                      : "AZ = " + two_decimals(az) + " EL = " + two_decimals(el) + " SK = 0.00\r\n";
        } else if (motor_menu && words.size() == 3 && words[0] == "a") {
            const double value = std::stod(words[2]);
            if (words[1] == "0") {
                sent.push_back(value);
                target_mech = resolve(value);
                resolved.push_back(target_mech);
            } else {
                target_el = value;
            }
            if (g2) {
                out += "Angle = " + two_decimals(words[1] == "0" && report_mechanical ? target_mech : value) + "\r\n";
            }
        }
        if (!g2) {
            return {out};
        }
        return {out, menu + ">"};
    }
};

struct Bench {
    WrapDish dish;
    FakeTransport wire{[this](const std::string& c) { return dish.respond(c); }};
    FakeClock clock;
    std::vector<std::string> log;
    std::optional<Controller> controller;

    Bench(VariantId variant, double start_mech, double start_el, bool report_mechanical) {
        const FirmwareProfile& row = profile(variant);
        dish.g2 = variant == VariantId::carryout_g2;
        dish.window = {row.az_min, row.az_max};
        dish.report_mechanical = report_mechanical;
        dish.mech = dish.target_mech = start_mech;
        dish.el = dish.target_el = start_el;
        ControllerOptions options{};
        options.variant = variant;
        options.leapfrog = false;
        options.clock = DishClock::manual([this] { return clock.now; });
        options.log = [this](LogLevel, const std::string& message) { log.push_back(message); };
        controller.emplace(wire, options);
    }

    void run_until_idle() {
        for (int calls = 0; calls < 2000; ++calls) {
            clock.now += 100ms;
            const Status status = controller->service();
            INFO(status.message);
            REQUIRE(status);
            if (controller->idle()) {
                return;
            }
        }
        FAIL("controller never became idle");
    }

    // Sends the target, runs it to the end, and returns the dish's mechanical azimuth.
    double go(double az, double el, double rate) {
        REQUIRE(controller->set_target({az, el}, rate));
        run_until_idle();
        return dish.mech;
    }

    bool logged(const std::string& text) const {
        return std::any_of(log.begin(), log.end(),
                           [&](const std::string& m) { return m.find(text) != std::string::npos; });
    }
};

struct PassPoint {
    double az, el;
};

// A pass from az0 over `span` degrees (signed), elevation from el_min up to el_peak and back.
std::vector<PassPoint> pass(double az0, double span, double el_min, double el_peak, int points) {
    std::vector<PassPoint> out;
    for (int i = 0; i <= points; ++i) {
        const double f = static_cast<double>(i) / points;
        out.push_back({az0 + span * f, el_min + (el_peak - el_min) * std::sin(f * 3.14159265358979)});
    }
    return out;
}

// Every azimuth command resolved inside the usable window, and was a number the console has for
// an absolute move: 0..360 where '-' means relative (G2), else the mechanical angle in the travel.
void check_commands_safe(const WrapDish& dish) {
    const wrap::Window usable = wrap::usable_window(dish.window);
    for (double value : dish.sent) {
        CHECK(value >= 0.0);
        CHECK(value < (dish.g2 ? 360.0 : usable.max + 0.01));
    }
    for (double mech : dish.resolved) {
        CHECK(mech >= usable.min - 0.01);
        CHECK(mech <= usable.max + 0.01);
    }
}

// Largest change of the dish's mechanical azimuth between consecutive queries from `from` on.
double largest_move(const WrapDish& dish, std::size_t from) {
    double largest = 0;
    for (std::size_t i = from + 1; i < dish.trajectory.size(); ++i) {
        largest = std::max(largest, std::fabs(dish.trajectory[i] - dish.trajectory[i - 1]));
    }
    return largest;
}

}  // namespace

TEST_CASE("controller wrap: a clockwise pass across north on the G2 is followed without an unwind") {
    const bool mechanical = GENERATE(false, true);
    INFO((mechanical ? "mechanical" : "displayed") << " azimuth report");
    Bench bench(VariantId::carryout_g2, -60.0, 18.0, mechanical);  // 300 = -60 after homing
    REQUIRE(bench.controller->initialize());
    REQUIRE(bench.controller->mechanical_azimuth());
    CHECK(*bench.controller->mechanical_azimuth() == Approx(-60));

    const auto points = pass(300, 120, 18, 60, 30);  // 300 -> 60 clockwise
    // Pass start: -60 has 81 deg left before +21.33; the controller moves to -420 by waypoints.
    CHECK(bench.go(points[0].az, points[0].el, 0.5) == Approx(-420).margin(0.01));
    CHECK(bench.logged("a pass is starting"));
    CHECK(bench.dish.resolved == std::vector<double>{-180, -300, -420});
    const std::size_t started = bench.dish.trajectory.size();
    for (std::size_t i = 1; i < points.size(); ++i) {
        const double mech = bench.go(points[i].az, points[i].el, 0.5);
        CHECK(mech == Approx(-420 + points[i].az - 300).margin(0.01));
        CHECK(*bench.controller->mechanical_azimuth() == Approx(mech).margin(0.01));
        CHECK(bench.controller->last_position()->az == Approx(normalize_azimuth(mech)).margin(0.01));
    }
    CHECK(bench.dish.mech == Approx(-300).margin(0.01));
    CHECK(largest_move(bench.dish, started) <= 4.0 + 0.01);  // one target step, never an unwind
    check_commands_safe(bench.dish);
    CHECK(bench.controller->describe_wrap().find("mechanical az -300.00") != std::string::npos);
}

// 150 -> 330 on the G2 is 180 deg either way round: two legs, by 240, so that the firmware cannot
// take the other way. `_` names the waypoint while that leg runs (where a stop would land).
TEST_CASE("controller wrap: describe() names the waypoint a long azimuth move goes by while it runs") {
    Bench bench(VariantId::carryout_g2, -210.0, 30.0, false);  // 150 = -210 after homing
    REQUIRE(bench.controller->initialize());
    CHECK(bench.controller->describe().find("waypoints") == std::string::npos);
    REQUIRE(bench.controller->set_target({330.0, 30.0}, 0.0));
    std::string while_first_leg;
    for (int calls = 0; calls < 200 && bench.dish.sent.size() < 2; ++calls) {
        bench.clock.now += 100ms;
        REQUIRE(bench.controller->service());
        if (bench.dish.sent.size() == 1 && while_first_leg.empty()) {
            while_first_leg = bench.controller->describe();
        }
    }
    CHECK(bench.dish.sent == std::vector<double>{240.0, 330.0});
    CHECK(while_first_leg.find(
              "; target az 330.00 el 30.00; azimuth by waypoints: the leg under way ends at az 240.00") !=
          std::string::npos);
    bench.run_until_idle();
    CHECK(bench.dish.mech == Approx(-30).margin(0.01));
    CHECK(bench.controller->describe().find("waypoints") == std::string::npos);
}

TEST_CASE("controller wrap: an anticlockwise pass across north on the Trav'ler starts on 420") {
    const bool mechanical = GENERATE(false, true);
    INFO((mechanical ? "mechanical" : "displayed") << " azimuth report");
    Bench bench(VariantId::travler_hal205, 60.0, 15.0, mechanical);
    REQUIRE(bench.controller->initialize());
    CHECK(*bench.controller->mechanical_azimuth() == Approx(60));  // the reading itself

    const auto points = pass(60, -120, 15, 70, 30);  // 60 -> 300 anticlockwise
    CHECK(bench.go(points[0].az, points[0].el, -0.5) == Approx(420).margin(0.01));
    CHECK(bench.dish.resolved == std::vector<double>{180, 300, 420});
    const std::size_t started = bench.dish.trajectory.size();
    for (std::size_t i = 1; i < points.size(); ++i) {
        bench.go(points[i].az, points[i].el, -0.5);
    }
    CHECK(bench.dish.mech == Approx(300).margin(0.01));
    CHECK(largest_move(bench.dish, started) <= 4.0 + 0.01);
    check_commands_safe(bench.dish);
}

TEST_CASE("controller wrap: without a rate hint, continuity alone carries a Trav'ler across north") {
    const bool mechanical = GENERATE(false, true);
    Bench bench(VariantId::travler_hal205, 300.0, 15.0, mechanical);
    REQUIRE(bench.controller->initialize());
    for (const PassPoint& p : pass(300, 120, 15, 50, 30)) {
        bench.go(p.az, p.el, 0.0);
    }
    CHECK(bench.dish.mech == Approx(420).margin(0.01));
    CHECK(largest_move(bench.dish, 0) <= 4.0 + 0.01);
    CHECK(bench.dish.resolved.size() == 30);  // one azimuth leg per later target, no waypoints
    check_commands_safe(bench.dish);
}

TEST_CASE("controller wrap: the end of a pass never restarts it (el falling to el_min, noisy rate sign)") {
    Bench bench(VariantId::travler_hal205, 300.0, 15.0, false);
    REQUIRE(bench.controller->initialize());
    const auto points = pass(300, 120, 15, 40, 30);
    for (std::size_t i = 0; i < points.size(); ++i) {
        // Near the end the rate estimate flickers through zero and changes sign.
        const double rate = i + 3 >= points.size() ? (i % 2 == 0 ? -0.01 : 0.0) : 0.4;
        bench.go(points[i].az, points[i].el, rate);
    }
    // At 420 only 33 deg are left clockwise and 60 has 393: a pass-start decision here would unwind.
    CHECK(bench.dish.mech == Approx(420).margin(0.01));
    CHECK(largest_move(bench.dish, 0) <= 4.0 + 0.01);
    CHECK_FALSE(bench.logged("a pass is starting"));
}

TEST_CASE("controller wrap: a pass no branch holds unwinds just past its culmination") {
    // G2, anticlockwise 40 -> 260 (140 deg): 40 is only -320, 101 deg from -421.33, and +40 is
    // beyond the travel. At the culmination (330, mechanical -390) 70 deg are still to come and 31
    // are left: the unwind comes with the first target a degree lower (316: -404 becomes -44),
    // where it costs least on the sky.
    Bench bench(VariantId::carryout_g2, -320.0, 18.0, false);
    REQUIRE(bench.controller->initialize());
    double lowest = 0;
    for (const PassPoint& p : pass(40, -140, 18, 50, 35)) {
        lowest = std::min(lowest, bench.go(p.az, p.el, -0.5));
    }
    CHECK(lowest >= -421.33 - 0.01);                      // never beyond the margin, never at the stop
    CHECK(lowest >= -400.0 - 0.01);                       // turned back well before it
    CHECK(bench.dish.mech == Approx(-100).margin(0.01));  // 260 after one unwind
    CHECK(bench.logged("past its culmination"));
    CHECK_FALSE(bench.logged("continuing would pass the wrap limit"));
    check_commands_safe(bench.dish);
}

TEST_CASE("controller wrap: a pass picked up mid-way unwinds at the margin when it cannot fit") {
    // The same pass, the client starting with the satellite at 39 deg: its start unseen, the
    // azimuth still to come is unknown, so the unwind waits for the limit (less the margin).
    Bench bench(VariantId::carryout_g2, -320.0, 18.0, false);
    REQUIRE(bench.controller->initialize());
    double lowest = 0;
    const auto points = pass(40, -140, 18, 50, 35);
    for (std::size_t i = 8; i < points.size(); ++i) {
        lowest = std::min(lowest, bench.go(points[i].az, points[i].el, -0.5));
    }
    CHECK(lowest >= -421.33 - 0.01);
    CHECK(lowest < -419.0);
    CHECK(bench.dish.mech == Approx(-100).margin(0.01));
    CHECK(bench.logged("continuing would pass the wrap limit"));
    check_commands_safe(bench.dish);
}

TEST_CASE("controller wrap: -180..180 azimuths drive the dish exactly like 0..360") {
    std::vector<double> resolved[2];
    for (int form = 0; form < 2; ++form) {
        Bench bench(VariantId::carryout_g2, -60.0, 18.0, false);
        REQUIRE(bench.controller->initialize());
        for (const PassPoint& p : pass(300, 120, 18, 60, 30)) {
            const double az = normalize_azimuth(p.az);
            bench.go(form == 0 ? az : (az > 180.0 ? az - 360.0 : az), p.el, 0.5);
        }
        resolved[form] = bench.dish.resolved;
    }
    CHECK(resolved[0] == resolved[1]);
}

TEST_CASE("controller wrap: a repeated identical target is a no-op, whatever the rate hint") {
    Bench bench(VariantId::carryout_g2, -60.0, 18.0, false);
    REQUIRE(bench.controller->initialize());
    bench.go(310, 30, 0.5);
    const std::size_t mark = bench.wire.commands().size();
    REQUIRE(bench.controller->set_target({310, 30}, 0.5));
    CHECK(bench.controller->idle());
    REQUIRE(bench.controller->set_target({-50, 30}, -0.2));  // the same target in -180..180
    CHECK(bench.controller->idle());
    bench.controller->service();
    CHECK(bench.wire.commands().size() == mark);
}

TEST_CASE("controller wrap: the estimate survives a re-initialisation only if the dish still reads it") {
    Bench bench(VariantId::travler_hal205, 300.0, 15.0, false);
    REQUIRE(bench.controller->initialize());
    for (const PassPoint& p : pass(300, 100, 15, 50, 10)) {
        bench.go(p.az, p.el, 0.0);
    }
    REQUIRE(*bench.controller->mechanical_azimuth() == Approx(400).margin(0.01));
    SECTION("lost sync, dish where it was: still 400") {
        REQUIRE(bench.controller->reinitialize(10s));
        CHECK(*bench.controller->mechanical_azimuth() == Approx(400).margin(0.01));
    }
    SECTION("the dish moved (rebooted and calibrated): the start assumption again") {
        bench.dish.mech = bench.dish.target_mech = 90;
        REQUIRE(bench.controller->reinitialize(10s));
        CHECK(*bench.controller->mechanical_azimuth() == Approx(90).margin(0.01));
    }
}

TEST_CASE("controller wrap: an azimuth that prints as 360.00 is sent as 0.00 where 360 is no angle of the travel") {
    Bench bench(VariantId::carryout_g2, -10.0, 30.0, false);
    REQUIRE(bench.controller->initialize());
    bench.go(359.997, 30, 0.0);
    REQUIRE(bench.dish.sent.size() == 1);
    CHECK(bench.dish.sent.front() == 0.0);
    CHECK(bench.dish.mech == Approx(0.0));  // the branch continuous with -10
    CHECK(bench.controller->idle());
}

TEST_CASE("controller wrap: on the Trav'ler the mechanical angle itself is sent, 360.00 included") {
    Bench bench(VariantId::travler_hal205, 350.0, 30.0, false);
    REQUIRE(bench.controller->initialize());
    bench.go(359.997, 30, 0.0);
    REQUIRE(bench.dish.sent.size() == 1);
    CHECK(bench.dish.sent.front() == 360.0);
    CHECK(bench.dish.mech == Approx(360.0));  // the branch continuous with 350
    bench.go(43.0, 30, 0.0);
    CHECK(bench.dish.sent.back() == 403.0);
    CHECK(bench.dish.mech == Approx(403.0));
}
