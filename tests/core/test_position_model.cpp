// The position model between polls (position_model.hpp): a leg in flight advances the reading
// along the variant's estimated move time with an accelerate/brake profile.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>

#include "birdcage/position_model.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

TEST_CASE("position model: no leg in flight, the reading; a leg, from its start to its target") {
    const FirmwareProfile& g2 = profile(VariantId::carryout_g2);
    const Clock::time_point t0 = Clock::time_point{} + 1h;
    const AzEl last{100, 30};
    CHECK(modelled_position(g2, last, std::nullopt, t0 + 10s).az == Approx(100));

    const LegMotion leg{Axis::azimuth, 100.0, 140.0, t0, t0};
    const auto move = estimated_move_time(g2, Axis::azimuth, 40.0);
    REQUIRE(move > 0ms);
    CHECK(modelled_position(g2, last, leg, t0).az == Approx(100));
    const AzEl half = modelled_position(g2, last, leg, t0 + move / 2);
    CHECK(half.az == Approx(120).margin(0.1));   // symmetric profile: halfway at half time
    CHECK(half.el == Approx(30));                 // the other axis does not move
    const AzEl quarter = modelled_position(g2, last, leg, t0 + move / 4);
    CHECK(quarter.az < 110.0);                    // still accelerating: less than a quarter of the way
    CHECK(modelled_position(g2, last, leg, t0 + move * 3).az == Approx(140));
}

TEST_CASE("position model: an azimuth leg across north takes the short way and wraps") {
    const FirmwareProfile& g2 = profile(VariantId::carryout_g2);
    const Clock::time_point t0 = Clock::time_point{} + 1h;
    const LegMotion leg{Axis::azimuth, 350.0, 10.0, t0, t0};
    const auto move = estimated_move_time(g2, Axis::azimuth, 20.0);
    const double halfway = modelled_position(g2, AzEl{350, 30}, leg, t0 + move / 2).az;
    CHECK(std::fabs(azimuth_difference(0.0, halfway)) < 0.1);   // at north, whichever side of 0/360
    CHECK(modelled_position(g2, AzEl{350, 30}, leg, t0 + move).az == Approx(10));
}
