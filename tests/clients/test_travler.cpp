// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Gabe's Trav'ler clients (docs/firmware.md §3.6, §4.5, §5.6, Appendix C) replayed over the real pty:
// the bytes they write, with their pauses or lack of them, and their parse of what comes back.
#include <catch2/catch.hpp>

#include <cstdio>
#include <memory>
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

Options options_for(Variant variant) {
    Options options;
    options.variant = variant;
    options.time_scale = time_scale;
    return options;
}

// What the client's float(text) then str() makes of a two-decimal reply field.
std::string as_reported(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", value);
    return py_float(std::stod(text));
}

// travler_init.py v1.0 (§3.6): readline until a line contains `NoGPS`, then six writes with no
// pause and no read. Returns the stripped lines it printed.
std::vector<std::string> travler_init(ClientPort& port, double give_up_after_seconds = 60.0) {
    std::vector<std::string> lines;
    const auto give_up = Clock::now() + std::chrono::duration_cast<Clock::duration>(Seconds(give_up_after_seconds));
    for (;;) {
        REQUIRE(Clock::now() < give_up);  // the client itself would wait forever (§12.2)
        const std::string line = py_strip(port.readline(1.0));
        lines.push_back(line);
        if (line.find("NoGPS") != std::string::npos)
            break;
    }
    for (const char* command : {"q\r", "\r", "os\r", "kill Search\r", "q\r", "\r"})
        port.write(command);
    return lines;
}

// travler_rotor.py's start-up: three writes, no reads.
void travler_rotor_start(ClientPort& port, const std::string& motor_menu) {
    port.write("q\r");
    port.write("\r");
    port.write(motor_menu + "\r");
}

// travler_rotor.py v2.0 (§3.6, §12.1) after its start-up writes; the HAL 2.05 copy differs in
// the motor menu word (§4.5), travler_pro_rotor.py in the start-up (§5.6).
class TravlerRotor {
public:
    explicit TravlerRotor(ClientPort& port) : port_(port) {}

    // rotctld `p`: `a`, then read(200) with the 1 s timeout; first AZ/EL match wins; the cache
    // survives a failed parse ("AZ or EL not found.").
    std::string p() {
        port_.write("a\r");
        const std::string chunk = port_.read(200, 1.0);
        static const std::regex az_field("AZ =\\s+(\\d+\\.\\d+)");
        static const std::regex el_field("EL =\\s+(\\d+\\.\\d+)");
        std::smatch az;
        std::smatch el;
        parsed_ = std::regex_search(chunk, az, az_field) && std::regex_search(chunk, el, el_field);
        if (parsed_) {
            az_ = std::stod(az[1].str());
            el_ = std::stod(el[1].str());
        }
        return py_float(az_) + "\n" + py_float(el_) + "\n";
    }

    // rotctld `P az el`: the leap-frog nudge from the cached position, elevation block
    // included with its bug (it moves the azimuth target, §12.1), then two writes, no reads,
    // axis order alternating per move.
    std::string P(double target_az, double target_el) {
        const auto nudge = [](double delta) {
            if (delta > 2.0)
                return 1.0;
            if (delta > 1.0)
                return 0.5;
            if (delta < -2.0)
                return -1.0;
            if (delta < -1.0)
                return -0.5;
            return 0.0;
        };
        target_az += nudge(target_az - az_);
        target_az += nudge(target_el - el_);  // sic
        sent_az_ = target_az;
        sent_el_ = target_el;
        const std::string az_command = "a 0 " + py_float(target_az) + "\r";
        const std::string el_command = "a 1 " + py_float(target_el) + "\r";
        port_.write(moves_ % 2 == 0 ? az_command : el_command);
        port_.write(moves_ % 2 == 0 ? el_command : az_command);
        ++moves_;
        return "RPRT 0\n ";
    }

    bool parsed() const { return parsed_; }
    double sent_az() const { return sent_az_; }
    double sent_el() const { return sent_el_; }

private:
    ClientPort& port_;
    double az_ = 0.0, el_ = 0.0;
    double sent_az_ = 0.0, sent_el_ = 0.0;
    int moves_ = 0;
    bool parsed_ = false;
};

// A pass of rotctld commands: every p after the dish has stopped reports what the rotor sent.
void track(Emulator& dish, TravlerRotor& rotor) {
    REQUIRE(wait_for([&] { return !dish.moving(); }, std::chrono::seconds(30)));
    const std::string first = rotor.p();
    REQUIRE(rotor.parsed());
    CHECK(first == as_reported(dish.true_position().az) + "\n" + as_reported(dish.true_position().el) + "\n");
    for (const auto& [az, el] : {std::pair{200.0, 40.0}, {190.5, 50.25}, {30.0, 20.0}, {31.5, 20.5}}) {
        CAPTURE(az, el);
        const std::size_t received = dish.received_commands().size();
        CHECK(rotor.P(az, el) == "RPRT 0\n ");
        REQUIRE(wait_for([&] { return dish.received_commands().size() >= received + 2 && !dish.moving(); },
                         std::chrono::seconds(30)));
        const std::string reply = rotor.p();  // the unread move replies come first in its 200 bytes
        CHECK(rotor.parsed());
        CHECK(reply == as_reported(rotor.sent_az()) + "\n" + as_reported(rotor.sent_el()) + "\n");
        CHECK(dish.true_position().az == Approx(rotor.sent_az()).margin(0.01));
    }
}

}  // namespace

TEST_CASE("travler_init.py started during boot, then travler_rotor.py v2.0 (HAL 0.0.00)", "[clients][hal000][boot]") {
    Options options = options_for(Variant::travler_hal000);
    options.already_booted = false;
    Emulator dish(options);
    {
        ClientPort init(dish.device_path(), time_scale);
        const auto lines = travler_init(init);
        CHECK(lines.back() == "NoGPS");
    }
    // kill Search arrived: the wandering stops.
    REQUIRE(wait_for([&] { return !dish.search_running(); }, std::chrono::seconds(10)));
    ClientPort port(dish.device_path(), time_scale);
    travler_rotor_start(port, "mot");
    TravlerRotor rotor(port);
    track(dish, rotor);
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("travler_init.py loses its commands against a deaf window after NoGPS (boot-input-drop switch)",
          "[clients][hal000][boot]") {
    Options options = options_for(Variant::travler_hal000);
    options.already_booted = false;
    options.boot_input_drop = 20.0;  // simulated seconds: a second of real time at this scale
    Emulator dish(options);
    ClientPort init(dish.device_path(), time_scale);
    travler_init(init);
    const auto quiet = init.read(1, 0.5);  // the dish answers nothing it was told
    CHECK(quiet.empty());
    CHECK(dish.search_running());
}

TEST_CASE("travler_rotor.py (HAL 2.05 copy, `motor` menu) tracks a dish that is up", "[clients][hal205]") {
    Emulator dish(options_for(Variant::travler_hal205));
    ClientPort port(dish.device_path(), time_scale);
    travler_rotor_start(port, "motor");
    TravlerRotor rotor(port);
    track(dish, rotor);
}

TEST_CASE("travler_rotor.py against an `a` reply with one field per line (position-layout switch)",
          "[clients][hal000]") {
    Options options = options_for(Variant::travler_hal000);
    options.travler_position_layout = birdcage::sim::TravlerPositionLayout::line_per_axis;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    travler_rotor_start(port, "mot");
    TravlerRotor rotor(port);
    track(dish, rotor);  // its regexes do not care about the line breaks
}

TEST_CASE("travler_rotor.py finds no position in an integer-only reply (position-decimals=0 switch)",
          "[clients][hal000]") {
    Options options = options_for(Variant::travler_hal000);
    options.position_decimals = 0;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    travler_rotor_start(port, "mot");
    TravlerRotor rotor(port);
    CHECK(rotor.p() == "0.0\n0.0\n");  // "AZ or EL not found." - the cached start value
    CHECK_FALSE(rotor.parsed());
}

TEST_CASE("travler_pro_rotor.py v2.0: paced start-up through the IDU's odu tunnel, then p/P", "[clients][pro]") {
    Emulator dish(options_for(Variant::travler_pro));
    ClientPort port(dish.device_path(), time_scale);
    // §5.6: q, 1 s, CR, 1 s, odu, 1 s, then CR q CR mot with no pauses; the rotor part is
    // travler_rotor.py's (no further start-up writes).
    port.write("q\r");
    port.client_sleep(1.0);
    port.write("\r");
    port.client_sleep(1.0);
    port.write("odu\r");
    port.client_sleep(1.0);
    for (const char* command : {"\r", "q\r", "\r", "mot\r"})
        port.write(command);
    TravlerRotor rotor(port);
    track(dish, rotor);
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("travler_pro_rotor.py first version (odu q CR mot, no pauses) reaches MOT>", "[clients][pro]") {
    Emulator dish(options_for(Variant::travler_pro));
    ClientPort port(dish.device_path(), time_scale);
    for (const char* command : {"odu\r", "q\r", "\r", "mot\r"})
        port.write(command);
    TravlerRotor rotor(port);
    track(dish, rotor);
}

TEST_CASE("travler_pro_rotor.py fails if `q` at the ODU root returns to the IDU (pro-q-returns-to-idu switch)",
          "[clients][pro]") {
    Options options = options_for(Variant::travler_pro);
    options.pro_q_at_odu_root_returns_to_idu = true;
    Emulator dish(options);
    ClientPort port(dish.device_path(), time_scale);
    for (const char* command : {"odu\r", "q\r", "\r", "mot\r"})
        port.write(command);
    TravlerRotor rotor(port);
    // `q` closed the tunnel: `mot` and `a` land on the IDU console, which knows neither.
    CHECK(rotor.p() == "0.0\n0.0\n");
    CHECK_FALSE(rotor.parsed());
}
