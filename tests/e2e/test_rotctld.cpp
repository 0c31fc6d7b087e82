// End to end: emulated dish <- pty <- stock /usr/bin/rotctld + preloaded backend <- stock rotctl -m 2.
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace std::chrono_literals;
using birdcage::sim::Variant;

namespace {

struct ModelUnderTest {
    Variant variant;
    int model;
    const char* name;
    double el_min;
    double el_max;
    // Emulator time scale for tests that watch a move happen (slow enough to catch it mid-move).
    double watchable_time_scale;
};

const ModelUnderTest kModels[] = {
    {Variant::travler_hal000, 90101, "Trav'ler HAL 0.0.00", 15.0, 90.0, 8.0},
    {Variant::travler_hal205, 90102, "Trav'ler HAL 2.05", 15.0, 90.0, 8.0},
    {Variant::travler_pro, 90103, "Trav'ler Pro", 12.0, 75.0, 8.0},
    {Variant::carryout2003, 90104, "Carryout HAL 1.00.065", 22.0, 73.0, 4.0},
    {Variant::carryout_g2, 90105, "Carryout G2", 18.0, 65.0, 2.0},
};

} // namespace

TEST_CASE("rotctl -l lists the Winegard models only when the backend is preloaded", "[e2e][registration]") {
    const e2e::CommandResult with = e2e::run({"/usr/bin/rotctl", "-l"}, e2e::preload_environment());
    REQUIRE(with.exit_code == 0);
    for (const ModelUnderTest& m : kModels) {
        INFO(m.name);
        CHECK(with.out.find(std::to_string(m.model)) != std::string::npos);
        CHECK(with.out.find(m.name) != std::string::npos);
    }
    CHECK(with.out.find("Winegard") != std::string::npos);
    // Registration is silent: no debug noise from the load-time constructor.
    CHECK(with.err.find("rot_register") == std::string::npos);

    const e2e::CommandResult without = e2e::run({"/usr/bin/rotctl", "-l"});
    CHECK(without.out.find("Winegard") == std::string::npos);
}

TEST_CASE("stock rotctld drives the dish: P moves it, p reports it", "[e2e]") {
    for (const ModelUnderTest& m : kModels) {
        DYNAMIC_SECTION(m.name) {
            e2e::Rig rig(e2e::dish_options(m.variant, 100.0, 30.0, 50.0), m.model, {"-C", "leapfrog=0"});
            const e2e::CommandResult set = rig.rotctl({"P", "180", "45"});
            INFO(set.out << set.err);
            REQUIRE(set.exit_code == 0);

            REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 180.0, 45.0, 0.1); }, 30s));

            std::vector<double> reported;
            const bool reports = e2e::wait_until(
                [&] {
                    reported = e2e::numbers(rig.rotctl({"p"}).out);
                    return reported.size() == 2 && e2e::angle_between(reported[0], 180.0) <= 0.1 &&
                           std::fabs(reported[1] - 45.0) <= 0.1;
                },
                10s);
            INFO("rotctl p printed " << reported.size() << " numbers");
            CHECK(reports);
            CHECK(rig.dish().hazards_received() == 0);
        }
    }
}

TEST_CASE("leapfrog (default on) leads each axis in its direction of travel", "[e2e][leapfrog]") {
    // From (100, 30) both axes lag by more than 2 degrees: each is led by 1 degree. Upstream's
    // bug would have put both nudges on azimuth (182, 45).
    const ModelUnderTest& m = kModels[4];
    e2e::Rig rig(e2e::dish_options(m.variant, 100.0, 30.0, 50.0), m.model);
    REQUIRE(rig.rotctl({"P", "180", "45"}).exit_code == 0);
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 181.0, 46.0, 0.1); }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("S stops the dish: the leg not yet sent is dropped", "[e2e][stop]") {
    for (const ModelUnderTest& m : kModels) {
        DYNAMIC_SECTION(m.name) {
            e2e::Rig rig(e2e::dish_options(m.variant, 100.0, 30.0, m.watchable_time_scale), m.model, {"-C", "leapfrog=0"});
            // The first move sends azimuth first; elevation waits until azimuth has arrived.
            REQUIRE(rig.rotctl({"P", "280", "50"}).exit_code == 0);
            REQUIRE(e2e::wait_until([&] { return rig.dish().moving(); }, 10s));
            REQUIRE(rig.rotctl({"S"}).exit_code == 0);

            REQUIRE(e2e::wait_until([&] { return !rig.dish().moving(); }, 30s));
            const birdcage::sim::Pose stopped = rig.dish().true_position();
            // Give a wrongly queued elevation leg every chance to show up.
            REQUIRE(rig.rotctl({"p"}).exit_code == 0);
            CHECK_FALSE(e2e::wait_until([&] { return rig.dish().moving(); }, 1500ms));
            CHECK(std::fabs(rig.dish().true_position().el - 30.0) < 0.05);
            CHECK(std::fabs(stopped.el - 30.0) < 0.05);
            CHECK(rig.dish().hazards_received() == 0);
        }
    }
}

TEST_CASE("elevation is clamped to the variant's limits", "[e2e][limits]") {
    for (const ModelUnderTest& m : kModels) {
        DYNAMIC_SECTION(m.name) {
            e2e::Rig rig(e2e::dish_options(m.variant, 100.0, 30.0, 50.0), m.model, {"-C", "leapfrog=0"});
            REQUIRE(rig.rotctl({"P", "120", "5"}).exit_code == 0);
            CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, m.el_min, 0.1); }, 30s));
            if (m.el_max < 90.0) {
                REQUIRE(rig.rotctl({"P", "120", "89"}).exit_code == 0);
                CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, m.el_max, 0.1); }, 30s));
            }
            CHECK(rig.dish().hazards_received() == 0);
        }
    }
}

TEST_CASE("rotctld wire replies: errors are RPRT codes, the session survives them", "[e2e][wire]") {
    const ModelUnderTest& m = kModels[4];
    e2e::Rig rig(e2e::dish_options(m.variant, 100.0, 30.0, 50.0), m.model, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());

    const std::string pos = client.ask("p", 2);
    const std::vector<double> values = e2e::numbers(pos);
    REQUIRE(values.size() == 2);
    CHECK(std::fabs(values[0] - 100.0) < 0.1);
    CHECK(std::fabs(values[1] - 30.0) < 0.1);

    CHECK(client.ask("P 999 20", 1) == "RPRT -1\n");  // Hamlib's own range check
    CHECK(client.ask("P nan 45", 1) == "RPRT -1\n");  // passes Hamlib's check, refused by the backend
    CHECK(client.ask("P 120 40", 1) == "RPRT 0\n");
    CHECK(client.ask("_", 1).find("Winegard") != std::string::npos);
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, 40.0, 0.1); }, 30s));
    CHECK(rig.dish().hazards_received() == 0);
}
