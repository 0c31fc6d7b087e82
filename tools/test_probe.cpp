// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe against the emulated G2: the report lists every submenu docs/firmware.md 6.3 lists,
// with its prompt, and the dish sees no hazard. `record` tees a piped session into a transcript.
// --deep finds the commands the emulator accepts but leaves out of `?`, sends no hazard and does
// not move the dish.
#include <catch2/catch.hpp>

#include <array>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <fstream>
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
    CHECK_THAT(report, Catch::Contains("\"error_string\": \"Invalid command\""));  // the captured G2's
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
    // The captured root lists its 12 submenus only: no `reboot` or `stow` there.
    const std::string root_help = report.substr(report.find("\"root_help\""), report.find("\"menus\"") - report.find("\"root_help\""));
    CHECK_THAT(root_help, !Catch::Contains("\"name\": \"reboot\""));
    CHECK_THAT(root_help, !Catch::Contains("\"name\": \"stow\""));
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

namespace {

// The "deep" object's entry for one menu, up to the next menu.
std::string deep_menu(const std::string& report, const std::string& menu)
{
    const std::size_t deep = report.find("\"deep\": {");
    REQUIRE(deep != std::string::npos);
    const std::size_t start = report.find("{\"menu\": \"" + menu + "\"", deep);
    REQUIRE(start != std::string::npos);
    const std::size_t end = report.find("{\"menu\": ", start + 1);
    return report.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

}  // namespace

TEST_CASE("birdcage-probe --deep finds the commands a G2 accepts but does not list, and never moves it")
{
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;  // hiding `l` and `dis` from `?` is the reconstruction's switch
    options.unlisted_commands = true;
    sim::Emulator dish(options);
    const sim::Pose before = dish.true_position();
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() +
                                   " --variant g2 --deep --submenu mot --submenu dvb --submenu nvs 2>/dev/null");

    // `?` does not list them ...
    CHECK_THAT(report, !Catch::Contains("{\"name\": \"l\""));
    CHECK_THAT(report, !Catch::Contains("{\"name\": \"dis\""));
    // ... deep discovery finds them, each in its own menu, with its reply.
    const std::string mot = deep_menu(report, "mot");
    CHECK_THAT(mot, Catch::Contains("\"prompt\": \"MOT>\", \"unknown_reply\": [\"Unknown command\"]"));
    CHECK_THAT(mot, Catch::Contains("{\"word\": \"l\", \"reply\": [\"0 AZIMUTH\", \"1 ELEVATION\"]}"));
    CHECK_THAT(mot, !Catch::Contains("\"word\": \"dis\""));
    const std::string dvb = deep_menu(report, "dvb");
    CHECK_THAT(dvb, Catch::Contains("{\"word\": \"dis\", \"reply\": [\"Freq:"));
    CHECK_THAT(dvb, !Catch::Contains("\"word\": \"l\""));
    // NVS> reads the next index for any unknown word: there is nothing to compare with.
    CHECK_THAT(deep_menu(report, "nvs"), Catch::Contains("answers two unknown words differently"));
    // The motion words of the built-in list are reported, not sent.
    CHECK_THAT(report, Catch::Contains("{\"word\": \"g\", \"reason\": \"starts or may start motion"));
    CHECK_THAT(report, Catch::Contains("{\"word\": \"agc\", \"reason\": \"streams"));
    CHECK_THAT(report, Catch::Contains("\"stopped\": null"));
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    for (const auto& line : dish.received_commands()) {
        INFO(line);
        const std::string verb = line.substr(0, line.find(' '));
        CHECK(verb != "g");
        CHECK(verb != "h");
        CHECK(verb != "agc");
    }
    const sim::Pose after = dish.true_position();
    CHECK(std::fabs(after.az - before.az) < 1e-9);
    CHECK(std::fabs(after.el - before.el) < 1e-9);
    CHECK(!dish.moving());
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}

TEST_CASE("birdcage-probe --deep accepts nothing unlisted where the emulator hides nothing")
{
    // The reconstructed console with unlisted_commands off: `l` is an unknown command. (On the
    // captured console the probe's help parser still cuts `ela2s`/`els2a` at their descriptions'
    // ` - ` and then finds them by deep discovery: the parser's fix is a change of its own.)
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;
    sim::Emulator dish(options);
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() +
                                   " --variant g2 --deep --submenu mot 2>/dev/null");
    const std::string mot = deep_menu(report, "mot");
    CHECK_THAT(mot, Catch::Contains("\"accepted\": []"));
    CHECK_THAT(mot, !Catch::Contains("\"tried\": 0,"));
    CHECK(dish.hazards_received() == 0);
}

TEST_CASE("birdcage-probe --deep never sends a hazard or an argument, whatever the word list says")
{
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.time_scale = 20.0;
    options.g2_console = sim::G2Console::reconstructed;  // `stow`/`reboot` at the root, `l` unlisted
    options.unlisted_commands = true;
    sim::Emulator dish(options);
    const auto path = std::filesystem::temp_directory_path() / ("birdcage-words-" + std::to_string(::getpid()) + ".txt");
    {
        std::ofstream words(path);
        words << "# hazards and arguments first\nstow\nreboot\ndef\ninv\nscan\nq\nQ\ng 10 20\na 0 90\nl\n";
    }
    // Without --variant the guard judges with the G2's rules; the root walk itself sends no hazard.
    const std::string report = run(std::string(BIRDCAGE_PROBE_PATH) + " --port " + dish.device_path() +
                                   " --baud 115200 --deep --wordlist " + path.string() +
                                   " --submenu root --submenu mot --submenu eeprom 2>/dev/null");
    std::filesystem::remove(path);

    for (const char* refused : {"stow", "reboot", "def", "inv", "scan", "Q"}) {
        INFO(refused);
        CHECK_THAT(report, Catch::Contains(std::string("{\"command\": \"") + refused + "\", \"reason\": \"refused"));
    }
    CHECK_THAT(report, Catch::Contains("{\"word\": \"g 10 20\", \"reason\": \"more than one word"));
    CHECK_THAT(report, Catch::Contains("{\"word\": \"a 0 90\", \"reason\": \"more than one word"));
    CHECK_THAT(deep_menu(report, "mot"), Catch::Contains("{\"word\": \"l\""));
    for (const auto& line : dish.received_commands()) {
        INFO(line);
        CHECK(line.find(' ') == std::string::npos);  // no arguments
    }
    CHECK_THAT(report, Catch::Contains("\"final_prompt\": \"TRK>\""));
    CHECK(dish.hazards_received() == 0);
    CHECK(dish.shell_alive());
}
