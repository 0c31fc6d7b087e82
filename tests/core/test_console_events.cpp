// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// ControllerOptions::console_events: what the controller learns from each reply is reported as a
// value, in the order the console's output was read (console_events.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "fake_transport.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;
using Kind = ConsoleEvent::Kind;

namespace {

struct EventBench {
    Clock::time_point now = Clock::time_point{} + 1h;
    std::vector<ConsoleEvent> events;

    ControllerOptions options(VariantId variant) {
        ControllerOptions options{};
        options.variant = variant;
        options.leapfrog = false;
        options.clock = DishClock::manual([this] { return now; });
        options.console_events = [this](const ConsoleEvent& event) { events.push_back(event); };
        return options;
    }
    std::vector<ConsoleEvent> of_kind(Kind kind) const {
        std::vector<ConsoleEvent> found;
        std::copy_if(events.begin(), events.end(), std::back_inserter(found),
                     [kind](const ConsoleEvent& event) { return event.kind == kind; });
        return found;
    }
    void run_until_idle(Controller& controller) {
        for (int calls = 0; calls < 1000 && !controller.idle(); ++calls) {
            now += 100ms;
            const Status status = controller.service();
            INFO(status.message);
            REQUIRE((status || status.code == Errc::timeout));
        }
        REQUIRE(controller.idle());
    }
};

}  // namespace

TEST_CASE("console events: a G2 reports the menus it reached, each position reply and each move acknowledgement") {
    FakeG2 dish;
    FakeTransport wire([&dish](const std::string& command) { return dish.respond(command); });
    EventBench bench;
    Controller controller(wire, bench.options(VariantId::carryout_g2));
    REQUIRE(controller.initialize());

    const auto reached = bench.of_kind(Kind::reached);
    REQUIRE(reached.size() == 2);
    CHECK(reached[0].menu == "root");
    CHECK(reached[0].text == "TRK>");
    CHECK(reached[1].menu == "mot");
    CHECK(reached[1].text == "MOT>");
    REQUIRE(bench.events.back().kind == Kind::position);
    CHECK(bench.events.back().position->az == Approx(180.0));
    CHECK(bench.events.back().position->el == Approx(45.0));

    // The motor menu's prompt after every `a` is no news: no further `reached`. (A small change:
    // the controller asks again after a large one at rest, Controller::query_position().)
    bench.events.clear();
    dish.az = dish.target_az = 180.25;
    REQUIRE(controller.query_position());
    REQUIRE(bench.events.size() == 1);
    CHECK(bench.events[0].kind == Kind::position);
    CHECK(bench.events[0].position->az == Approx(180.25));

    bench.events.clear();
    REQUIRE(controller.set_target({200.0, 30.0}));
    bench.run_until_idle(controller);
    const auto acks = bench.of_kind(Kind::move_ack);
    REQUIRE(acks.size() == 2);
    CHECK(acks[0].command == "a 0 200.00");
    CHECK(*acks[0].angle == Approx(200.0));
    CHECK(acks[1].command == "a 1 30.00");
    CHECK(*acks[1].angle == Approx(30.0));
    CHECK(bench.of_kind(Kind::reached).empty());
    CHECK_FALSE(bench.of_kind(Kind::position).empty());
}

TEST_CASE("console events: a stall line in a position reply is a fault event beside the position") {
    FakeG2 dish;
    FakeTransport wire([&dish](const std::string& command) { return dish.respond(command); });
    EventBench bench;
    Controller controller(wire, bench.options(VariantId::carryout_g2));
    REQUIRE(controller.initialize());
    bench.events.clear();

    dish.extra_lines_after_query = {"AZ MOTOR STALLED"};
    CHECK(controller.query_position().status.code == Errc::protocol);
    const auto faults = bench.of_kind(Kind::fault);
    REQUIRE(faults.size() == 1);
    CHECK(faults[0].text == "AZ MOTOR STALLED");
    CHECK(bench.of_kind(Kind::position).size() == 1);
    CHECK(bench.of_kind(Kind::unrecognised).empty());
}

TEST_CASE("console events: the INT_MAX sentinel is an unhomed event, never a position") {
    FakeG2 dish;
    dish.homed = false;
    FakeTransport wire([&dish](const std::string& command) { return dish.respond(command); });
    EventBench bench;
    Controller controller(wire, bench.options(VariantId::carryout_g2));
    controller.initialize();
    bench.events.clear();

    CHECK(controller.query_position().status.code == Errc::not_homed);
    REQUIRE(bench.events.size() == 1);
    CHECK(bench.events[0].kind == Kind::unhomed);
    CHECK(bench.events[0].command == "a");
}

TEST_CASE("console events: a reply its parser cannot use is unrecognised, with the command and its first line") {
    FakeG2 dish;
    bool garbled = false;
    FakeTransport wire([&](const std::string& command) {
        if (garbled && command == "a") {
            return std::vector<std::string>{"a\r\nWhat?\r\n", "MOT>"};
        }
        return dish.respond(command);
    });
    EventBench bench;
    Controller controller(wire, bench.options(VariantId::carryout_g2));
    REQUIRE(controller.initialize());
    bench.events.clear();

    garbled = true;
    CHECK_FALSE(controller.query_position());
    REQUIRE(bench.events.size() == 1);
    CHECK(bench.events[0].kind == Kind::unrecognised);
    CHECK(bench.events[0].command == "a");
    CHECK(bench.events[0].text == "What?");
}

TEST_CASE("console events: every live line of a 2003 Carryout `g` is a live position, however the reads split them") {
    FakeTransport wire([](const std::string& command) {
        if (command.rfind("g ", 0) == 0) {
            return std::vector<std::string>{command + "\r\n", "az = 17000   el = 4000\r\n"};
        }
        if (command == "?") {
            return std::vector<std::string>{"?\r\ntarget - Send dish to AZ/EL\r\n"};
        }
        return std::vector<std::string>{};
    });
    EventBench bench;
    Controller controller(wire, bench.options(VariantId::carryout2003));
    REQUIRE(controller.initialize());
    bench.events.clear();

    REQUIRE(controller.set_target({180, 45}));
    bench.now += 100ms;
    REQUIRE(controller.service());
    // Two samples in one read: both are reported, not only the newest the controller keeps.
    wire.push_input("az = 17500   el = 4250\r\naz = 18000   el = 4500\r\n");
    bench.run_until_idle(controller);

    const auto live = bench.of_kind(Kind::live_position);
    REQUIRE(live.size() == 3);
    CHECK(live[0].position->az == Approx(170.0));
    CHECK(live[1].position->az == Approx(175.0));
    CHECK(live[1].position->el == Approx(42.5));
    CHECK(live[2].position->az == Approx(180.0));
    CHECK(live[2].position->el == Approx(45.0));
    CHECK(bench.of_kind(Kind::position).empty());
}

TEST_CASE("console events: every kind has its own stable name") {
    const Kind kinds[] = {Kind::position, Kind::live_position, Kind::move_ack, Kind::fault,
                          Kind::unhomed,  Kind::unrecognised,  Kind::reached};
    std::vector<std::string_view> names;
    for (const Kind kind : kinds) {
        const auto name = console_event_name(kind);
        INFO(name);
        CHECK(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string_view::npos);
        CHECK(std::find(names.begin(), names.end(), name) == names.end());
        names.push_back(name);
    }
    CHECK(console_event_name(Kind::live_position) == "live_position");
}
