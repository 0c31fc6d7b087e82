// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "console/framer.hpp"

using namespace birdcage;
using Kind = FrameEvent::Kind;
using Events = std::vector<FrameEvent>;

namespace {

// Feeds the chunks in order and returns every event, as a test of one named byte sequence.
Events frame(const FirmwareProfile& variant, const std::vector<std::string>& chunks, std::string echo = {}) {
    ConsoleFramer framer(variant);
    framer.expect_echo(echo);
    Events all;
    for (const auto& chunk : chunks) {
        for (auto& event : framer.feed(chunk)) {
            all.push_back(std::move(event));
        }
    }
    return all;
}

const FirmwareProfile& g2() {
    return profile(VariantId::carryout_g2);
}
const FirmwareProfile& hal205() {
    return profile(VariantId::travler_hal205);
}

}  // namespace

TEST_CASE("framer: named byte sequences") {
    struct Case {
        const char* legend;
        const FirmwareProfile& variant;
        std::vector<std::string> chunks;
        std::string echo;
        Events expected;
    };
    const Case cases[] = {
        {"G2 position reply with echo and prompt",
         g2(),
         {"a\r\nAngle[0] = 180.00\r\nAngle[1] = 45.00\r\nMOT>"},
         "a",
         {{Kind::echo, "a"},
          {Kind::line, "Angle[0] = 180.00"},
          {Kind::line, "Angle[1] = 45.00"},
          {Kind::prompt, "MOT>"}}},
        {"LF-only line ends",
         g2(),
         {"a\nAngle = 1.00\nMOT>"},
         "a",
         {{Kind::echo, "a"}, {Kind::line, "Angle = 1.00"}, {Kind::prompt, "MOT>"}}},
        {"CR-only line ends",
         g2(),
         {"a\rAngle = 1.00\rMOT>"},
         "a",
         {{Kind::echo, "a"}, {Kind::line, "Angle = 1.00"}, {Kind::prompt, "MOT>"}}},
        {"LF CR and blank lines produce no empty lines",
         g2(),
         {"\n\r\n\rone\n\r\r\ntwo\r\n"},
         "",
         {{Kind::line, "one"}, {Kind::line, "two"}}},
        {"CR LF split across chunks", g2(), {"one\r", "\ntwo\r\n"}, "", {{Kind::line, "one"}, {Kind::line, "two"}}},
        {"prompt split across chunks",
         g2(),
         {"Angle = 1.00\r\nMO", "T>"},
         "",
         {{Kind::line, "Angle = 1.00"}, {Kind::prompt, "MOT>"}}},
        {"prompt with a trailing space", g2(), {"\r\nTRK> "}, "", {{Kind::prompt, "TRK>"}}},
        {"bare '>' prompt (Trav'ler, likely)", hal205(), {"\r\n>"}, "", {{Kind::prompt, ">"}}},
        {"echo after the prompt on the same line",
         g2(),
         {"TRK>nvs\r\nNVS>"},
         "nvs",
         {{Kind::echo, "TRK>nvs"}, {Kind::prompt, "NVS>"}}},
        {"prompt on a line of its own",
         g2(),
         {"    Saving ... \r\nNVS>\r\n"},
         "",
         {{Kind::line, "    Saving ... "}, {Kind::prompt, "NVS>"}}},
        {"help lines with <cmd> are not prompts",
         g2(),
         {"?\r\nEnter <a3981> - A3981 menu\r\nhelp [<command>]\r\nEnter <mot>", " - Motor menu\r\nTRK>"},
         "?",
         {{Kind::echo, "?"},
          {Kind::line, "Enter <a3981> - A3981 menu"},
          {Kind::line, "help [<command>]"},
          {Kind::line, "Enter <mot> - Motor menu"},
          {Kind::prompt, "TRK>"}}},
        {"a chunk ending right after a help-line '>' is not a prompt",
         g2(),
         {"Enter <a3981>", " - x\r\n"},
         "",
         {{Kind::line, "Enter <a3981> - x"}}},
        {"lowercase word before '>' is not a prompt", g2(), {"abc>"}, "", {}},
        // A product tag before the documented prompt, or marks after it: the menu is the same.
        {"tagged prompt (WG TRK>) is reported as its documented text",
         g2(),
         {"\r\nWG TRK>"},
         "",
         {{Kind::prompt, "TRK>"}}},
        {"bracket tag and echo after it",
         g2(),
         {"[G2]MOT>a\r\n    Angle[0] = 180.00\r\n[G2]MOT>"},
         "a",
         {{Kind::echo, "[G2]MOT>a"}, {Kind::line, "    Angle[0] = 180.00"}, {Kind::prompt, "MOT>"}}},
        {"marks after the '>' and a space", hal205(), {"\r\ndish:TRK>$ "}, "", {{Kind::prompt, "TRK>"}}},
        {"a tagged bare prompt", hal205(), {"\r\nant >"}, "", {{Kind::prompt, ">"}}},
        {"leading non-ASCII garbage is dropped and reported",
         g2(),
         {"\xff\xfe\x80"
          "Angle = 1.00\r\nMOT>"},
         "",
         {{Kind::line, "Angle = 1.00"}, {Kind::noise, "\xff\xfe\x80"}, {Kind::prompt, "MOT>"}}},
        {"NULs inside a line",
         g2(),
         {std::string("Ang\0le = 1.00\r\n", 15)},
         "",
         {{Kind::line, "Angle = 1.00"}, {Kind::noise, std::string(1, '\0')}}},
        {"unsolicited stall lines",
         g2(),
         {"AZ MOTOR STALLED\r\nEL MOTOR STALLED\r\nEL Motor Home Failure\r\n"},
         "",
         {{Kind::fault_line, "AZ MOTOR STALLED"},
          {Kind::fault_line, "EL MOTOR STALLED"},
          {Kind::fault_line, "EL Motor Home Failure"}}},
        {"G2 boot lines",
         g2(),
         {"Bootloader v1.01\r\nSPI1 init @ 4 MHz\r\nBoot Complete\r\nLoc Startup: IDU NOT Present\r\nTRK>"},
         "",
         {{Kind::boot_line, "Bootloader v1.01"},
          {Kind::line, "SPI1 init @ 4 MHz"},
          {Kind::boot_line, "Boot Complete"},
          {Kind::boot_line, "Loc Startup: IDU NOT Present"},
          {Kind::prompt, "TRK>"}}},
        {"Trav'ler boot-complete lines",
         hal205(),
         {"Homing done\r\nNoGPS\r\nNo LNB Voltage\n"},
         "",
         {{Kind::line, "Homing done"}, {Kind::boot_line, "NoGPS"}, {Kind::boot_line, "No LNB Voltage"}}},
        {"a prompt read together with line noise after it (idle RS-485 bus)",
         g2(),
         {"a 1 40.00\r\nAngle = 40.00\r\nMOT>I\"p\xC2\x1E}Z"},
         "a 1 40.00",
         {{Kind::echo, "a 1 40.00"},
          {Kind::line, "Angle = 40.00"},
          {Kind::prompt, "MOT>"},
          {Kind::noise, "I\"p\xC2\x1E"}}},
        {"our echo after a prompt is not cut at a noise byte",
         g2(),
         {"TRK>nv", std::string("\0s\r\nNVS>", 8)},
         "nvs",
         {{Kind::echo, "TRK>nvs"}, {Kind::noise, std::string(1, '\0')}, {Kind::prompt, "NVS>"}}},
        {"printable noise with a '>' is no prompt", g2(), {"\r\nxy>\x9c"}, "", {{Kind::noise, "\x9c"}}},
        {"echo only once",
         g2(),
         {"a\r\na\r\nMOT>"},
         "a",
         {{Kind::echo, "a"}, {Kind::line, "a"}, {Kind::prompt, "MOT>"}}},
        {"no echo from the console", hal205(), {"AZ = 1.00 EL = 2.00\r\n"}, "a", {{Kind::line, "AZ = 1.00 EL = 2.00"}}},
    };
    for (const auto& c : cases) {
        INFO(c.legend);
        const Events events = frame(c.variant, c.chunks, c.echo);
        // Noise events are reported once per chunk; compare kinds and texts in order.
        REQUIRE(events.size() == c.expected.size());
        for (std::size_t i = 0; i < events.size(); ++i) {
            INFO("event " << i);
            CHECK(events[i].kind == c.expected[i].kind);
            CHECK(events[i].text == c.expected[i].text);
        }
    }
}

TEST_CASE("framer: the garbage-prefixed prompt is still a prompt") {
    ConsoleFramer framer(profile(VariantId::carryout_g2));
    const Events events = framer.feed(std::string("\x00\x01MOT>", 6));
    REQUIRE(events.size() == 2);
    CHECK(events[0].kind == Kind::noise);
    CHECK(events[1] == FrameEvent{Kind::prompt, "MOT>"});
}

TEST_CASE("framer: partial lines are held until terminated") {
    ConsoleFramer framer(profile(VariantId::carryout_g2));
    CHECK(framer.feed("Angle[0] = 18").empty());
    CHECK(framer.partial_line() == "Angle[0] = 18");
    const Events events = framer.feed("0.00\r\n");
    REQUIRE(events.size() == 1);
    CHECK(events[0].text == "Angle[0] = 180.00");
    framer.feed("junk");
    framer.reset();
    CHECK(framer.partial_line().empty());
}

TEST_CASE("looks_like_prompt") {
    CHECK(looks_like_prompt("TRK>"));
    CHECK(looks_like_prompt("A3981>"));
    CHECK(looks_like_prompt(">"));
    CHECK(looks_like_prompt("MOT> "));
    CHECK_FALSE(looks_like_prompt("MOT>  "));
    CHECK_FALSE(looks_like_prompt("Enter <a3981>"));
    CHECK_FALSE(looks_like_prompt("TRK>nvs"));
    CHECK_FALSE(looks_like_prompt(""));
    CHECK_FALSE(looks_like_prompt("mot>"));
    // Known by shape: a short tag before, marks after; the documented text is what counts.
    CHECK(prompt_text("WG TRK>") == "TRK>");
    CHECK(prompt_text("[G2]MOT>") == "MOT>");
    CHECK(prompt_text("dish:TRK>$ ") == "TRK>");
    CHECK(prompt_text("#>") == ">");
    CHECK(prompt_text("TRK>>") == "TRK>");
    CHECK(prompt_text("Enter <a3981>").empty());
    CHECK(prompt_text("a very long banner TRK>").empty());  // more than a tag
    CHECK(prompt_text("Gmot>").empty());
}
