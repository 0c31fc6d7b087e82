// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The G2-shell clients (docs/firmware.md §6.6, §7, Appendix C) against the Carryout G2 over the
// real pty: Davidson's winegard-sky-scan scripts, mjlangan's G2+ rotor and Fox's rotor. All of
// them send `q` at the root prompt first, so they need the "harmless" reading of §14 G2.2; the
// test names say so.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <regex>

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

Options g2(bool root_q_harmless) {
    Options options;
    options.variant = Variant::carryout_g2;
    options.time_scale = time_scale;
    options.g2_root_q = root_q_harmless ? birdcage::sim::G2RootQ::harmless : birdcage::sim::G2RootQ::kill;
    return options;
}

// library/winegard.py (§6.6): write, then one byte at a time until `>`, 15 s per byte, strict
// decode. An empty optional is the library's "failed" status.
class DavidsonLink {
public:
    explicit DavidsonLink(ClientPort& port) : port_(port) {}

    std::optional<std::string> command(const std::string& text) {
        port_.write(text + "\r");
        auto reply = port_.read_through('>', 15.0);
        if (reply)
            REQUIRE(strict_ascii(*reply));
        if (reply)
            replies_.push_back({text, *reply});
        return reply;
    }

    // rotator.py's position parse: every digits.digits run, exactly two (AZ, EL).
    std::optional<std::pair<double, double>> position() {
        const auto reply = command("a");
        if (!reply)
            return std::nullopt;
        static const std::regex decimal("[0-9]+\\.[0-9]+");
        const auto numbers = regex_all(*reply, decimal);
        if (numbers.size() != 2)
            return std::nullopt;
        return std::pair{std::stod(numbers[0]), std::stod(numbers[1])};
    }

    // skyscan.py's RSSI parse: every digit run, exactly six; reads, average, current last.
    std::optional<std::array<long, 3>> rssi() {
        const auto reply = command("rssi 10");
        if (!reply)
            return std::nullopt;
        static const std::regex digits("[0-9]+");
        const auto runs = regex_all(*reply, digits);
        if (runs.size() != 6)
            return std::nullopt;
        return std::array<long, 3>{std::stol(runs[3]), std::stol(runs[4]), std::stol(runs[5])};
    }

    // Appendix C: each reply is the echo of its own command (nothing left over from the one
    // before) and ends with exactly one `>`, the prompt.
    void check_replies() const {
        for (const auto& [sent, reply] : replies_) {
            CAPTURE(sent, reply);
            CHECK(reply.starts_with(sent + "\r\n"));
            CHECK(std::count(reply.begin(), reply.end(), '>') == 1);
        }
    }

private:
    ClientPort& port_;
    std::vector<std::pair<std::string, std::string>> replies_;
};

}  // namespace

TEST_CASE("Davidson home.py [root q harmless]: q mot h 0 h 1 a 0 180 q, every reply ends in its prompt",
          "[clients][g2]") {
    Options options = g2(true);
    options.g2_homed = false;  // NVS 20 TRUE: the axes are uncalibrated until homed (§6.2)
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    DavidsonLink link(port);
    bool success = true;
    for (const char* command : {"q", "mot", "h 0", "h 1", "a 0 180", "q"}) {
        const auto reply = link.command(command);
        success = success && reply && reply->back() == '>';
    }
    port.client_sleep(4.0);
    CHECK(success);
    link.check_replies();
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(180.0).margin(0.01));
    CHECK(dish.true_position().el == Approx(65.0).margin(0.015));
    CHECK(dish.hazards_received() == 1);  // the root q, harmless here but never to be sent
    CHECK(dish.shell_alive());
}

TEST_CASE("Davidson home.py fails against the default root-q reading (kill): no prompt for 15 s",
          "[clients][g2][hazard]") {
    Emulator dish(g2(false));
    ClientPort port(dish.device_path(), time_scale);
    DavidsonLink link(port);
    CHECK_FALSE(link.command("q"));
    CHECK_FALSE(dish.shell_alive());
}

TEST_CASE("Davidson rotator.py [root q harmless]: p is exactly two decimals, P is a 0 / a 1", "[clients][g2]") {
    Emulator dish(g2(true));
    ClientPort port(dish.device_path(), time_scale);
    DavidsonLink link(port);
    REQUIRE(link.command("q"));
    REQUIRE(link.command("mot"));
    // rotctld p / P as rotator.py answers them.
    const auto p = [&]() -> std::string {
        const auto position = link.position();
        if (!position)
            return "RPRT 1\n";
        return py_float(std::fmod(position->first - 0.0, 360.0)) + "\n" + py_float(position->second) + "\n";
    };
    const auto P = [&](double az, double el) -> std::string {
        const bool ok =
            link.command("a 0 " + py_float(std::fmod(az + 0.0, 360.0))) && link.command("a 1 " + py_float(el));
        return ok ? "RPRT 0\n" : "RPRT 1\n";
    };
    CHECK(p() == "180.0\n45.0\n");
    CHECK(P(200.25, 40.5) == "RPRT 0\n");
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(p() == "200.25\n40.5\n");
    CHECK(P(123.0, 18.0) == "RPRT 0\n");
    CHECK(P(124.0, 19.0) == "RPRT 0\n");  // issued while the dish still moves
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(p() == "124.0\n19.0\n");
    link.check_replies();
}

TEST_CASE("Davidson skyscan.py [root q harmless]: setup, then per point a 1, 0.2 s, q dvb rssi 10 q mot",
          "[clients][g2]") {
    Emulator dish(g2(true));
    ClientPort port(dish.device_path(), time_scale);
    DavidsonLink link(port);
    for (const char* command : {"q", "dvb", "lnbdc odu", "q", "mot", "a 0 110", "a 1 18"})
        REQUIRE(link.command(command));
    port.client_sleep(4.0);
    // A 3 x 3 corner of skyscan.sh's grid (AZ 110.., EL 18.., step 1.0), loops as written.
    int points = 0;
    for (double az = 110.0; az <= 112.0; az += 1.0) {
        REQUIRE(link.command("a 0 " + py_float(az)));
        for (double el = 18.0; el <= 20.0; el += 1.0) {
            REQUIRE(link.command("a 1 " + py_float(el)));
            port.client_sleep(0.2);
            REQUIRE(link.command("q"));
            REQUIRE(link.command("dvb"));
            const auto rssi = link.rssi();
            REQUIRE(rssi);  // -1 in its output file otherwise
            CHECK((*rssi)[0] == 10);
            CHECK((*rssi)[1] >= 380);
            CHECK((*rssi)[1] <= 600);
            ++points;
            REQUIRE(link.command("q"));
            REQUIRE(link.command("mot"));
        }
        REQUIRE(link.command("a 1 18"));
        port.client_sleep(1.0);
    }
    REQUIRE(link.command("q"));
    CHECK(points == 9);
    link.check_replies();
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(112.0).margin(0.01));
    CHECK(dish.true_position().el == Approx(18.0).margin(0.015));
    CHECK(dish.hazards_received() == 1);
}

TEST_CASE("Davidson skyscan.py's six-integer RSSI parse needs the echo (echo switch off: parse fails)",
          "[clients][g2]") {
    Options options = g2(true);
    options.echo = false;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    DavidsonLink link(port);
    REQUIRE(link.command("dvb"));
    CHECK_FALSE(link.rssi());
}

TEST_CASE("mjlangan G2+ rotor [root q harmless, G2+ home report]: h * until `AZ - Angle: 1 Wrap: 0`, then Angle acks",
          "[clients][g2]") {
    Options options = g2(true);
    options.g2_homed = false;
    options.home_report = birdcage::sim::HomeReport::g2plus_status;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    // Lines until `pattern` matches one (1 s readline, decode errors ignored); the client waits
    // forever, the test gives up after `limit` real seconds.
    const auto wait_line = [&](const std::regex& pattern, double limit, auto&& accept) {
        const auto give_up = Clock::now() + std::chrono::duration_cast<Clock::duration>(Seconds(limit));
        while (Clock::now() < give_up) {
            const std::string line = port.readline(1.0);
            std::smatch match;
            if (std::regex_search(line, match, pattern) && accept(match))
                return true;
        }
        return false;
    };
    port.write("q\r");
    port.write("\r");
    port.write("mot\r");
    port.write("h *\r");
    static const std::regex homed("AZ\\s*-\\s*Angle:\\s*1\\s*Wrap:\\s*0");
    REQUIRE(wait_line(homed, 20.0, [](const std::smatch&) { return true; }));
    // rotctld P: mot, a 0, wait for its Angle ack, a 1, the same, RPRT 0 + space, q.
    static const std::regex ack("Angle\\s*=\\s*(-?\\d+(\\.\\d+)?)");
    const auto P = [&](double az, double el) {
        port.write("mot\r");
        for (const auto& [axis, target] : {std::pair{0, az}, {1, el}}) {
            port.write("a " + std::to_string(axis) + " " + py_float(target) + "\r");
            REQUIRE(wait_line(
                ack, 20.0, [target](const std::smatch& m) { return std::abs(std::stod(m[1].str()) - target) < 0.01; }));
        }
        port.write("q\r");
        return std::string("RPRT 0\n ");
    };
    CHECK(P(200.0, 40.0) == "RPRT 0\n ");
    CHECK(P(350.5, 64.0) == "RPRT 0\n ");
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(350.5).margin(0.01));
    CHECK(dish.true_position().el == Approx(64.0).margin(0.015));
}

TEST_CASE("mjlangan G2+ rotor waits in vain for its homing line on the 02.02.48 report (home-report default)",
          "[clients][g2]") {
    Options options = g2(true);
    options.g2_homed = false;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    for (const char* command : {"q\r", "\r", "mot\r", "h *\r"})
        port.write(command);
    static const std::regex homed("AZ\\s*-\\s*Angle:\\s*1\\s*Wrap:\\s*0");
    std::string seen;
    const auto give_up = Clock::now() + std::chrono::seconds(10);
    while (seen.find("wrap_max") == std::string::npos && Clock::now() < give_up)
        seen += port.readline(1.0);
    seen += port.readline(1.0);  // and whatever follows within a second
    CHECK(seen.find("home:0  wrap_pos:0  wrap_min:-42333  wrap_max:2333") != std::string::npos);
    CHECK_FALSE(std::regex_search(seen, homed));
}

TEST_CASE("Fox rotor [root q harmless]: h * until a 100-byte chunk ends in MOT>, then `= d.dd` within 100 bytes",
          "[clients][g2]") {
    Options options = g2(true);
    options.g2_homed = false;  // tracker disabled, so no power-on limit finding (§7.2)
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    for (const char* command : {"q\r", "\r", "mot\r", "h *\r"})
        port.write(command);
    const auto give_up = Clock::now() + std::chrono::seconds(20);
    for (;;) {
        REQUIRE(Clock::now() < give_up);
        const std::string chunk = port.read(100, 1.0);
        REQUIRE(strict_ascii(chunk));
        if (py_strip(chunk).ends_with("MOT>"))
            break;
    }
    port.write("q\r");
    static const std::regex value("= (\\d+\\.\\d+)");
    const auto P = [&](double az, double el) {
        std::array<double, 2> parsed{};
        port.reset_input_buffer();
        port.write("mot\r");
        for (const auto& [axis, target] : {std::pair{0, az}, {1, el}}) {
            if (axis == 1)
                port.reset_input_buffer();
            port.write("a " + std::to_string(axis) + " " + py_float(target) + "\r");
            const std::string chunk = port.read(100, 1.0);
            REQUIRE(strict_ascii(chunk));
            std::smatch match;
            REQUIRE(std::regex_search(chunk, match, value));  // the client crashes otherwise
            parsed[static_cast<std::size_t>(axis)] = std::stod(match[1].str());
        }
        port.write("q\r");
        return parsed;
    };
    const auto first = P(200.0, 40.0);
    CHECK(first[0] == Approx(200.0));
    CHECK(first[1] == Approx(40.0));
    const auto second = P(95.5, 60.25);
    CHECK(second[0] == Approx(95.5));
    CHECK(second[1] == Approx(60.25));
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    CHECK(dish.true_position().az == Approx(95.5).margin(0.01));
    CHECK(dish.true_position().el == Approx(60.25).margin(0.015));
}

TEST_CASE("G2 boot: a client's CR right after Boot Complete gets the late lines, then the prompts",
          "[clients][g2][boot]") {
    Options options = g2(false);
    options.already_booted = false;
    options.late_boot_line_delay = 2.0;  // simulated: 0.1 s real
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    const auto give_up = Clock::now() + std::chrono::seconds(30);
    std::string boot;
    while (boot.find("Boot Complete\r\n") == std::string::npos) {
        REQUIRE(Clock::now() < give_up);
        boot += port.readline(1.0);
    }
    port.write("\r");
    std::string rest;
    while (rest.find("TRK>\r\nTRK>") == std::string::npos) {
        REQUIRE(Clock::now() < give_up);
        rest += port.read(1, 1.0);
    }
    // The captured boot: an empty line, then `Loc Startup: ...` and the status lines up to
    // `GPS Not Found`; the CR kept since `Boot Complete` is answered after the boot's TRK>.
    CHECK(rest.starts_with("\r\nLoc Startup: IDU NOT Present\r\napp_dipswitch:101\r\n"));
    CHECK(rest.ends_with("Enabled LNB ODU 18V\r\nGPS Not Found\r\nTRK>\r\nTRK>"));
    CHECK(dish.hazards_received() == 0);
}
