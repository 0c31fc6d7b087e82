// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/variants.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

TEST_CASE("variants: one row per VariantId, looked up by id and name") {
    const VariantId ids[] = {VariantId::travler_hal000, VariantId::travler_hal205, VariantId::travler_pro,
                             VariantId::carryout2003, VariantId::carryout_g2};
    REQUIRE(all_profiles().size() == std::size(ids));
    std::set<std::string_view> names;
    for (const VariantId id : ids) {
        const FirmwareProfile& row = profile(id);
        INFO(row.short_name);
        CHECK(row.id == id);
        CHECK(variant_from_name(row.short_name) == id);
        CHECK(row.el_min < row.el_max);
        CHECK(row.line_ending == "\r");
        names.insert(row.display_name);
    }
    CHECK(names.size() == std::size(ids));  // rot_init checks each caps' model name against it
    CHECK_FALSE(variant_from_name("g3"));
}

TEST_CASE("variants: facts from docs/firmware.md") {
    const auto& g2 = profile(VariantId::carryout_g2);
    CHECK(g2.short_name == "g2");
    CHECK(g2.baud == 115200);
    CHECK(g2.root_prompt == "TRK>");
    CHECK(g2.motor_prompt == "MOT>");
    CHECK(g2.el_min == 18.0);
    CHECK(g2.el_max == 65.0);
    CHECK(g2.has(quirk_q_at_root_kills_shell));
    CHECK(g2.has(quirk_requires_homing));
    CHECK(g2.search_kill.empty());

    const auto& hal205 = profile(VariantId::travler_hal205);
    CHECK(hal205.baud == 57600);
    CHECK_FALSE(hal205.prompt_known());
    REQUIRE(hal205.motor_menu_entry.size() == 1);
    CHECK(hal205.motor_menu_entry[0].command == "motor");
    REQUIRE(hal205.search_kill.size() == 6);
    CHECK(hal205.search_kill[2].command == "ngsearch");
    CHECK(hal205.search_kill[3].command == "s");
    CHECK(hal205.boot_complete_markers.size() == 2);
    CHECK_FALSE(hal205.has(quirk_q_at_root_kills_shell));

    const auto& hal000 = profile(VariantId::travler_hal000);
    CHECK(hal000.motor_menu_entry[0].command == "mot");
    CHECK(hal000.search_kill[3].command == "kill Search");
    CHECK(hal000.el_min == 15.0);

    const auto& pro = profile(VariantId::travler_pro);
    CHECK(pro.el_min == 12.0);
    CHECK(pro.el_max == 75.0);
    CHECK(pro.has(quirk_odu_tunnel));

    const auto& carryout = profile(VariantId::carryout2003);
    CHECK(carryout.el_min == 22.0);
    CHECK(carryout.el_max == 73.0);
    CHECK(carryout.position_query.empty());
    CHECK(carryout.move_style == MoveStyle::combined_g);
    CHECK(carryout.motor_menu_entry[0].command == "target");
}

TEST_CASE("estimated_move_time: G2 trapezoid (docs/tracking.md 1.4)") {
    const auto& g2 = profile(VariantId::carryout_g2);
    CHECK(estimated_move_time(g2, Axis::azimuth, 1.0) == 100ms);
    CHECK(estimated_move_time(g2, Axis::azimuth, 180.0).count() == Approx(2931).margin(2));
    CHECK(estimated_move_time(g2, Axis::elevation, 47.0).count() == Approx(1157).margin(2));
    CHECK(estimated_move_time(g2, Axis::azimuth, -90.0).count() == Approx(1547).margin(2));
}

TEST_CASE("estimated_move_time: Trav'ler time fit (docs/firmware.md 3.4), floored where the fit dips") {
    const auto& hal205 = profile(VariantId::travler_hal205);
    CHECK(estimated_move_time(hal205, Axis::azimuth, 0.2) == 300ms);
    CHECK(estimated_move_time(hal205, Axis::azimuth, 0.7) == 500ms);
    CHECK(estimated_move_time(hal205, Axis::azimuth, 1.3) == 1000ms);
    CHECK(estimated_move_time(hal205, Axis::azimuth, 10.0).count() == Approx(6400).margin(100));
    CHECK(estimated_move_time(hal205, Axis::azimuth, 90.0).count() == Approx(13500).margin(100));
}

TEST_CASE("variants: park positions lie within the limits") {
    for (const auto& p : all_profiles()) {
        INFO(p.short_name);
        CHECK(p.park_el >= p.el_min);
        CHECK(p.park_el <= p.el_max);
    }
}
