// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A dish still moving when the backend starts. A Trav'ler Pro prints no ready line (docs/firmware.md
// 5.2): it boots (deaf), runs its boot moves, starts its TV search, and the backend stops the
// search once its console answers; the emulated axes then brake to a stop over seconds, so the
// backend's first readings and the client's first target come while the dish still moves. Its
// cable-wrap branch and its first leg must wait for the dish at rest: the dish must end on the
// target, on a branch its travel allows, with the backend knowing where it is.
//
// The console is the dialect generator's Trav'ler Pro of the dialects matrix's cell that failed
// under load (its motor: 26.6 deg/s, braking at 4.8 deg/s2, a 2.4 s start-up delay), run in dish
// time (emulated_console.hpp): the same on a loaded machine as on an idle one. The moment the
// backend starts is varied along the search.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "base/azel.hpp"
#include "birdcage_sim/dialect.hpp"
#include "dish/controller.hpp"
#include "emulated_console.hpp"
#include "tracking/wrap.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

constexpr double target_az = 150.0, target_el = 40.0;
constexpr std::uint32_t dialect_seed = 17;

}  // namespace

TEST_CASE("start at rest: a dish still moving when the backend starts ends on the target", "[start_rest]") {
    const sim::TravlerBootMoves boot_moves =
        GENERATE(sim::TravlerBootMoves::park, sim::TravlerBootMoves::home_return, sim::TravlerBootMoves::none);
    const int search_ms = GENERATE(range(1, 12)) * 1700;  // how long the search runs before the backend starts
    const int idle_steps = GENERATE(0, 10);               // worker steps between the start and the target
    INFO("boot moves " << sim::travler_boot_moves_name(boot_moves) << ", search for " << search_ms << " ms, "
                       << idle_steps << " idle steps");
    sim::Options o = sim::draw_dialect(sim::Variant::travler_pro, dialect_seed).options;
    o.already_booted = false;
    o.travler_boot_moves = boot_moves;
    o.start_az = 100.0;
    o.start_el = 30.0;
    test::EmulatedConsole dish(o);
    ControllerOptions options{};
    options.variant = VariantId::travler_pro;
    options.leapfrog = false;
    options.clock = dish.clock();
    Controller controller(dish, options);

    for (int ticks = 0; ticks < 3000 && (dish.console().booting() || !dish.console().search_running()); ++ticks) {
        dish.tick(100ms);
    }
    REQUIRE(dish.console().search_running());
    dish.tick(std::chrono::milliseconds(search_ms));

    // As the service worker runs: initialise, read the position once more, step every 50 ms (an
    // idle worker reads the position every second), take the client's target, step until the
    // dish is at rest and the controller idle (a bound of dish time, not a timing assertion),
    // and read the position as an idle worker does.
    const Status initialised = controller.initialize();
    INFO(initialised.message);
    REQUIRE(initialised);
    (void)controller.query_position();
    const bool moving_at_start = dish.console().moving();
    for (int step = 1; step <= idle_steps; ++step) {
        dish.tick(50ms);
        const Status status = controller.service();
        INFO(status.message);
        REQUIRE(status);
    }
    REQUIRE(controller.set_target({target_az, target_el}));
    int steps = 0;
    for (; steps < 6000 && (!controller.idle() || dish.console().moving()); ++steps) {
        dish.tick(50ms);
        const Status status = controller.service();
        INFO(status.message);
        REQUIRE((status || status.code == Errc::timeout));
    }
    REQUIRE(steps < 6000);
    dish.tick(1s);
    REQUIRE(controller.query_position());

    const sim::Pose pose = dish.console().position();
    const double mechanical = dish.console().mechanical_az();
    INFO("dish at rest at az " << pose.az << " (mechanical " << mechanical << ") el " << pose.el
                               << (moving_at_start ? "; it was moving when the backend started" : ""));
    CHECK(std::fabs(azimuth_difference(pose.az, target_az)) <= 0.1);
    CHECK(std::fabs(pose.el - target_el) <= 0.1);
    CHECK(controller.wrap_tracker().window().contains(mechanical));
    const auto estimate = controller.mechanical_azimuth();
    REQUIRE(estimate);
    CHECK(*estimate == Approx(mechanical).margin(0.3));
    CHECK(dish.console().hazards() == 0);
}
