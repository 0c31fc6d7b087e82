// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "console/session.hpp"
#include "fake_transport.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;

namespace {

struct LogCapture {
    std::vector<std::pair<LogLevel, std::string>> entries;
    LogSink sink() {
        return [this](LogLevel level, const std::string& message) { entries.emplace_back(level, message); };
    }
    bool contains(const std::string& text) const {
        for (const auto& [level, message] : entries) {
            if (message.find(text) != std::string::npos) {
                return true;
            }
        }
        return false;
    }
};

}  // namespace

TEST_CASE("session: G2 transaction ends on the prompt and drops the echo") {
    FakeG2 dish;
    dish.menu = "MOT";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    LogCapture log;
    ConsoleSession session(wire, profile(VariantId::carryout_g2), log.sink());

    const auto reply = session.transact("a", 1000ms);
    REQUIRE(reply);
    CHECK(reply.value.lines == std::vector<std::string>{"Angle[0] = 180.00", "Angle[1] = 45.00"});
    CHECK(reply.value.prompt == "MOT>");
    CHECK(session.menu() == "mot");
    CHECK(wire.written() == "a\r");
    CHECK(log.contains("CMD a\\r"));
    CHECK(log.contains("RES a\\r\\nAngle[0] = 180.00"));
}

TEST_CASE("session: a missing prompt is a timeout on prompt-known firmware") {
    FakeTransport wire([](const std::string& c) { return std::vector<std::string>{c + "\r\nAngle = 1.00\r\n"}; });
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});
    session.set_requests(request_move);
    const auto reply = session.transact("a 0 1.00", 500ms);
    CHECK(reply.status.code == Errc::timeout);
    CHECK(reply.value.lines == std::vector<std::string>{"Angle = 1.00"});
}

TEST_CASE("session: without a known prompt the reply ends when complete and quiet") {
    FakeTravler dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(wire, profile(VariantId::travler_hal205), {});
    const auto reply = session.transact("a", 1000ms, [](Span<const std::string> lines) { return lines.size() >= 2; });
    REQUIRE(reply);
    CHECK(reply.value.lines.size() == 3);
    CHECK(reply.value.prompt.empty());

    SECTION("an incomplete reply times out") {
        const auto partial =
            session.transact("a", 300ms, [](Span<const std::string> lines) { return lines.size() >= 9; });
        CHECK(partial.status.code == Errc::timeout);
    }
}

TEST_CASE("session: a prompt split across reads is still found") {
    FakeTransport wire([](const std::string& c) {
        return std::vector<std::string>{c + "\r\n", "Angle[0] = 1.00\r\nAngle[1] = 2.00\r\nMO", "T>"};
    });
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});
    const auto reply = session.transact("a", 1000ms);
    REQUIRE(reply);
    CHECK(reply.value.prompt == "MOT>");
    CHECK(reply.value.lines.size() == 2);
}

TEST_CASE("session: hazard guard refuses before any byte is written") {
    FakeG2 dish;  // at TRK>
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});

    SECTION("q with the menu unknown") {
        CHECK(session.transact("q", 1000ms).status.code == Errc::hazard);
        CHECK(wire.written().empty());
    }
    SECTION("q at TRK> after a resync") {
        REQUIRE(session.resync(1000ms));
        CHECK(session.menu() == "root");
        const std::size_t before = wire.written().size();
        CHECK(session.transact("q", 1000ms).status.code == Errc::hazard);
        CHECK(wire.written().size() == before);
        CHECK_FALSE(dish.shell_killed);
    }
    SECTION("q from MOT> is allowed") {
        REQUIRE(session.resync(1000ms));
        REQUIRE(session.transact("mot", 1000ms));
        CHECK(session.menu() == "mot");
        REQUIRE(session.transact("q", 1000ms));
        CHECK(session.menu() == "root");
    }
    for (const char* command : {"scan", "e 20 1", "s", "stow", "reboot", "def", "inv 3", "ee 1 2"}) {
        DYNAMIC_SECTION("refuses " << command) {
            CHECK(session.transact(command, 1000ms).status.code == Errc::hazard);
            CHECK(wire.written().empty());
        }
    }
    SECTION("NVS writes pass when explicitly allowed, in NVS>") {
        session.set_allow_nvs_write(true);
        session.set_menu("nvs");
        CHECK(session.transact("e 20 1", 1000ms).status.code != Errc::hazard);
    }
    SECTION("an allowed NVS write is still refused where the menu is unknown (`e` engages in MOT>)") {
        session.set_allow_nvs_write(true);
        CHECK(session.transact("e 20 1", 1000ms).status.code == Errc::hazard);
        CHECK(wire.written().empty());
    }
    SECTION("a session that did not ask for motion sends no move") {
        CHECK(session.transact("a 0 180.00", 1000ms).status.code == Errc::hazard);
        CHECK(wire.written().empty());
    }
    SECTION("moves are refused once the axes are known to be unhomed") {
        session.set_requests(backend_requests);
        session.set_axes_unhomed(true);
        CHECK(session.transact("a 0 180.00", 1000ms).status.code == Errc::not_homed);
        CHECK(wire.written().empty());
    }
}

TEST_CASE("session: stale input is consumed first, boot lines set reboot_seen") {
    FakeG2 dish;
    dish.menu = "MOT";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    LogCapture log;
    ConsoleSession session(wire, profile(VariantId::carryout_g2), log.sink());
    wire.push_input("Angle[0] = 99.00\r\nAngle[1] = 99.00\r\n");  // a late reply to an earlier query
    const auto reply = session.transact("a", 1000ms);
    REQUIRE(reply);
    CHECK(reply.value.lines.front() == "Angle[0] = 180.00");
    CHECK(log.contains("stale output ignored: Angle[0] = 99.00"));
    CHECK_FALSE(session.reboot_seen());

    wire.push_input("Bootloader v1.01\r\nBoot Complete\r\nTRK>");
    dish.menu = "TRK";
    CHECK(session.resync(1000ms));
    CHECK(session.reboot_seen());
    CHECK(session.menu() == "root");
}

TEST_CASE("session: a stall line is surfaced as an error, with the reply kept") {
    FakeG2 dish;
    dish.menu = "MOT";
    dish.extra_lines_after_query = {"AZ MOTOR STALLED"};
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});
    const auto reply = session.transact("a", 1000ms);
    CHECK(reply.status.code == Errc::protocol);
    CHECK(reply.status.message.find("AZ MOTOR STALLED") != std::string::npos);
    CHECK(reply.value.lines.size() == 2);
}

TEST_CASE("session: hang-up is reported as disconnected") {
    FakeTransport wire;
    wire.hang_up();
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});
    CHECK(session.transact("", 1000ms).status.code == Errc::disconnected);
}

TEST_CASE("session: menu inference where prompts are unknown") {
    FakeTravler dish;
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(wire, profile(VariantId::travler_hal205), {});
    session.set_requests(backend_requests);
    CHECK(session.menu().empty());
    CHECK(session.transact("s", 500ms).status.code == Errc::hazard);  // could be NVS save
    REQUIRE(session.transact("q", 500ms));
    CHECK(session.menu() == "root");
    REQUIRE(session.transact("ngsearch", 500ms));
    CHECK(session.menu() == "ngsearch");
    CHECK(session.transact("s", 500ms));
}

TEST_CASE("session: listen stops on an awaited line") {
    FakeTransport wire;
    ConsoleSession session(wire, profile(VariantId::travler_hal000), {});
    wire.push_input("Calibrating\r\n");
    wire.push_input("NoGPS\r\n");
    const auto heard = session.listen(1000ms, [](const std::string& line) { return line == "NoGPS"; });
    REQUIRE(heard);
    CHECK(heard.value.lines == std::vector<std::string>{"Calibrating", "NoGPS"});
    CHECK(session.reboot_seen());
    CHECK(session.listen(10ms, [](const std::string&) { return true; }).status.code == Errc::timeout);
}

TEST_CASE("session: a stale prompt does not end the next reply early") {
    FakeG2 dish;
    dish.menu = "MOT";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(wire, profile(VariantId::carryout_g2), {});
    wire.push_input("\r\nMOT>");  // e.g. the late prompt of a command that timed out
    const auto first = session.transact("a", 1000ms);
    REQUIRE(first);
    CHECK(first.value.lines.size() == 2);
    const auto second = session.transact("a", 1000ms);
    REQUIRE(second);
    CHECK(second.value.lines.size() == 2);
}
