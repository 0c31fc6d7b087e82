// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The emulator's default G2 against the only real G2 console text there is
// (sim/transcripts/captured/g2-bench-02.02.48.txt): every VERBATIM block of that file that shows a
// command's reply or the boot log must come out of the emulator byte for byte, with the CR LF
// line endings and the prompts the capture does not show (docs/firmware.md §6.1) around it.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "birdcage_sim/console.hpp"

using namespace birdcage::sim;

namespace {

// The VERBATIM blocks of the captured file by their `####` heading, annotations (`← ...`) and the
// trailing spaces they leave removed.
std::map<std::string, std::vector<std::string>> verbatim_blocks() {
    std::ifstream file(BIRDCAGE_SOURCE_DIR "/sim/transcripts/captured/g2-bench-02.02.48.txt");
    REQUIRE(file);
    std::map<std::string, std::vector<std::string>> blocks;
    std::vector<std::string>* current = nullptr;
    const std::string verbatim_mark = "#### VERBATIM — ";
    for (std::string line; std::getline(file, line);) {
        if (line.starts_with("#### ")) {
            current = line.starts_with(verbatim_mark) ? &blocks[line.substr(verbatim_mark.size())] : nullptr;
            continue;
        }
        if (current == nullptr)
            continue;
        line = std::regex_replace(line, std::regex(" *← .*$"), "");
        line = std::regex_replace(line, std::regex(" +$"), "");
        current->push_back(line);
    }
    for (auto& [heading, lines] : blocks)
        if (!lines.empty() && lines.back().empty())
            lines.pop_back();  // the separator line
    return blocks;
}

const std::vector<std::string>& block(const std::string& heading) {
    static const auto blocks = verbatim_blocks();
    const auto found = blocks.find(heading);
    INFO("captured block " << heading);
    REQUIRE(found != blocks.end());
    return found->second;
}

std::string crlf_lines(const std::vector<std::string>& lines) {
    std::string text;
    for (const std::string& line : lines)
        text += line + "\r\n";
    return text;
}

Options captured_g2() {
    Options options;
    options.variant = Variant::carryout_g2;
    return options;
}

// Everything the console prints for `bytes` until it is idle again.
std::string converse(Console& console, const std::string& bytes) {
    console.feed(bytes);
    std::string output;
    for (int step = 0; step < 2000 && (step < 20 || console.moving()); ++step) {
        console.advance(0.05);
        output += console.take_output();
    }
    return output;
}

}  // namespace

TEST_CASE("captured G2: the boot log, bursts and lines in their order and time", "[captured][g2]") {
    // Bootloader block: `[0.050s] <text>`, the hex lines standing for raw bytes.
    std::string expected;
    std::vector<double> stamps;
    for (const std::string& line : block("Bootloader Phase (<50ms, non-interactive)")) {
        std::smatch match;
        REQUIRE(std::regex_match(line, match, std::regex(R"(\[([0-9.]+)s\] (.*))")));
        stamps.push_back(std::stod(match[1]));
        const std::string text = match[2];
        if (std::regex_match(text, std::regex("([0-9a-f]{2} ?)+"))) {
            std::istringstream hex(text);
            for (std::string byte; hex >> byte;)
                expected.push_back(static_cast<char>(std::stoi(byte, nullptr, 16)));
        } else {
            expected += text + "\r\n";
        }
    }
    expected += crlf_lines(block("Application Phase (~10s to prompt)")) + "TRK>";

    Options options = captured_g2();
    options.already_booted = false;
    Console console(options);
    std::string boot;
    double first_byte_at = -1.0, application_at = -1.0;
    for (int step = 0; step < 1500 && (console.booting() || step < 10); ++step) {
        console.advance(0.01);
        const std::string bytes = console.take_output();
        if (!bytes.empty() && first_byte_at < 0.0)
            first_byte_at = console.time();
        if (bytes.find("Application Starting") != std::string::npos)
            application_at = console.time();
        boot += bytes;
    }
    CHECK(boot == expected);
    CHECK(first_byte_at == Approx(stamps.front()).margin(0.011));
    CHECK(application_at == Approx(stamps.back()).margin(0.011));
    CHECK(console.time() == Approx(10.0).margin(0.2));  // "~10s to prompt"
}

TEST_CASE("captured G2: MOT> a, a 1 46, ?, l and the homing output", "[captured][g2]") {
    Console console(captured_g2());  // at AZ 180, EL 45 as in the capture
    converse(console, "mot\r");
    const auto& position = block("Position Query");
    CHECK(converse(console, "a\r") == crlf_lines({position.begin(), position.end() - 1}) + position.back());
    const auto& move = block("Move Command");
    CHECK(converse(console, "a 1 46\r") == crlf_lines({move.begin(), move.end() - 1}) + move.back());
    CHECK(converse(console, "?\r") == "?\r\n" + crlf_lines(block("MOT Submenu — Full Command Reference")) + "MOT>");
    CHECK(converse(console, "l\r") == crlf_lines(block("Motor List")) + "MOT>");
    CHECK(converse(console, "h *\r") == "h *\r\n" + crlf_lines(block("Homing Sequence")) + "MOT>");
}

TEST_CASE("captured G2: DVB rssi 5 has the captured shape", "[captured][g2]") {
    Console console(captured_g2());
    converse(console, "dvb\r");
    // The numbers are the sky's (the capture's 500 is its unit's floor at 18 V); the rest is text.
    const auto digits = std::regex("avg: [0-9]+  cur: [0-9]+");
    const auto& rssi = block("RSSI Response Format");
    const std::string captured = crlf_lines({rssi.begin(), rssi.end() - 1}) + rssi.back();
    CHECK(std::regex_replace(converse(console, "rssi 5\r"), digits, "avg: N  cur: N") ==
          std::regex_replace(captured, digits, "avg: N  cur: N"));
}

TEST_CASE("captured G2: the other menus' captured replies", "[captured][g2]") {
    struct Case {
        const char* menu;
        const char* heading;
        bool echoed;  // the block begins with the typed command
        const char* command;
    };
    const Case cases[] = {
        {"a3981", "Diagnostics", true, nullptr},
        {"a3981", "Microstepping Configuration", true, nullptr},
        {"a3981", "Fault Reset", true, nullptr},
        {"dipswitch", "Dipswitch (`DIPSWITCH>`)", true, nullptr},
        {"eeprom", "EEPROM Structure", true, nullptr},
        {"latlon", "LATLON (`LATLON>`)", true, nullptr},
        {"peak", "STB Control Test (`stb`)", true, nullptr},
        {"os", "System Identification (`id`)", false, "id"},
        {"nvs", "NVS Values", false, "d"},
    };
    for (const Case& c : cases) {
        INFO(c.heading);
        Console console(captured_g2());
        converse(console, std::string(c.menu) + "\r");
        std::vector<std::string> lines = block(c.heading);
        const std::string command = c.echoed ? lines.front() : c.command;
        if (!c.echoed)
            lines.insert(lines.begin(), command);
        std::string reply = converse(console, command + "\r");
        CHECK(reply == crlf_lines(lines) + reply.substr(reply.rfind("\r\n") + 2));
        CHECK(reply.ends_with(">"));
    }
}
