// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe against the emulated G2: the report lists every submenu docs/firmware.md 6.3 lists,
// with its prompt, and the dish sees no hazard. `record` tees a piped session into a transcript.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"

namespace sim = birdcage::sim;

namespace {

std::string run(const std::string& command)
{
    std::string output;
    FILE* pipe = ::popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::array<char, 4096> buffer{};
    while (const std::size_t count = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), count);
    CHECK(::pclose(pipe) == 0);
    return output;
}

sim::Emulator make_g2()
{
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    return sim::Emulator(options);
}

}  // namespace

TEST_CASE("birdcage-probe maps every G2 submenu with its prompt and sends no hazard")
{
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    sim::Emulator dish(options);
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --variant g2");

    CHECK_THAT(report, Catch::Contains("\"baud\": 115200"));
    CHECK_THAT(report, Catch::Contains("\"root_prompt\": \"TRK>\""));
    CHECK_THAT(report, Catch::Contains("\"error_string\": \"Unknown command\""));
    const std::array<std::pair<const char*, const char*>, 12> submenus{{
        {"a3981", "A3981>"}, {"adc", "ADC>"}, {"dipswitch", "DIPSWITCH>"}, {"dvb", "DVB>"},
        {"eeprom", "EE>"}, {"gpio", "GPIO>"}, {"latlon", "LATLON>"}, {"mot", "MOT>"},
        {"nvs", "NVS>"}, {"os", "OS>"}, {"peak", "PEAK>"}, {"step", "STEP>"},
    }};
    for (const auto& [name, prompt] : submenus) {
        INFO(name);
        CHECK_THAT(report, Catch::Contains(std::string("{\"name\": \"") + name + "\", \"prompt\": \"" + prompt + "\""));
    }
    // The help trap: `help [<command>]` is usage, not a command and not a prompt.
    CHECK_THAT(report, !Catch::Contains("\"name\": \"help\""));
    CHECK_THAT(report, Catch::Contains("{\"command\": \"reboot\""));  // refused, not sent
    CHECK_THAT(report, Catch::Contains("{\"command\": \"stow\""));
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

TEST_CASE("birdcage-probe record tees a piped session into a transcript and refuses root q")
{
    sim::Emulator dish = make_g2();
    const auto path = std::filesystem::temp_directory_path() / ("birdcage-record-" + std::to_string(::getpid()) + ".log");
    run("printf 'mot\\na\\nq\\nq\\n' | " + std::string(BIRDCAGE_PROBE_PATH) + " record --variant g2 --port " +
        dish.device_path() + " --output " + path.string() + " 2>/dev/null");

    const auto transcript = sim::load_transcript(path.string());
    std::filesystem::remove(path);
    CHECK(transcript.header("Variant") == "g2");
    CHECK(transcript.header("Serial") == "115200 8N1");
    std::string host, dish_bytes;
    for (const auto& entry : transcript.entries)
        (entry.direction == sim::Direction::host_to_dish ? host : dish_bytes) += entry.bytes;
    CHECK(host == "mot\ra\rq\r");  // the second q would have been at TRK>
    CHECK_THAT(dish_bytes, Catch::Contains("Angle[0] = 180.00"));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

TEST_CASE("birdcage-probe without --variant waits for a booting G2 through the console synchroniser")
{
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 10.0;
    options.already_booted = false;
    sim::Emulator dish(options);
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() + " --baud 115200");

    // The root prompt is the one confirmed after the boot, not a stale line read mid-boot.
    CHECK_THAT(report, Catch::Contains("\"root_prompt\": \"TRK>\""));
    CHECK_THAT(report, Catch::Contains("{\"name\": \"mot\", \"prompt\": \"MOT>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}
