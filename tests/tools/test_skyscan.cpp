// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-skyscan's grid, serpentine order and resume logic.
#include "skyscan.hpp"

#include <catch2/catch.hpp>

using namespace birdcage::skyscan;

TEST_CASE("ranges: from:to:step, inclusive, malformed ones refused") {
    const auto r = parse_range("110:114:2");
    REQUIRE(r);
    CHECK(values(*r) == std::vector<double>{110, 112, 114});
    CHECK(values(*parse_range("0:1:0.4")) == std::vector<double>{0, 0.4, 0.8});
    CHECK_FALSE(parse_range("10:5:1"));
    CHECK_FALSE(parse_range("1:5:0"));
    CHECK_FALSE(parse_range("1:5"));
    CHECK_FALSE(parse_range("a:5:1"));
}

TEST_CASE("serpentine: elevation up in even columns, down in odd ones, every point once") {
    const auto plan = serpentine(*parse_range("10:12:1"), *parse_range("20:22:1"));
    REQUIRE(plan.size() == 9);
    const double expected[9][2] = {{10, 20}, {10, 21}, {10, 22}, {11, 22}, {11, 21},
                                   {11, 20}, {12, 20}, {12, 21}, {12, 22}};
    for (std::size_t i = 0; i < plan.size(); ++i) {
        CHECK(plan[i].az == expected[i][0]);
        CHECK(plan[i].el == expected[i][1]);
    }
    // Consecutive points are one step apart: no sweep back to the bottom of the next column.
    for (std::size_t i = 1; i < plan.size(); ++i) {
        CHECK(std::abs(plan[i].az - plan[i - 1].az) + std::abs(plan[i].el - plan[i - 1].el) == 1.0);
    }
}

TEST_CASE("rows: our CSV and the upstream `az el rssi` format, headers and garbage skipped") {
    const auto ours = parse_row("174.00,43.00,562,2026-11-23T21:00:00Z");
    REQUIRE(ours);
    CHECK(ours->az == 174.0);
    CHECK(ours->value == 562.0);
    CHECK(ours->time == "2026-11-23T21:00:00Z");
    const auto upstream = parse_row("110.0 18.0 409\r");
    REQUIRE(upstream);
    CHECK(upstream->el == 18.0);
    CHECK(upstream->value == 409.0);
    CHECK_FALSE(parse_row("az,el,value,time"));
    CHECK_FALSE(parse_row(""));
    CHECK_FALSE(parse_row("110.0 18.0"));
    CHECK(format_row(*ours) == "174.00,43.00,562,2026-11-23T21:00:00Z");
}

TEST_CASE("resume: an interrupted last row is dropped and scanned again, nothing is repeated") {
    const std::string text = "az,el,value,time\n10.00,20.00,401,t\n10.00,21.00,402,t\n10.00,22.0";
    CHECK(complete_length(text) == text.rfind('\n') + 1);
    const auto done = parse_scan(text);
    REQUIRE(done.size() == 2);
    const auto plan = serpentine(*parse_range("10:11:1"), *parse_range("20:22:1"));
    const auto rest = remaining(plan, done);
    REQUIRE(rest.size() == 4);
    CHECK(rest.front().el == 22.0);  // the cut-off row
    CHECK(rest.back().az == 11.0);
    CHECK(rest.back().el == 20.0);
    // Float text of the same point matches (0.01 degree lattice).
    CHECK(remaining(plan, parse_scan("10.0 20.0 1\n10.000001,21,1,\n")).size() == 4);
    CHECK(remaining(plan, {}).size() == plan.size());
}
