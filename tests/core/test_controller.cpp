// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The Controller over scripted consoles of every variant: initialisation, moves per move style,
// stop, leapfrog, homing, faults. Over 500 lines because it is the one place each variant's row is
// exercised through the composed controller; the parts have their own files (wrap tracker,
// synchroniser, session, az mapping).
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "fake_transport.hpp"
#include "tracking/position_model.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;
using Commands = std::vector<std::string>;

namespace {

struct FakeClock {
    Clock::time_point now = Clock::time_point{} + 1h;
    std::function<Clock::time_point()> source() {
        return [this] { return now; };
    }
};

ControllerOptions options_for(VariantId variant, FakeClock& clock, bool leapfrog = false) {
    ControllerOptions options{};
    options.variant = variant;
    options.leapfrog = leapfrog;
    options.clock = DishClock::manual(clock.source());
    return options;
}

// Commands written since `from` (index into FakeTransport::commands()).
Commands since(const FakeTransport& wire, std::size_t from) {
    return Commands(wire.commands().begin() + static_cast<std::ptrdiff_t>(from), wire.commands().end());
}

// Pumps service() with the fake clock advancing `step` per call until idle (bounded).
int run_until_idle(Controller& controller, FakeClock& clock, std::chrono::milliseconds step = 100ms) {
    for (int calls = 1; calls <= 1000; ++calls) {
        clock.now += step;
        const Status status = controller.service();
        INFO(status.message);
        REQUIRE((status || status.code == Errc::timeout));
        if (controller.idle()) {
            return calls;
        }
    }
    FAIL("controller never became idle");
    return -1;
}

// initialize(), then service() until the dish is known at rest (readings that agree over 250 ms of
// dish time; legs wait until then): what a test that moves the dish starts from.
Status initialise_at_rest(Controller& controller, FakeClock& clock) {
    if (Status initialised = controller.initialize(); !initialised) {
        return initialised;
    }
    for (int calls = 0; calls < 4 || (calls < 100 && !controller.idle()); ++calls) {
        clock.now += 100ms;
        if (Status status = controller.service(); !status) {
            return status;
        }
    }
    return controller.idle() ? Status::ok() : Status{Errc::timeout, "the dish never came to rest"};
}

bool contains(const Commands& commands, const std::string& command) {
    return std::find(commands.begin(), commands.end(), command) != commands.end();
}

}  // namespace

// A fake G2 already wired to a controller on a fake clock: the set-up most G2 tests share.
struct G2Bench {
    FakeG2 dish;
    FakeTransport wire{[this](const std::string& c) { return dish.respond(c); }};
    FakeClock clock;
    Controller controller{wire, options_for(VariantId::carryout_g2, clock)};
};

TEST_CASE_METHOD(G2Bench, "controller G2: initialise a booted dish at TRK> without ever sending q at the root") {
    REQUIRE(controller.initialize());
    // Two bare line endings: the prompt counts only once two consecutive pokes end on it.
    CHECK(wire.commands() == Commands{"", "", "mot", "a"});
    CHECK(controller.initialised());
    REQUIRE(controller.last_position());
    CHECK(controller.last_position()->az == Approx(180));
    CHECK(controller.last_position()->el == Approx(45));
    CHECK_FALSE(dish.shell_killed);
    CHECK(controller.describe().find("Carryout G2") != std::string::npos);
}

TEST_CASE("controller G2: initialise from a submenu leaves it with q, then enters MOT>") {
    FakeG2 dish;
    dish.menu = "DVB";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    CHECK(wire.commands() == Commands{"", "", "q", "mot", "a"});
    CHECK_FALSE(dish.shell_killed);
}

TEST_CASE("controller G2: already in MOT> still passes through the root safely") {
    FakeG2 dish;
    dish.menu = "MOT";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    CHECK(wire.commands() == Commands{"", "", "q", "mot", "a"});
}

TEST_CASE("controller G2: waits for the boot to complete") {
    FakeG2 dish;
    bool booted = false;
    FakeTransport wire([&](const std::string& c) { return booted ? dish.respond(c) : Commands{}; });
    wire.push_delayed(
        "Bootloader v1.01\r\nMotor init: System=12Inch\r\nAntenna Facing Front\r\nBoot Complete\r\n"
        "Loc Startup: IDU NOT Present\r\nTRK>",
        4);
    FakeClock clock;
    auto options = options_for(VariantId::carryout_g2, clock);
    std::vector<std::string> log;
    options.log = [&](LogLevel, const std::string& m) {
        log.push_back(m);
        if (m.find("Boot Complete") != std::string::npos) {
            booted = true;
        }
    };
    Controller controller(wire, options);
    REQUIRE(controller.initialize());
    CHECK(wire.commands() == Commands{"", "", "", "mot", "a"});
    CHECK(std::any_of(log.begin(), log.end(),
                      [](const std::string& m) { return m.find("waiting for the dish") != std::string::npos; }));
}

TEST_CASE("controller: boot wait is bounded by boot_timeout") {
    FakeTransport wire;  // a dish that never says anything
    FakeClock clock;
    auto options = options_for(VariantId::carryout_g2, clock);
    options.boot_timeout = 90s;
    Controller controller(wire, options);
    const Status status = controller.initialize();
    CHECK(status.code == Errc::timeout);
    // The reason names what was seen and what was expected.
    CHECK(status.message.find("expected the console's prompt (TRK>") != std::string::npos);
    CHECK(status.message.find("stayed silent") != std::string::npos);
    CHECK_FALSE(controller.initialised());
}

TEST_CASE_METHOD(G2Bench, "controller G2: moves one axis at a time, alternating the first axis") {
    REQUIRE(initialise_at_rest(controller, clock));

    std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({190, 50}));
    CHECK(wire.commands().size() == mark);  // set_target does no I/O
    CHECK_FALSE(controller.idle());
    run_until_idle(controller, clock);
    // The first leg after initialisation arrives only on a second reading that agrees: a dish that
    // still runs a calibration may sweep the axis through the leg's end (docs/tracking.md).
    CHECK(since(wire, mark) == Commands{"a 0 190.00", "a", "a", "a 1 50.00", "a"});
    CHECK(controller.last_position()->az == Approx(190));

    mark = wire.commands().size();
    REQUIRE(controller.set_target({200, 55}));
    run_until_idle(controller, clock);
    CHECK(since(wire, mark) == Commands{"a 1 55.00", "a", "a 0 200.00", "a"});

    SECTION("a repeated identical target is a no-op") {
        mark = wire.commands().size();
        REQUIRE(controller.set_target({200, 55}));
        CHECK(controller.idle());
        controller.service();
        CHECK(since(wire, mark).empty());
    }
    SECTION("only the axis that changes is commanded") {
        mark = wire.commands().size();
        REQUIRE(controller.set_target({200, 60}));
        run_until_idle(controller, clock);
        CHECK(since(wire, mark) == Commands{"a 1 60.00", "a"});
    }
}

TEST_CASE("controller G2: leapfrog leads both axes against the last known position") {
    FakeG2 dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock, true));
    REQUIRE(initialise_at_rest(controller, clock));
    const std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({190, 46.5}));
    run_until_idle(controller, clock);
    CHECK(since(wire, mark) == Commands{"a 0 191.00", "a", "a", "a 1 47.00", "a"});  // first leg: two readings
    CHECK(controller.current_target()->az == Approx(190));                           // the target, not the led command
}

TEST_CASE_METHOD(G2Bench, "controller: target validation and clamping") {
    REQUIRE(controller.initialize());
    CHECK(controller.set_target({std::nan(""), 45}).code == Errc::invalid_argument);
    CHECK(controller.set_target({180, 1.0 / 0.0}).code == Errc::invalid_argument);
    REQUIRE(controller.set_target({370, 80}));
    CHECK(controller.current_target()->az == Approx(10));
    CHECK(controller.current_target()->el == Approx(65));
    REQUIRE(controller.set_target({-10, 5}));
    CHECK(controller.current_target()->az == Approx(350));
    CHECK(controller.current_target()->el == Approx(18));
}

TEST_CASE("controller: user elevation limits never exceed the variant's") {
    FakeTransport wire;
    FakeClock clock;
    auto options = options_for(VariantId::carryout_g2, clock);
    options.el_min = 20;
    options.el_max = 80;
    Controller narrowed(wire, options);
    CHECK(narrowed.el_min() == 20);
    CHECK(narrowed.el_max() == 65);
    options.el_min = 10;
    options.el_max = 30;
    Controller widened(wire, options);
    CHECK(widened.el_min() == 18);
    CHECK(widened.el_max() == 30);
}

TEST_CASE("controller G2: polls until the axis arrives") {
    FakeG2 dish;
    dish.step_per_query = 2.0;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(initialise_at_rest(controller, clock));
    const std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({190, 45}));
    run_until_idle(controller, clock);
    const Commands sent = since(wire, mark);
    CHECK(sent.front() == "a 0 190.00");
    CHECK(std::count(sent.begin(), sent.end(), "a") == 6);  // 182, 184, ..., 190, 190 (the first leg)
    CHECK(controller.last_position()->az == Approx(190));
}

TEST_CASE("controller G2: an axis that stops short is declared done after the still window") {
    FakeG2 dish;
    FakeTransport wire([&](const std::string& c) {
        auto out = dish.respond(c);
        if (c.rfind("a 0 ", 0) == 0) {
            dish.target_az -= 5;  // e.g. a mechanical stop
        }
        return out;
    });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    REQUIRE(controller.set_target({200, 45}));
    const int calls = run_until_idle(controller, clock);
    CHECK(calls >= 20);  // 2 s still window at 100 ms per call
    CHECK(controller.last_position()->az == Approx(195));
}

TEST_CASE("controller G2: a leg that keeps creeping is abandoned after 2 x estimate + margin") {
    FakeG2 dish;
    dish.step_per_query = 0.05;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    REQUIRE(controller.set_target({190, 45}));
    Status last;
    for (int i = 0; i < 200 && !controller.idle(); ++i) {
        clock.now += 100ms;
        const Status status = controller.service();
        if (!status) {
            last = status;
        }
    }
    CHECK(last.code == Errc::timeout);
    CHECK(controller.idle());
}

TEST_CASE_METHOD(G2Bench, "controller: cancel_pending drops legs not yet sent, the leg in flight finishes") {
    REQUIRE(initialise_at_rest(controller, clock));
    const std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({190, 50}));
    clock.now += 100ms;
    REQUIRE(controller.service());  // sends AZ
    controller.cancel_pending();
    CHECK_FALSE(controller.current_target());
    run_until_idle(controller, clock);
    CHECK_FALSE(contains(since(wire, mark), "a 1 50.00"));
    CHECK(contains(since(wire, mark), "a 0 190.00"));
}

TEST_CASE("controller G2: unhomed axes refuse moves and say so") {
    FakeG2 dish;
    dish.homed = false;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    CHECK(controller.query_position().status.code == Errc::not_homed);
    CHECK(controller.set_target({180, 45}).code == Errc::not_homed);
    CHECK(controller.describe().find("NOT homed") != std::string::npos);
    for (const auto& command : wire.commands()) {
        CHECK(command.rfind("a 0", 0) != 0);
    }
}

// Hamlib's netrotctl (rotctl -m 2) reads get_info into 64 bytes: a client of rotctld sees the first
// 63 characters of "Winegard " + describe(), so the identity and the state come first.
TEST_CASE_METHOD(G2Bench, "controller: describe() leads with the dish and its state, then the details") {
    REQUIRE(initialise_at_rest(controller, clock));
    CHECK(controller.describe().rfind("Carryout G2: idle; [g2, 115200 baud, prompt MOT>]", 0) == 0);
    REQUIRE(controller.set_target({200.0, 30.0}));
    REQUIRE(controller.service());
    CHECK(controller.describe().rfind("Carryout G2: moving; [g2, ", 0) == 0);

    FakeG2 unhomed_dish;
    unhomed_dish.homed = false;
    FakeTransport unhomed_wire([&](const std::string& c) { return unhomed_dish.respond(c); });
    Controller unhomed(unhomed_wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(unhomed.initialize());
    const std::string text = unhomed.describe();
    CHECK(text.rfind("Carryout G2: axes NOT homed, idle; [g2, ", 0) == 0);
    CHECK(text.find("reset (R 1) homes the axes") > text.find("[g2, "));
}

// On a pty no line speed applies: a G2 emulated at rotctld's default -s must not read "57600 baud".
TEST_CASE("controller: describe() names no line speed on a pty") {
    FakeG2 dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    ControllerOptions options = options_for(VariantId::carryout_g2, clock);
    options.line_baud = 57600;
    options.line_is_pty = true;
    Controller controller(wire, options);
    REQUIRE(controller.initialize());
    CHECK(controller.describe().rfind("Carryout G2: idle; [g2, pty, no line speed, prompt MOT>]", 0) == 0);
    CHECK(controller.describe().find("baud") == std::string::npos);
}

TEST_CASE("controller: every dish's identity and its longest leading state fit get_info's 63 characters") {
    // The longest words a state can start with: the controller's, and the backend's for a dish
    // that is not answering (src/hamlib/winegard_ops.cpp).
    const std::vector<std::string> leading = {"not initialised", "axes NOT homed", "TV search ON", "homing",
                                              "moving",          "idle",           "RECOVERING",   "NOT ANSWERING"};
    for (const FirmwareProfile& p : all_profiles()) {
        for (const bool detected : {false, true}) {
            for (const std::string& state : leading) {
                const std::string head = "Winegard " + dish_identity(p, detected) + ": " + state;
                INFO(head);
                CHECK(head.size() <= 63);
            }
        }
    }
}

TEST_CASE_METHOD(G2Bench, "controller G2: a reboot seen during operation requires re-initialisation") {
    REQUIRE(initialise_at_rest(controller, clock));
    REQUIRE(controller.set_target({190, 50}));
    clock.now += 100ms;
    REQUIRE(controller.service());
    wire.push_input("Bootloader v1.01\r\nBoot Complete\r\nTRK>");
    dish.menu = "TRK";
    Status status;
    for (int i = 0; i < 5 && status; ++i) {
        clock.now += 100ms;
        status = controller.service();
    }
    CHECK(status.code == Errc::not_initialised);
    CHECK(controller.idle());
    CHECK_FALSE(controller.initialised());
    const Status again = controller.initialize();
    INFO(again.message);
    REQUIRE(again);
    CHECK_FALSE(dish.shell_killed);
}

TEST_CASE("controller G2: skip_init trusts the user but still reads the prompt") {
    FakeG2 dish;
    dish.menu = "MOT";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    auto options = options_for(VariantId::carryout_g2, clock);
    options.skip_init = true;
    Controller controller(wire, options);
    REQUIRE(controller.initialize());
    CHECK(wire.commands() == Commands{"", "", "a"});
}

TEST_CASE("controller HAL 2.05: initialise stops the search the ngsearch way and enters motor") {
    FakeTravler dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::travler_hal205, clock));
    REQUIRE(controller.initialize());
    CHECK(wire.commands() == Commands{"", "?", "", "?", "q", "", "q", "", "ngsearch", "s", "q", "", "motor", "a"});
    CHECK(controller.last_position()->az == Approx(90));
    CHECK(controller.last_position()->el == Approx(30));
}

TEST_CASE("controller HAL 2.05: waits for NoGPS / No LNB Voltage when the console is silent") {
    FakeTravler dish;
    bool booted = false;  // a calibrating dish ignores its input
    FakeTransport wire([&](const std::string& c) { return booted ? dish.respond(c) : Commands{}; });
    const int arrives_after = GENERATE(1, 3, 6);
    wire.push_delayed("Calibrating...\r\nNo LNB Voltage\r\n", arrives_after);
    FakeClock clock;
    auto options = options_for(VariantId::travler_hal205, clock);
    options.log = [&](LogLevel, const std::string& m) {
        if (m.find("No LNB Voltage") != std::string::npos) {
            booted = true;
        }
    };
    Controller controller(wire, options);
    const Status status = controller.initialize();
    INFO(status.message);
    REQUIRE(status);
    CHECK(contains(wire.commands(), "ngsearch"));
    CHECK(controller.last_position());
}

TEST_CASE("controller HAL 0.0.00: os / kill Search, mot") {
    FakeTravler dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::travler_hal000, clock));
    REQUIRE(controller.initialize());
    CHECK(since(wire, 4) == Commands{"q", "", "q", "", "os", "kill Search", "q", "", "mot", "a"});
}

TEST_CASE("controller HAL 2.05: moves without a prompt, polling AZ/EL replies") {
    FakeTravler dish;
    dish.step_per_query = 3.0;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::travler_hal205, clock, true));
    REQUIRE(initialise_at_rest(controller, clock));
    const std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({100, 35}));
    run_until_idle(controller, clock);
    const Commands sent = since(wire, mark);
    CHECK(sent.front() == "a 0 101.00");  // led by 1 deg
    CHECK(contains(sent, "a 1 36.00"));
    CHECK(controller.last_position()->az == Approx(101));
    CHECK(controller.last_position()->el == Approx(36));
}

// Steering on a slow mount re-aims more often than a leg ends (near a culmination the azimuth runs
// at 2 deg/s on a Trav'ler that takes seconds per leg): whatever the count of re-aims, the axis not
// in flight moves next, or the azimuth's legs run back to back while the elevation waits.
TEST_CASE("controller HAL 2.05: re-aims during an azimuth leg send the elevation next") {
    FakeTravler dish;
    dish.step_per_query = 0.5;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::travler_hal205, clock));
    REQUIRE(initialise_at_rest(controller, clock));
    const int re_aims = GENERATE(1, 2, 3);
    const std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({100, 30}));  // azimuth only: 10 deg at 0.5 deg per poll
    clock.now += 100ms;
    REQUIRE(controller.service());
    REQUIRE(since(wire, mark).front() == "a 0 100.00");
    for (int k = 1; k <= re_aims; ++k) {
        clock.now += 100ms;
        REQUIRE(controller.set_target({100.0 + k, 30.0 + k}));
        REQUIRE(controller.service());
    }
    run_until_idle(controller, clock);
    Commands moves;
    for (const std::string& c : since(wire, mark)) {
        if (c.rfind("a ", 0) == 0) {
            moves.push_back(c);
        }
    }
    INFO(re_aims << " re-aims");
    REQUIRE(moves.size() >= 2);
    CHECK(moves[1].rfind("a 1 ", 0) == 0);
}

TEST_CASE("controller HAL 2.05: an axis that arrived within tolerance stays modelled until a reading shows it still") {
    FakeTravler dish;
    dish.step_per_query = 0.15;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::travler_hal205, clock));
    REQUIRE(controller.initialize());
    // A first leg of its own ends the watch for a calibration still running (its arrival wants two
    // agreeing readings); the legs below are a tracking client's.
    // Two azimuth legs, out and back, so that the azimuth goes first in the next move again.
    for (const double az : {89.85, 90.0}) {
        REQUIRE(controller.set_target({az, 30}));
        for (int calls = 0; calls < 100 && (!controller.idle() || controller.moving_axes().azimuth); ++calls) {
            clock.now += 100ms;
            REQUIRE(controller.service());
        }
        REQUIRE(controller.last_position()->az == Approx(az));
    }
    REQUIRE(controller.set_target({91, 30.5}));
    for (int calls = 0; calls < 100 && !controller.moving_axes().elevation; ++calls) {
        clock.now += 100ms;
        REQUIRE(controller.service());
    }
    // Azimuth arrived at 90.90 (within 0.2 of 91) and the elevation leg is in flight.
    const MovingAxes moving = controller.moving_axes();
    REQUIRE(moving.elevation);
    REQUIRE(moving.azimuth);
    CHECK(moving.azimuth->latest.value == Approx(90.9));
    CHECK(moving.azimuth->to == Approx(91.0));
    CHECK(modelled_position(controller.profile(), *controller.last_position(), moving, clock.now + 10s).az ==
          Approx(91.0));
    // The next readings: azimuth 91.00 (still moving), then 91.00 again (at rest): no longer modelled.
    for (int polls = 0; polls < 2; ++polls) {
        clock.now += 100ms;
        REQUIRE(controller.service());
    }
    CHECK_FALSE(controller.moving_axes().azimuth);
    CHECK(controller.last_position()->az == Approx(91.0));
}

TEST_CASE("controller HAL 2.05: a motor that starts seconds after each command is waited for, not re-sent") {
    // Each axis at rest stays put for 2.5 s of polls after its command, then runs 1 deg per poll.
    FakeTravler dish;
    dish.step_per_query = 1.0;
    dish.startup_queries = 25;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    auto options = options_for(VariantId::travler_hal205, clock);
    std::vector<std::string> warnings;
    options.log = [&](LogLevel level, const std::string& m) {
        if (level == LogLevel::warning) {
            warnings.push_back(m);
        }
    };
    Controller controller(wire, options);
    REQUIRE(controller.initialize());
    for (int step = 1; step <= 3; ++step) {
        const AzEl target{90.0 + 10.0 * step, 30.0 + 2.0 * step};
        const std::size_t mark = wire.commands().size();
        REQUIRE(controller.set_target(target));
        if (step > 1) {
            // The delay is learnt: 1.5 s after the first command `p` still has the axis at its start.
            for (int polls = 0; polls < 15; ++polls) {
                clock.now += 100ms;
                REQUIRE(controller.service());
            }
            const MovingAxes moving = controller.moving_axes();
            REQUIRE(!moving.empty());
            const AzEl modelled =
                modelled_position(controller.profile(), *controller.last_position(), moving, clock.now);
            CHECK(modelled.az == Approx(target.az - 10.0).margin(0.05));
            CHECK(modelled.el == Approx(target.el - 2.0).margin(0.05));
        }
        run_until_idle(controller, clock);
        const Commands sent = since(wire, mark);
        INFO("step " << step << ": " << Catch::Detail::stringify(sent));
        CHECK(std::count_if(sent.begin(), sent.end(), [](const std::string& c) { return c.rfind("a 0 ", 0) == 0; }) ==
              1);
        CHECK(std::count_if(sent.begin(), sent.end(), [](const std::string& c) { return c.rfind("a 1 ", 0) == 0; }) ==
              1);
        CHECK(controller.last_position()->az == Approx(target.az).margin(0.2));
        CHECK(controller.last_position()->el == Approx(target.el).margin(0.2));
    }
    INFO(Catch::Detail::stringify(warnings));
    CHECK(std::none_of(warnings.begin(), warnings.end(),
                       [](const std::string& m) { return m.find("stopped at") != std::string::npos; }));
}

TEST_CASE("controller Carryout 2003: target + g, listens during the move, reports honestly") {
    std::vector<std::string> moves;
    FakeTransport wire([&](const std::string& c) {
        if (c.rfind("g ", 0) == 0) {
            moves.push_back(c);
            return Commands{c + "\r\n", "az = 17000   el = 4000\r\n"};
        }
        if (c == "?") {
            return Commands{"?\r\ntarget - Send dish to AZ/EL\r\n"};
        }
        return Commands{};
    });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout2003, clock));
    REQUIRE(controller.initialize());
    // Prompt-less: `?` answered the same twice proves a live console.
    CHECK(wire.commands() == Commands{"", "?", "", "?", "q", "", "target"});
    CHECK(controller.query_position().status.code == Errc::unsupported);

    REQUIRE(controller.set_target({180, 45}));
    clock.now += 100ms;
    REQUIRE(controller.service());
    CHECK(moves == Commands{"g 180.00 45.00"});
    const std::size_t after_g = wire.commands().size();
    wire.push_input("az = 18000   el = 4500\r\n");
    run_until_idle(controller, clock);
    CHECK(wire.commands().size() == after_g);  // nothing sent while `g` runs
    const auto position = controller.query_position();
    REQUIRE(position);
    CHECK(position.value.az == Approx(180));
    CHECK(position.value.el == Approx(45));
}

TEST_CASE("controller Carryout 2003: without live output the commanded position is reported as such") {
    FakeTransport wire([](const std::string& c) { return c == "?" ? Commands{"target - Send dish\r\n"} : Commands{}; });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout2003, clock));
    REQUIRE(controller.initialize());
    REQUIRE(controller.set_target({100, 30}));
    run_until_idle(controller, clock, 1000ms);
    REQUIRE(controller.query_position());
    CHECK(controller.query_position().value.az == Approx(100));
    CHECK(controller.describe().find("last commanded") != std::string::npos);
}

// A terse 2003 Carryout (LF, no echo, a bare `> ` in every menu) that reboots silently: the only
// evidence is what its live output does (docs/firmware.md 8.1-8.4).
struct TerseCarryout {
    bool in_target = false;
    bool rebooted = false;  // at its root again; `g` is an unknown command, answered silently
    std::vector<std::string> moves;
    std::vector<std::string> respond(const std::string& c) {
        if (c == "target") {
            in_target = true;
        } else if (c == "q") {
            in_target = false;
        } else if (c.rfind("g ", 0) == 0) {
            moves.push_back(c);
            if (in_target && !rebooted) {
                return {"\n", "az = 17000   el = 4000\n"};  // the move runs; more lines follow
            }
        } else if (c == "?") {
            return {"\n", in_target ? "G\n" : "TARGET\n", "> "};
        }
        return {"\n", "> "};
    }
};

// That Carryout initialised, with `g 180.00 45.00` sent: where each of its reboot tests starts.
struct TerseCarryoutMoving {
    TerseCarryout dish;
    FakeTransport wire{[this](const std::string& c) { return dish.respond(c); }};
    FakeClock clock;
    Controller controller{wire, options_for(VariantId::carryout2003, clock)};
    TerseCarryoutMoving() {
        REQUIRE(controller.initialize());
        REQUIRE(controller.set_target({180, 45}));
        clock.now += 100ms;
        REQUIRE(controller.service());
    }
};

TEST_CASE("controller Carryout 2003: live output that stops short with no prompt means a silent reboot") {
    TerseCarryoutMoving rig;
    REQUIRE(rig.dish.moves == Commands{"g 180.00 45.00"});
    // The rig.dish loses power here: no more live lines, no prompt.
    Status status = Status::ok();
    for (int calls = 0; calls < 1000 && status && !rig.controller.idle(); ++calls) {
        rig.clock.now += 100ms;
        status = rig.controller.service();
    }
    CHECK(status.code == Errc::not_initialised);
    CHECK(rig.controller.needs_reinit());
    REQUIRE(rig.controller.last_position());
    CHECK(rig.controller.last_position()->az == Approx(170));  // the last live sample, not the target
    CHECK(rig.controller.describe().find("last commanded") == std::string::npos);

    REQUIRE(rig.controller.reinitialize(1000ms));
    CHECK_FALSE(rig.controller.needs_reinit());
}

TEST_CASE("controller Carryout 2003: a g answered by a bare prompt without live output was not run") {
    TerseCarryoutMoving rig;
    rig.wire.push_input("az = 18000   el = 4500\n> ");  // this console prints live positions during g
    run_until_idle(rig.controller, rig.clock);
    CHECK_FALSE(rig.controller.needs_reinit());

    rig.dish.rebooted = true;  // back at its root after a silent reboot: `g` is answered by `> ` alone
    REQUIRE(rig.controller.set_target({100, 30}));
    Status status = Status::ok();
    for (int calls = 0; calls < 100 && status && !rig.controller.idle(); ++calls) {
        rig.clock.now += 100ms;
        status = rig.controller.service();
    }
    CHECK(rig.dish.moves.back() == "g 100.00 30.00");
    CHECK(status.code == Errc::not_initialised);
    CHECK(rig.controller.needs_reinit());
    CHECK(rig.controller.last_position()->az == Approx(180));  // not the target it never went to
}

TEST_CASE("controller Carryout 2003: a g whose prompt comes before its live output is followed") {
    TerseCarryoutMoving rig;
    rig.wire.push_input("az = 18000   el = 4500\n> ");
    run_until_idle(rig.controller, rig.clock);

    // Firmware that runs `g` in the background: the prompt at once, the live lines after it.
    rig.dish.rebooted = true;
    REQUIRE(rig.controller.set_target({150, 40}));
    rig.clock.now += 100ms;
    REQUIRE(rig.controller.service());
    rig.wire.push_input("az = 16500   el = 4200\n");
    rig.clock.now += 100ms;
    REQUIRE(rig.controller.service());
    rig.wire.push_input("az = 15000   el = 4000\n");
    run_until_idle(rig.controller, rig.clock);
    CHECK_FALSE(rig.controller.needs_reinit());
    CHECK(rig.controller.last_position()->az == Approx(150));
}

TEST_CASE("controller: service before initialise with work queued reports not_initialised") {
    FakeTransport wire;
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    CHECK(controller.service());
    REQUIRE(controller.set_target({100, 30}));
    CHECK(controller.service().code == Errc::not_initialised);
    CHECK(wire.commands().empty());
}

TEST_CASE("controller G2: a stall reported during a leg abandons it with a protocol error") {
    FakeG2 dish;
    dish.step_per_query = 1.0;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(initialise_at_rest(controller, clock));
    REQUIRE(controller.set_target({190, 45}));
    clock.now += 100ms;
    REQUIRE(controller.service());  // sends AZ
    dish.extra_lines_after_query = {"AZ MOTOR STALLED"};
    clock.now += 100ms;
    const Status status = controller.service();
    CHECK(status.code == Errc::protocol);
    CHECK(status.message.find("AZ MOTOR STALLED") != std::string::npos);
    CHECK(controller.idle());
    CHECK(controller.last_position()->az == Approx(181));  // the position that came with it is kept
}

TEST_CASE("controller G2: a stall is kept for take_fault(), drops the other leg, and the same target retries") {
    FakeG2 dish;
    dish.step_per_query = 1.0;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(initialise_at_rest(controller, clock));
    REQUIRE(controller.set_target({190, 50}));  // AZ leg, then EL leg
    clock.now += 100ms;
    REQUIRE(controller.service());
    dish.extra_lines_after_query = {"AZ MOTOR STALLED"};
    clock.now += 100ms;
    CHECK(controller.service().code == Errc::protocol);
    CHECK(controller.take_fault().find("AZ MOTOR STALLED") != std::string::npos);
    CHECK(controller.take_fault().empty());  // once
    CHECK(controller.idle());                // the EL leg was dropped with the AZ one
    const std::size_t before = wire.commands().size();
    REQUIRE(controller.set_target({190, 50}));  // the same target again is a retry, not a no-op
    clock.now += 100ms;
    REQUIRE(controller.service());
    // Axes alternate which goes first: this second move starts with elevation.
    CHECK((contains(since(wire, before), "a 0 190.00") || contains(since(wire, before), "a 1 50.00")));
}

TEST_CASE("controller G2: after a reboot, reinitialize() forgets what was commanded") {
    FakeG2 dish;
    dish.step_per_query = 1.0;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    REQUIRE(controller.set_target({190, 50}));
    clock.now += 100ms;
    REQUIRE(controller.service());
    wire.push_input("Bootloader v1.01\r\nBoot Complete\r\nTRK>");
    dish.menu = "TRK";
    for (int i = 0; i < 5 && !controller.needs_reinit(); ++i) {
        clock.now += 100ms;
        (void)controller.service();
    }
    REQUIRE(controller.needs_reinit());
    REQUIRE(controller.reinitialize(1000ms));
    CHECK_FALSE(controller.needs_reinit());
    CHECK_FALSE(controller.current_target());
    const std::size_t before = wire.commands().size();
    REQUIRE(controller.set_target({190, 50}));
    clock.now += 100ms;
    REQUIRE(controller.service());
    CHECK(since(wire, before).size() == 1);  // the leg is sent again
}

// A boot that moves the dish (a Trav'ler's calibration, a G2 that homes) can leave it far off on one
// axis only; the first move after the recovery starts with that axis whatever the alternation's
// turn, so the pointing error falls soonest.
TEST_CASE("controller G2: after a recovery the axis farther off on the sky moves first") {
    FakeG2 dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(initialise_at_rest(controller, clock));
    REQUIRE(controller.set_target({190, 50}));
    run_until_idle(controller, clock);  // azimuth went first: elevation's turn next
    wire.push_input("Bootloader v1.01\r\nBoot Complete\r\nTRK>");
    dish.menu = "TRK";
    dish.az = dish.target_az = 0.0;  // where the boot left it
    dish.el = dish.target_el = 45.0;
    for (int i = 0; i < 5 && !controller.needs_reinit(); ++i) {
        clock.now += 100ms;
        (void)controller.query_position();  // an idle poll reads the boot output
    }
    REQUIRE(controller.needs_reinit());
    REQUIRE(controller.reinitialize(1000ms));
    for (int calls = 0; calls < 4; ++calls) {  // readings that agree over 250 ms: at rest where the boot left it
        clock.now += 100ms;
        REQUIRE(controller.service());
    }
    std::size_t mark = wire.commands().size();
    REQUIRE(controller.set_target({20, 43}));  // 14 deg off on the sky in azimuth, 2 in elevation
    run_until_idle(controller, clock);
    // The first leg after a re-initialisation arrives on a second agreeing reading, as after the first.
    CHECK(since(wire, mark) == Commands{"a 0 20.00", "a", "a", "a 1 43.00", "a"});
    // Alternation resumes from there.
    mark = wire.commands().size();
    REQUIRE(controller.set_target({15, 48}));  // inside the G2's travel, which ends at AZ 23.33
    run_until_idle(controller, clock);
    CHECK(since(wire, mark) == Commands{"a 1 48.00", "a", "a 0 15.00", "a"});
}

TEST_CASE("controller G2: a position that jumps at rest and does not repeat is refused (line noise)") {
    FakeG2 dish;
    dish.az = 123.45;
    dish.target_az = 123.45;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    FakeClock clock;
    Controller controller(wire, options_for(VariantId::carryout_g2, clock));
    REQUIRE(controller.initialize());
    REQUIRE(controller.last_position()->az == Approx(123.45));
    // One reply lost a byte: `123.45` arrived as `13.45`; the repeat query reads the truth.
    int queries = 0;
    wire.set_responder([&](const std::string& c) {
        auto out = dish.respond(c);
        if (c == "a" && queries++ == 0) {
            out.front() = "a\r\nAngle[0] = 13.45\r\nAngle[1] = 45.00\r\n";
        }
        return out;
    });
    const auto position = controller.query_position();
    CHECK(position.status.code == Errc::protocol);
    CHECK(controller.last_position()->az == Approx(123.45));
    // Noise bytes inside a reply are dropped by the framer and never parsed as a position.
    wire.set_responder([&](const std::string& c) {
        auto out = dish.respond(c);
        if (c == "a") {
            out.front() =
                "a\r\nAngle[0] = 1\x8f\xff"
                "23.45\r\nAngle[1] = 4\x01"
                "5.00\r\n";
        }
        return out;
    });
    const auto noisy = controller.query_position();
    CHECK(noisy.value.az == Approx(123.45));
    CHECK(controller.last_position()->az == Approx(123.45));
}

// A G2 whose `h <axis>` holds the shell until the test says the axis is homed (docs/firmware.md 6.4).
struct HomingG2 {
    FakeG2 dish;
    std::vector<std::string> homes;
    FakeTransport wire{[this](const std::string& c) {
        if (c.rfind("h ", 0) == 0) {
            homes.push_back(c);
            return Commands{c + "\r\n"};  // no prompt until the axis is homed
        }
        return dish.respond(c);
    }};
    FakeClock clock;
    Controller controller{wire, options_for(VariantId::carryout_g2, clock)};
};

TEST_CASE_METHOD(HomingG2, "controller G2: homing runs without blocking, one slice per service() call") {
    dish.homed = false;
    REQUIRE(controller.initialize());
    REQUIRE(controller.unhomed());
    REQUIRE(controller.start_home());
    CHECK(controller.homing());
    CHECK_FALSE(controller.idle());
    CHECK(controller.leg_in_flight());  // the shell is held: no submenu visits meanwhile

    clock.now += 100ms;
    REQUIRE(controller.service());
    CHECK(homes == Commands{"h 1"});
    const std::size_t after_h1 = wire.commands().size();
    for (int call = 0; call < 5; ++call) {  // the axis is still homing: nothing else is sent
        clock.now += 1s;
        REQUIRE(controller.service());
        CHECK(controller.homing());
    }
    CHECK(wire.commands().size() == after_h1);
    CHECK(controller.query_position().status.code == Errc::busy);
    CHECK(wire.commands().size() == after_h1);

    wire.push_input("MOT>");  // elevation homed
    REQUIRE(controller.service());
    CHECK(homes == Commands{"h 1", "h 0"});
    CHECK(controller.homing());

    dish.homed = true;
    dish.az = dish.target_az = 0.0;
    dish.el = dish.target_el = 65.0;
    wire.push_input("MOT>");  // azimuth homed
    REQUIRE(controller.service());
    CHECK_FALSE(controller.homing());
    CHECK(controller.idle());
    CHECK_FALSE(controller.unhomed());
    REQUIRE(controller.last_position());
    CHECK(controller.last_position()->az == Approx(0.0));
    CHECK(controller.last_position()->el == Approx(65.0));
}

TEST_CASE_METHOD(HomingG2, "controller G2: a home whose prompt never returns gives up after its bound") {
    REQUIRE(controller.initialize());
    REQUIRE(controller.start_home());
    Status status = Status::ok();
    int calls = 0;
    for (; calls < 1000 && status && controller.homing(); ++calls) {
        clock.now += 10s;
        status = controller.service();
    }
    CHECK(status.code == Errc::timeout);
    CHECK_FALSE(controller.homing());
    CHECK(calls > 10);  // 180 s of dish time, not the first silent slice
}

TEST_CASE_METHOD(G2Bench, "controller G2: home() is the blocking form, a variant without homing refuses") {
    REQUIRE(controller.initialize());
    REQUIRE(controller.home());
    CHECK(contains(wire.commands(), "h 1"));
    CHECK(contains(wire.commands(), "h 0"));
    CHECK_FALSE(controller.homing());

    FakeTravler travler;
    FakeTransport wire2([&](const std::string& c) { return travler.respond(c); });
    Controller hal205(wire2, options_for(VariantId::travler_hal205, clock));
    CHECK(hal205.start_home().code == Errc::unsupported);
}
