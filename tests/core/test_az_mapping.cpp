// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The azimuth-mapping unit: what each reading predicts, what absolute numbers reach, and what the
// learner concludes from moves (docs/firmware.md §14 G2.4, §2, §3.5).
#include <catch2/catch.hpp>

#include "tracking/az_mapping.hpp"

using namespace birdcage;
using azmap::Mapping;

namespace {

const azmap::Travel travler{{0.0, 455.0}, false};
const azmap::Travel g2{{-423.33, 23.33}, true};

}  // namespace

TEST_CASE("az mapping: the number sent for a mechanical azimuth") {
    CHECK(azmap::command_value(403.004, travler) == 403.0);
    CHECK(azmap::command_value(359.997, travler) == 360.0);  // an angle of the travel
    CHECK(azmap::command_value(-60.0, g2) == 300.0);         // no negative absolute numbers
    CHECK(azmap::command_value(-0.003, g2) == 0.0);          // never 360.00
    CHECK(azmap::command_value(-370.0, g2) == 350.0);
}

TEST_CASE("az mapping: predictions of the three readings") {
    // Trav'ler at 350: 10 is 370 (nearest), 10 (literal), 10 (wrap point north, the long way).
    CHECK(azmap::predict(Mapping::nearest, 10, 350, travler) == Approx(370));
    CHECK(azmap::predict(Mapping::literal, 10, 350, travler) == Approx(10));
    CHECK(azmap::predict(Mapping::wrap_manager, 10, 350, travler, 0) == Approx(10));
    CHECK(azmap::predict(Mapping::wrap_manager, 10, 350, travler, 95) == Approx(370));
    CHECK(azmap::predict(Mapping::nearest, 403, 100, travler) == Approx(403));
    CHECK(azmap::predict(Mapping::literal, 403, 100, travler) == Approx(403));
    CHECK(azmap::predict(Mapping::wrap_manager, 403, 100, travler, 0) == Approx(43));
    CHECK(azmap::predict(Mapping::literal, 500, 100, travler) == Approx(455));  // clamped
    // G2 at -60: 340 is -20 (nearest and literal) or -20 (sector -360..0).
    CHECK(azmap::predict(Mapping::nearest, 340, -60, g2) == Approx(-20));
    CHECK(azmap::predict(Mapping::nearest, 340, -300, g2) == Approx(-380));
    CHECK(azmap::predict(Mapping::literal, 340, -300, g2) == Approx(-20));
    CHECK(azmap::predict(Mapping::literal, 10, -300, g2) == Approx(10));
    CHECK(azmap::predict(Mapping::wrap_manager, 10, -5, g2, 0) == Approx(-350));
}

TEST_CASE("az mapping: what absolute numbers reach") {
    const auto literal_g2 = azmap::reachable(Mapping::literal, g2);
    CHECK(literal_g2.min == Approx(-336.67));
    CHECK(literal_g2.max == Approx(23.33));
    CHECK(azmap::reachable(Mapping::literal, travler).max == Approx(455));
    CHECK(azmap::reachable(Mapping::wrap_manager, travler, 0).max == Approx(360));
    CHECK(azmap::reachable(Mapping::wrap_manager, travler, 95).min == Approx(95));
    CHECK(azmap::reachable(Mapping::wrap_manager, g2, 0).min == Approx(-360));
    CHECK(azmap::reachable(Mapping::wrap_manager, g2, 0).max == Approx(0));
    CHECK(azmap::wrap_sector(200, travler).min == Approx(200));
}

TEST_CASE("az mapping learner: moves every reading explains teach nothing, planning is the most permissive") {
    azmap::Learner learner(travler);
    CHECK_FALSE(learner.observe({120, 100, 100, 120, 120}));
    CHECK_FALSE(learner.observe({200, 120, 120, 200, 200}));
    CHECK_FALSE(learner.known());
    CHECK(learner.planning() == Mapping::nearest);
    CHECK(learner.plan_window({2, 453}).max == Approx(453));
    CHECK(learner.describe().find("still possible: nearest literal wrap_manager") != std::string::npos);
}

TEST_CASE("az mapping learner: a long way round at north is a wrap manager with its point there") {
    azmap::Learner learner(travler);
    // A pass growing from 248 (every reading agrees) ...
    CHECK_FALSE(learner.observe({300, 248, 248, 300, 300}));
    CHECK_FALSE(learner.observe({359.5, 300, 300, 359.5, 359.5}));
    // ... then 360.5 sent at 359.5: the dish turned back through 180 and stopped at 0.5.
    const auto moving = learner.observe({360.5, 359.5, 200.0, 359.5, std::nullopt});
    REQUIRE(moving);
    CHECK_FALSE(learner.possible(Mapping::nearest));
    CHECK_FALSE(learner.possible(Mapping::literal));
    CHECK(learner.known() == Mapping::wrap_manager);
    learner.observe({360.5, 359.5, 0.5, 359.5, 0.5});
    REQUIRE(learner.wrap_point());
    CHECK(std::min(*learner.wrap_point(), 360.0 - *learner.wrap_point()) <= 5.0);
    const auto window = learner.plan_window({2, 453});
    CHECK(window.min >= 2.0);
    CHECK(window.max <= 360.0);
    CHECK(window.max >= 354.0);
    CHECK(learner.describe().find("learnt wrap_manager") != std::string::npos);
}

TEST_CASE("az mapping learner: a G2 that goes back to -30 for 330 reads numbers literally (or by a wrap manager)") {
    azmap::Learner learner(g2);
    // Waypoints towards -390: 210 -> -150 and 90 -> -270 agree with every reading ...
    CHECK_FALSE(learner.observe({210, -30, -150, -30, -150}));
    CHECK_FALSE(learner.observe({90, -150, -270, -150, -270}));
    // ... 330 from -270 should have been -390 (nearest): it went up to -30.
    REQUIRE(learner.observe({330, -270, -270, -30, -30}));
    CHECK_FALSE(learner.possible(Mapping::nearest));
    CHECK(learner.planning() == Mapping::literal);
    const auto window = learner.plan_window({-421.33, 21.33});
    CHECK(window.min == Approx(-336.67));
    CHECK(window.max == Approx(21.33));
}

TEST_CASE("az mapping learner: a stated reading is kept, contradictions are counted") {
    azmap::Learner learner(travler, Mapping::literal);
    CHECK(learner.known() == Mapping::literal);
    // 10 from 350 went to 370: nearest's doing, not literal's.
    const auto message = learner.observe({10, 350, 350, 370, 370});
    REQUIRE(message);
    CHECK(message->find("does not explain") != std::string::npos);
    CHECK(learner.planning() == Mapping::literal);
    CHECK(learner.describe().find("literal (stated; 1 moves it did not explain)") != std::string::npos);
}

TEST_CASE("az mapping learner: a move no reading explains starts over") {
    azmap::Learner learner(travler);
    REQUIRE(learner.observe({360.5, 359.5, 200.0, 359.5, std::nullopt}));  // wrap manager, point at north
    // 100 from 100 ended at 250: nothing sends the axis there.
    const auto message = learner.observe({100, 100, 100, 250, 250});
    REQUIRE(message);
    CHECK(message->find("no known reading explains") != std::string::npos);
    CHECK(learner.possible(Mapping::nearest));
    CHECK(learner.possible(Mapping::literal));
    CHECK(learner.possible(Mapping::wrap_manager));
}
