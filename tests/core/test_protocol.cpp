// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "firmware/protocol.hpp"

using namespace birdcage;
using Lines = std::vector<std::string>;

TEST_CASE("format_degrees: fixed two decimals, no exponent, no negative zero") {
    CHECK(format_degrees(180.0) == "180.00");
    CHECK(format_degrees(45.25) == "45.25");
    CHECK(format_degrees(1e-05) == "0.00");
    CHECK(format_degrees(-0.0) == "0.00");
    CHECK(format_degrees(-0.004) == "0.00");
    CHECK(format_degrees(-0.005) == "-0.01");
    CHECK(format_degrees(359.999) == "360.00");
    CHECK(format_degrees(123456789.0) == "123456789.00");
    CHECK(format_degrees(0.125) == "0.13");
}

TEST_CASE("command builders") {
    CHECK(build_axis_move(Axis::azimuth, 180) == "a 0 180.00");
    CHECK(build_axis_move(Axis::elevation, 45.5) == "a 1 45.50");
    CHECK(build_combined_move({180, 45}) == "g 180.00 45.00");
    CHECK(build_nvs_dump(20) == "d 20");
    CHECK(build_rssi(10) == "rssi 10");
}

TEST_CASE("parse_travler_position: layouts and signs") {
    struct Case {
        const char* legend;
        Lines lines;
        double az, el;
    };
    const Case cases[] = {
        {"one line", {"AZ = 180.00 EL = 45.00 SK = 0.00"}, 180, 45},
        {"three lines", {"AZ = 12.5", "EL = 30.25", "SK = 1.00"}, 12.5, 30.25},
        {"wide spacing, no SK", {"AZ =    7.00     EL =\t8.00"}, 7, 8},
        {"no space before =", {"AZ= 7.00 EL= 8.00"}, 7, 8},
        {"negative values", {"AZ = -3.50 EL = -1.25 SK = 0.00"}, -3.5, -1.25},
        {"explicit plus", {"AZ = +3.50 EL = +1.25"}, 3.5, 1.25},
        {"integers", {"AZ = 180 EL = 45"}, 180, 45},
        {"surrounded by chatter", {"motor pos:", "AZ = 1.00 EL = 2.00 SK = 3.00", "done"}, 1, 2},
    };
    for (const auto& c : cases) {
        INFO(c.legend);
        const auto parsed = parse_travler_position(c.lines);
        REQUIRE(parsed);
        CHECK(parsed.value.az == Approx(c.az));
        CHECK(parsed.value.el == Approx(c.el));
    }
}

TEST_CASE("parse_travler_position: garbage never yields a position") {
    const Lines garbage[] = {
        {},
        {"AZ = 180.00"},
        {"EL = 45.00"},
        {"AZ = nan EL = 45.00"},
        {"AZ = inf EL = 45.00"},
        {"AZ = EL = 45"},
        {"AZ = 1e5 EL = 2"},
        {"XAZ = 1.00 XEL = 2.00"},
    };
    for (std::size_t i = 0; i < std::size(garbage); ++i) {
        INFO("case " << i);
        const auto parsed = parse_travler_position(garbage[i]);
        CHECK_FALSE(parsed);
        CHECK(parsed.status.code == Errc::protocol);
    }
}

TEST_CASE("parse_g2_position") {
    SECTION("normal reply") {
        const auto parsed = parse_g2_position(Lines{"Angle[0] = 180.00", "Angle[1] = 45.00"});
        REQUIRE(parsed);
        CHECK(parsed.value.az == Approx(180));
        CHECK(parsed.value.el == Approx(45));
    }
    SECTION("indented and signed (wrap window -423.33..+23.33)") {
        const auto parsed = parse_g2_position(Lines{"    Angle[0] = -180.50", "    Angle[1] = 18.00"});
        REQUIRE(parsed);
        CHECK(parsed.value.az == Approx(-180.5));
    }
    SECTION("INT_MAX sentinel means not homed") {
        CHECK(parse_g2_position(Lines{"Angle[0] = 2147483647.00", "Angle[1] = 65.00"}).status.code == Errc::not_homed);
        CHECK(parse_g2_position(Lines{"Angle[0] = 21474836.47", "Angle[1] = 65.00"}).status.code == Errc::not_homed);
        CHECK(parse_g2_position(Lines{"Step to Position EL angle error: 2147483647"}).status.code == Errc::not_homed);
    }
    SECTION("missing axis") {
        CHECK(parse_g2_position(Lines{"Angle[0] = 180.00"}).status.code == Errc::protocol);
    }
}

TEST_CASE("parse_g2_move_ack") {
    const auto ack = parse_g2_move_ack(Lines{"Angle = 46.00"});
    REQUIRE(ack);
    CHECK(ack.value == Approx(46));
    CHECK(parse_g2_move_ack(Lines{"Angle = -12.50"}).value == Approx(-12.5));
    CHECK_FALSE(parse_g2_move_ack(Lines{"Angle[0] = 46.00"}));
    CHECK_FALSE(parse_g2_move_ack(Lines{}));
}

TEST_CASE("parse_carryout_live: the 8.4 line shape") {
    const auto parsed = parse_carryout_live(Lines{"az = 18000   el = 4500"});
    REQUIRE(parsed);
    CHECK(parsed.value.az == Approx(180));
    CHECK(parsed.value.el == Approx(45));
    SECTION("the last sample wins") {
        const auto last = parse_carryout_live(Lines{"az = 100   el = 2200", "az = 200   el = 2300"});
        REQUIRE(last);
        CHECK(last.value.az == Approx(2));
        CHECK(last.value.el == Approx(23));
    }
    CHECK_FALSE(parse_carryout_live(Lines{"el = 4500"}));
    CHECK_FALSE(parse_carryout_live(Lines{"az = x   el = 4500"}));
    CHECK_FALSE(parse_carryout_live(Lines{"g 180.0 45.0"}));
}

TEST_CASE("parse_g2_nvs_line") {
    const auto entry = parse_g2_nvs_line(" 20) Disable Tracker Proc?            FALSE       FALSE       FALSE");
    REQUIRE(entry);
    CHECK(entry->index == 20);
    CHECK(entry->name == "Disable Tracker Proc?");
    CHECK(entry->current == "FALSE");
    CHECK(entry->default_value == "FALSE");
    const auto limit = parse_g2_nvs_line("101) Minimum Elevation Angle           18.00       18.00       18.00");
    REQUIRE(limit);
    CHECK(limit->index == 101);
    CHECK(limit->saved == "18.00");
    CHECK_FALSE(parse_g2_nvs_line("Num  Name                         Current      Saved      Default"));
    CHECK_FALSE(parse_g2_nvs_line("---- --------------------------  ----------  ----------  ----------"));
}

TEST_CASE("parse_g2_rssi") {
    const auto reading =
        parse_g2_rssi(Lines{"iterations:10  interval(msec):20", " Reads:10  RSSI[avg: 412  cur: 409]"});
    REQUIRE(reading);
    CHECK(reading.value.reads == 10);
    CHECK(reading.value.average == 412);
    CHECK(reading.value.current == 409);
    CHECK_FALSE(parse_g2_rssi(Lines{"iterations:10  interval(msec):20"}));
}

TEST_CASE("parse_position dispatches on the profile") {
    CHECK(parse_position(profile(VariantId::travler_hal205), Lines{"AZ = 1.00 EL = 2.00"}));
    CHECK_FALSE(parse_position(profile(VariantId::carryout_g2), Lines{"AZ = 1.00 EL = 2.00"}));
    CHECK(parse_position(profile(VariantId::carryout_g2), Lines{"Angle[0] = 1.00", "Angle[1] = 2.00"}));
}

TEST_CASE("hazard_check: every documented hazard is refused") {
    const auto& g2 = profile(VariantId::carryout_g2);
    const auto& hal205 = profile(VariantId::travler_hal205);
    struct Case {
        const char* legend;
        const FirmwareProfile& variant;
        std::string command;
        HazardContext context;
        Errc expected;
    };
    const HazardRequests backend = backend_requests;
    const Case cases[] = {
        {"G2 q at root kills the shell", g2, "q", {"root"}, Errc::hazard},
        {"G2 q in an unknown menu", g2, "q", {""}, Errc::hazard},
        {"G2 q in a submenu is fine", g2, "q", {"mot"}, Errc::ok},
        {"Trav'ler q anywhere is the clients' idiom", hal205, "q", {""}, Errc::ok},
        {"argument-less scan", g2, "scan", {"adc"}, Errc::hazard},
        // The real ADC listing calls `scan` a streaming sweep (§15): no caller asks for one.
        {"scan with arguments streams", g2, "scan 0 10", {"adc"}, Errc::hazard},
        {"NVS write", g2, "e 20 1", {"nvs"}, Errc::hazard},
        {"NVS write allowed", g2, "e 20 1", {"nvs", true}, Errc::ok},
        {"NVS read", g2, "e 20", {"nvs"}, Errc::ok},
        {"EEPROM write", g2, "ee 3 1", {"eeprom"}, Errc::hazard},
        {"NVS save", g2, "s", {"nvs"}, Errc::hazard},
        {"save in an unknown menu", hal205, "s", {"", false, false, backend}, Errc::hazard},
        {"ngsearch stop is not a save", hal205, "s", {"ngsearch", false, false, backend}, Errc::ok},
        {"ngsearch stop needs the search-stop request", hal205, "s", {"ngsearch"}, Errc::hazard},
        {"stow", g2, "stow", {"root", false, false, backend}, Errc::hazard},
        {"reboot", g2, "reboot", {"os", false, false, backend}, Errc::hazard},
        {"def", g2, "def", {"dvb", true, false, backend}, Errc::hazard},
        {"EEPROM invalidate", g2, "inv 3", {"eeprom", true, false, backend}, Errc::hazard},
        {"move on unhomed axes", g2, "a 0 180.00", {"mot", false, true, backend}, Errc::not_homed},
        {"query on unhomed axes", g2, "a", {"mot", false, true}, Errc::ok},
        {"move on homed axes", g2, "a 0 180.00", {"mot", false, false, backend}, Errc::ok},
        {"a move nobody asked for", g2, "a 0 180.00", {"mot"}, Errc::hazard},
        {"bare line", g2, "", {""}, Errc::ok},
    };
    for (const auto& c : cases) {
        INFO(c.legend);
        CHECK(hazard_check(c.variant, c.command, c.context).code == c.expected);
    }
}

TEST_CASE("menu_for_prompt") {
    const auto& g2 = profile(VariantId::carryout_g2);
    CHECK(menu_for_prompt(g2, "TRK>") == "root");
    CHECK(menu_for_prompt(g2, "MOT>") == "mot");
    CHECK(menu_for_prompt(g2, "EE>") == "eeprom");
    CHECK(menu_for_prompt(g2, "A3981> ") == "a3981");
    CHECK(menu_for_prompt(g2, "") == "");
    CHECK(menu_for_prompt(profile(VariantId::travler_hal000), ">") == "root");
}
