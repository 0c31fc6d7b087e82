// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The golden files pin what the core did, not how its messages are worded (docs/transcripts.md).
#include <catch2/catch.hpp>

#include <chrono>
#include <set>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "fake_transport.hpp"
#include "golden.hpp"

using namespace birdcage;

namespace {

constexpr Errc every_errc[] = {
    Errc::ok,     Errc::timeout,   Errc::protocol,        Errc::io,   Errc::invalid_argument, Errc::unsupported,
    Errc::hazard, Errc::not_homed, Errc::not_initialised, Errc::busy, Errc::disconnected};

// The `; `-separated phrases of describe(), e.g. "position az 180.00 el 45.00 (read back)".
std::vector<std::string> phrases_of(const std::string& description) {
    std::vector<std::string> phrases;
    std::size_t start = 0;
    while (start <= description.size()) {
        const std::size_t end = description.find("; ", start);
        phrases.push_back(description.substr(start, end == std::string::npos ? std::string::npos : end - start));
        if (end == std::string::npos)
            break;
        start = end + 2;
    }
    return phrases;
}

}  // namespace

TEST_CASE("golden: a status is its Errc name, rewording its message changes nothing") {
    const Status said_one_way{Errc::unsupported, "this dish cannot report its position at rest"};
    const Status said_another{Errc::unsupported, "position unavailable while the dish is idle"};
    CHECK(golden::status_field(said_one_way) == "error=unsupported");
    CHECK(golden::status_field(said_another) == golden::status_field(said_one_way));
    CHECK(golden::status_field(Status::ok()) == "ok");
}

TEST_CASE("golden: every Errc has its own identifier-like name, unlike to_string()'s words") {
    std::set<std::string> names;
    for (const Errc code : every_errc) {
        const std::string name = errc_name(code);
        INFO(name);
        CHECK(name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos);
        CHECK(names.insert(name).second);
    }
    CHECK(std::string(errc_name(Errc::protocol)) != to_string(Errc::protocol));
}

TEST_CASE("golden: the state lines come from the controller's values, none from describe()'s words") {
    test::FakeG2 dish;
    test::FakeTransport wire{[&dish](const std::string& command) { return dish.respond(command); }};
    ControllerOptions options;
    options.variant = VariantId::carryout_g2;
    Controller controller(wire, options);
    REQUIRE(controller.initialize());
    REQUIRE(controller.set_target({200.0, 30.0}));

    const auto lines = golden::state_lines(controller);
    CHECK(lines ==
          std::vector<std::string>{
              "state: variant=g2 detected=no baud=115200 menu=\"mot\" prompt=\"MOT>\" initialised=yes homed=yes "
              "tracker_enabled=no",
              "  position: az=180.00 el=45.00 source=readback",
              "  target: az=200.00 el=30.00",
              "  el_limits: min=18.00 max=65.00",
              "  pointing: leapfrog=on",
              "  wrap: travel=-423.33..23.33 mechanical_az=-180.00 az_reported=display target_mechanical_az=-160.00 "
              "az_mapping=auto possible=nearest,literal,wrap_manager planning=nearest wrap_point=unknown",
          });
    // Were describe() (or a piece of it) copied into the golden file, rewording it would break
    // every transcript test.
    // (One-word phrases such as "initialised" are also key names; every other phrase has a space.)
    const auto phrases = phrases_of(controller.describe());
    REQUIRE(phrases.size() >= 5);
    for (const auto& phrase : phrases) {
        if (phrase.find(' ') == std::string::npos)
            continue;
        for (const auto& line : lines) {
            INFO("describe() phrase \"" << phrase << "\" in \"" << line << "\"");
            CHECK(line.find(phrase) == std::string::npos);
        }
    }
}

TEST_CASE("golden: notes (# lines) are not compared and survive a rewrite before the event they annotate") {
    const std::string generated_header = "# birdcage-regress events for x.log\n";
    const std::string previous = generated_header +
                                 "op init: ok\n"
                                 "# the dish answers the second poke only\n"
                                 "  sent: a\\r\n"
                                 "\n"
                                 "# about an event that is gone\n"
                                 "  sent: gone\\r\n"
                                 "replay: complete\n"
                                 "# trailing note\n";
    const std::string fresh = generated_header + "op init: ok\n  sent: a\\r\nreplay: complete\n";

    CHECK(golden::content_lines(previous) ==
          std::vector<std::string>{"op init: ok", "  sent: a\\r", "  sent: gone\\r", "replay: complete"});
    std::vector<std::string> dropped;
    CHECK(golden::keep_annotations(previous, fresh, dropped) == generated_header +
                                                                    "op init: ok\n"
                                                                    "# the dish answers the second poke only\n"
                                                                    "  sent: a\\r\n"
                                                                    "replay: complete\n"
                                                                    "# trailing note\n");
    CHECK(dropped == std::vector<std::string>{"", "# about an event that is gone"});
}

TEST_CASE("golden: what the core parsed is one line of key=value fields per event, the dish's text quoted") {
    CHECK(golden::event_line(ConsoleEvent::read_position(ConsoleEvent::Kind::position, {180.0, 45.0})) ==
          "parsed: position az=180.00 el=45.00");
    CHECK(golden::event_line(ConsoleEvent::read_position(ConsoleEvent::Kind::live_position, {190.0, 40.62})) ==
          "parsed: live_position az=190.00 el=40.62");
    CHECK(golden::event_line(ConsoleEvent::move_acknowledged("a 0 89.00", 89.0)) ==
          "parsed: move_ack command=\"a 0 89.00\" angle=89.00");
    CHECK(golden::event_line(ConsoleEvent::fault_line("AZ MOTOR STALLED")) ==
          "parsed: fault line=\"AZ MOTOR STALLED\"");
    CHECK(golden::event_line(ConsoleEvent::reply_to(ConsoleEvent::Kind::unhomed, "a")) ==
          "parsed: unhomed command=\"a\"");
    CHECK(golden::event_line(ConsoleEvent::reply_to(ConsoleEvent::Kind::unrecognised, "a", " What?")) ==
          "parsed: unrecognised command=\"a\" line=\"\\x20What?\"");
    CHECK(golden::event_line(ConsoleEvent::reply_to(ConsoleEvent::Kind::unrecognised, "a")) ==
          "parsed: unrecognised command=\"a\" line=none");
    CHECK(golden::event_line(ConsoleEvent::menu_reached("mot", "MOT>")) == "reached: menu=\"mot\" prompt=\"MOT>\"");
    CHECK(golden::event_line(ConsoleEvent::menu_reached("", "")) == "reached: menu=unknown prompt=none");
}
