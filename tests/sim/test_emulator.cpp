// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator through its real pty, the way the backend and rotctld see it. No sleeping for
// motion: a large time scale and waits for conditions with deadlines.
#include <catch2/catch.hpp>

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "birdcage_sim/emulator.hpp"
#include "pty_client.hpp"

using namespace birdcage::sim;
using namespace birdcage::sim::testing;
using namespace std::chrono_literals;

namespace {

Options fast(Variant variant) {
    Options options;
    options.variant = variant;
    options.time_scale = 50.0;
    return options;
}

}  // namespace

TEST_CASE("pty: G2 answers prompts and `a` - a move changes the true position", "[emulator][g2]") {
    Emulator dish(fast(Variant::carryout_g2));
    REQUIRE(dish.device_path().starts_with("/dev/pts/"));
    PtyClient client(dish.device_path());
    CHECK(client.command("", "TRK>") == "\r\nTRK>");
    CHECK(client.command("mot", "MOT>") == "mot\r\nMOT>");
    CHECK(client.command("a", "MOT>") == "a\r\n    Angle[0] = 180.00\r\n    Angle[1] = 45.00\r\nMOT>");
    CHECK(client.command("a 0 210", "MOT>") == "a 0 210\r\n    Angle = 210.00\r\nMOT>");
    CHECK(client.command("a 1 30", "MOT>") == "a 1 30\r\n    Angle = 30.00\r\nMOT>");
    REQUIRE(wait_for([&] { return !dish.moving(); }));
    CHECK(dish.true_position().az == Approx(210.0).margin(0.01));
    CHECK(dish.true_position().el == Approx(30.0).margin(0.015));
    CHECK(dish.true_mechanical_az() == Approx(-150.0).margin(0.01));
    CHECK(dish.received_commands() == std::vector<std::string>{"", "mot", "a", "a 0 210", "a 1 30"});
    const auto history = dish.history();
    REQUIRE(history.size() > 10);
    CHECK(history.front().az == Approx(180.0));
    CHECK(history.back().el == Approx(30.0).margin(0.015));
    CHECK(history.back().t > history.front().t);
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("pty: symlink, and a client may close and reopen the device", "[emulator]") {
    Options options = fast(Variant::carryout_g2);
    options.link_path = "/tmp/birdcage-sim-test-" + std::to_string(::getpid());
    {
        Emulator dish(options);
        CHECK(dish.device_path() == options.link_path);
        struct stat info {};
        REQUIRE(::lstat(options.link_path.c_str(), &info) == 0);
        CHECK(S_ISLNK(info.st_mode));
        for (int round = 0; round < 3; ++round) {
            PtyClient client(dish.device_path());
            CHECK(client.command("", "TRK>") == "\r\nTRK>");
        }
    }
    struct stat info {};
    CHECK(::lstat(options.link_path.c_str(), &info) != 0);
}

TEST_CASE("pty: G2 root q is a hazard that kills the shell until power_cycle", "[emulator][g2][hazard]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    CHECK(client.command("q", "Terminating shell.\r\n").size() > 0);
    CHECK(dish.hazards_received() == 1);
    CHECK_FALSE(dish.shell_alive());
    CHECK(client.command("", ">", 300ms).empty());
    dish.power_cycle();
    CHECK(client.read_until("GPS Not Found\r\nTRK>").size() > 0);
    CHECK(client.command("", "TRK>") == "\r\nTRK>");
}

TEST_CASE("pty: G2 boot sequence at a high time scale", "[emulator][g2][boot]") {
    Options options = fast(Variant::carryout_g2);
    options.already_booted = false;
    options.time_scale = 100.0;
    Emulator dish(options);
    PtyClient client(dish.device_path());
    const std::string boot = client.read_until("TRK>", 10s);
    REQUIRE_FALSE(boot.empty());
    CHECK(boot.starts_with(std::string("\x01\x00", 2) +
                           "Bootloader version: 1.01\r\nApplication is running...\r\n\x98\x80\x96"));
    CHECK(boot.find("Boot Complete\r\n\r\nLoc Startup: IDU NOT Present\r\n") != std::string::npos);
    CHECK(boot.ends_with("GPS Not Found\r\nTRK>"));
    CHECK_FALSE(dish.search_running());
    CHECK(dish.true_position().el == Approx(45.0).margin(0.015));  // no homing at boot

    options.g2_console = birdcage::sim::G2Console::reconstructed;
    Emulator old(options);
    PtyClient old_client(old.device_path());
    const std::string old_boot = old_client.read_until("TRK>", 10s);
    CHECK(old_boot.starts_with("Bootloader v1.01\r\n"));
    CHECK(old_boot.find("wrap_min:-42333 wrap_max:2333\r\n") != std::string::npos);
    CHECK(old_boot.ends_with("Boot Complete\r\nLoc Startup: IDU NOT Present\r\nTRK>"));
    CHECK(old.true_position().el == Approx(65.0).margin(0.015));
}

TEST_CASE("pty: HAL 2.05 power-on: NoGPS, search wanders, ngsearch s q stops it", "[emulator][hal205]") {
    Options options = fast(Variant::travler_hal205);
    options.already_booted = false;
    options.time_scale = 100.0;
    Emulator dish(options);
    PtyClient client(dish.device_path());
    REQUIRE_FALSE(client.read_until("NoGPS", 10s).empty());
    REQUIRE(wait_for([&] { return dish.search_running(); }));
    const Pose before = dish.true_position();
    REQUIRE(wait_for([&] {
        const Pose now = dish.true_position();
        return std::abs(now.az - before.az) > 5.0 || std::abs(now.el - before.el) > 5.0;
    }));
    // birdcage's stop sequence (§4.3)
    client.command("q", "TRK>");
    client.command("", "TRK>");
    CHECK(client.command("ngsearch", "NGSEARCH>") == "ngsearch\r\nNGSEARCH>");
    client.command("s", "NGSEARCH>");
    CHECK(client.command("q", "TRK>") == "q\r\nTRK>");
    CHECK_FALSE(dish.search_running());
    REQUIRE(wait_for([&] { return !dish.moving(); }));
    CHECK(client.command("motor", "MOTOR>") == "motor\r\nMOTOR>");
    client.command("a 0 100", "MOTOR>");
    client.command("a 1 20", "MOTOR>");
    REQUIRE(wait_for([&] { return !dish.moving(); }, 20s));
    CHECK(client.command("a", "MOTOR>") == "a\r\nAZ = 100.00 EL = 20.00 SK = 0.00\r\nMOTOR>");
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("pty: CRLF clients and NVS hazards on the HAL 0.0.00", "[emulator][hal000]") {
    Emulator dish(fast(Variant::travler_hal000));
    PtyClient client(dish.device_path());
    client.send("nvs\r\n");
    CHECK(client.read_until("NVS>") == "nvs\r\nNVS>");
    client.send("e 127 0\r\n");
    CHECK(client.read_until("NVS>").find("127) Safe Minimum Elevation") != std::string::npos);
    CHECK(dish.hazards_received() == 1);
    CHECK(dish.received_commands() == std::vector<std::string>{"nvs", "e 127 0"});
}

TEST_CASE("pty: Carryout 2003 g streams positions and ends with the prompt", "[emulator][carryout2003]") {
    Emulator dish(fast(Variant::carryout2003));
    PtyClient client(dish.device_path());
    client.command("target", "TARGET>");
    const std::string live = client.command("g 150 40", "TARGET>");
    CHECK(live.starts_with("g 150 40\r\naz = 18000   el = 4500\r\n"));
    CHECK(live.ends_with("az = 15000   el = 4000\r\nTARGET>"));
    CHECK(dish.true_position().az == Approx(150.0));
}

TEST_CASE("pty: Trav'ler Pro client start-up sequence reaches the ODU motor menu", "[emulator][pro]") {
    Emulator dish(fast(Variant::travler_pro));
    PtyClient client(dish.device_path());
    client.send("q\r\rodu\r\rq\r\rmot\r");
    CHECK_FALSE(client.read_until("MOT>").empty());
    CHECK(client.command("a", "MOT>") == "a\r\nAZ = 180.00 EL = 45.00 SK = 0.00\r\nMOT>");
}
