// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// carryout_rotor.py v1.0 and carryout_scan.py (docs/firmware.md §8.4, §8.7, §12.3, Appendix C)
// against the 2003 Carryout over the real pty.
#include <catch2/catch.hpp>

#include "../sim/pty_client.hpp"
#include "birdcage_sim/emulator.hpp"
#include "client_port.hpp"

using namespace birdcage::clients;
using birdcage::sim::Emulator;
using birdcage::sim::Options;
using birdcage::sim::Variant;
using birdcage::sim::testing::wait_for;

namespace {

constexpr double time_scale = 20.0;

Options carryout() {
    Options options;
    options.variant = Variant::carryout2003;
    options.time_scale = time_scale;
    return options;
}

// carryout_rotor.py v1.0 (§8.7): P writes `target`, `g <az> <el>`, reads 100 bytes (1 s),
// parses them (§8.4), answers, then writes `q`. Its token index is a module-level variable
// that is never reset (§12.3): each search starts past the `el` of the previous success.
class CarryoutRotor {
public:
    explicit CarryoutRotor(ClientPort& port) : port_(port) {
        port_.write("q\r");
        port_.write("\r");
    }

    std::string P(double az, double el) {
        port_.write("target\r");
        port_.write("g " + py_float(az) + " " + py_float(el) + "\r");
        chunk_ = port_.read(100, 1.0);
        REQUIRE(strict_ascii(chunk_));  // .decode() would raise
        std::vector<std::string> tokens = py_split_space(py_strip(chunk_));
        tokens.erase(tokens.begin());
        parsed_ = false;
        for (; index_ < tokens.size(); ++index_) {
            if (tokens[index_] != "el")
                continue;
            // tokens[k-3] and tokens[k+2][:4]; Python would wrap a negative index and raise on
            // one past the end - either is a client failure here.
            REQUIRE(index_ >= 3);
            REQUIRE(index_ + 2 < tokens.size());
            const auto az_centi = py_int(tokens[index_ - 3]);
            const auto el_centi = py_int(tokens[index_ + 2].substr(0, 4));
            REQUIRE(az_centi);  // int() would raise
            REQUIRE(el_centi);
            az_ = static_cast<double>(*az_centi) / 100.0;
            el_ = static_cast<double>(*el_centi) / 100.0;
            parsed_ = true;
            ++index_;
            break;
        }
        port_.write("q\r");
        return "RPRT 0\n ";
    }

    std::string p() const { return py_float(az_) + "\n" + py_float(el_) + "\n"; }
    bool parsed() const { return parsed_; }
    const std::string& chunk() const { return chunk_; }

private:
    ClientPort& port_;
    std::size_t index_ = 0;
    double az_ = 0.0, el_ = 0.0;
    bool parsed_ = false;
    std::string chunk_;
};

}  // namespace

TEST_CASE("carryout_rotor.py: g live output parsed within 100 bytes / 1 s, the trailing q does not stop the dish",
          "[clients][carryout2003]") {
    Emulator dish(carryout());
    ClientPort port(dish.device_path(), time_scale);
    CarryoutRotor rotor(port);
    CHECK(rotor.p() == "0.0\n0.0\n");  // cached until the first move
    CHECK(rotor.P(200.0, 40.0) == "RPRT 0\n ");
    REQUIRE(rotor.parsed());
    // The first live line shows where the dish was when `g` started (180, 45).
    CHECK(rotor.p() == "180.0\n45.0\n");
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(200.0));
    CHECK(dish.true_position().el == Approx(40.0));

    // Later moves: whatever the stale index finds, the parse must not crash (REQUIREs inside)
    // and the dish must get there.
    for (const auto& [az, el] : {std::pair{230.0, 55.0}, {100.0, 25.0}}) {
        CAPTURE(az, el);
        const std::size_t received = dish.received_commands().size();
        rotor.P(az, el);
        REQUIRE(wait_for([&] { return dish.received_commands().size() >= received + 3 && !dish.moving(); },
                         std::chrono::seconds(30)));
        CHECK(dish.true_position().az == Approx(az));
        CHECK(dish.true_position().el == Approx(el));
    }
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("carryout_rotor.py: a trailing q that aborts g leaves the dish short (g-aborts switch)",
          "[clients][carryout2003]") {
    Options options = carryout();
    options.g_aborts_on_input = true;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    CarryoutRotor rotor(port);
    rotor.P(300.0, 60.0);
    REQUIRE(wait_for([&] { return dish.received_commands().size() >= 5 && !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az < 290.0);
}

TEST_CASE("carryout_scan.py: q CR target g, then per point target g q with no reads or pauses",
          "[clients][carryout2003]") {
    Emulator dish(carryout());
    ClientPort port(dish.device_path(), time_scale);
    // §8.7 move to start, then 5 s.
    for (const char* command : {"q\r", "\r", "target\r", "g 190 30\r"})
        port.write(command);
    port.client_sleep(5.0);
    REQUIRE(wait_for([&] { return dish.received_commands().size() >= 4 && !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(190.0));
    // One boustrophedon row of 1-degree steps; each sample is taken before the next move, and
    // moving the SDR samples takes ~0.3 s a point (§8.5).
    for (int az = 191; az <= 194; ++az) {
        port.client_sleep(0.3);
        port.write("target\r");
        port.write("g " + std::to_string(az) + " 30\r");
        port.write("q\r");
    }
    REQUIRE(wait_for([&] { return dish.received_commands().size() >= 4 + 12 && !dish.moving(); },
                     std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(194.0));
    CHECK(dish.shell_alive());
}
