// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// receiver.hpp's pure parts: the LNB supply commands and values, the reading's time budget.
#include "dish/receiver.hpp"
#include "firmware/variants.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace birdcage;

TEST_CASE("receiver: LNB supply commands and volts") {
    CHECK(build_lnb_supply(LnbSupply::odu_13v) == "lnbdc odu");
    CHECK(build_lnb_supply(LnbSupply::stb_18v) == "lnbdc stb");
    CHECK(lnb_volts(LnbSupply::odu_13v) == 13);
    CHECK(lnb_volts(lnb_boot_default) == 18);  // `Enabled LNB STB` at boot
    CHECK(lnb_supply_from_volts(13.0).value == LnbSupply::odu_13v);
    CHECK(lnb_supply_from_volts(18.0).value == LnbSupply::stb_18v);
    CHECK_FALSE(lnb_supply_from_volts(12.0));
    CHECK_FALSE(lnb_supply_from_volts(24.0));
    CHECK_FALSE(lnb_supply_from_volts(std::nan("")));
}

TEST_CASE("receiver: a reading's budget grows with its samples (20 ms each)") {
    CHECK(rssi_timeout(100) - rssi_timeout(10) == std::chrono::milliseconds(1800));
}

TEST_CASE("receiver: only the G2 row names a tuner menu") {
    for (VariantId id :
         {VariantId::travler_hal000, VariantId::travler_hal205, VariantId::travler_pro, VariantId::carryout2003}) {
        CHECK(profile(id).receiver_menu.empty());
    }
    CHECK(profile(VariantId::carryout_g2).receiver_menu == "dvb");
}
