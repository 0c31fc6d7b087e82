// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe's listing reader: the real G2 MOT listing (testdata/g2-mot-help.txt, a capture)
// gives its 23 commands, descriptions that contain ` - ` included; the emulator's old
// `Enter <cmd> - ...` layout and every layout the dialect generator draws give every command.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "birdcage_sim/console.hpp"
#include "birdcage_sim/dialect.hpp"
#include "birdcage_sim/emulator.hpp"
#include "probe/help_parser.hpp"

namespace sim = birdcage::sim;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::string line;
    for (const char c : text) {
        if (c == '\r' || c == '\n') {
            if (!line.empty())
                lines.push_back(std::exchange(line, {}));
        } else {
            line += c;
        }
    }
    if (!line.empty())
        lines.push_back(line);
    return lines;
}

std::set<std::string> lower_names(const std::vector<probe::HelpEntry>& entries) {
    std::set<std::string> names;
    for (const auto& entry : entries) {
        std::string name = entry.name;
        for (char& c : name)
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        names.insert(name);
    }
    return names;
}

// A console's answer to `?` at its root, without the echo and the prompt.
std::vector<std::string> root_listing(sim::Options options) {
    options.already_booted = true;
    options.idle_line.clear();
    sim::Console console(options);
    console.take_output();
    console.feed("?\r");
    console.advance(1.0);
    auto lines = lines_of(console.take_output());
    if (!lines.empty() && lines.front() == "?")
        lines.erase(lines.begin());  // the echo
    if (!lines.empty() && lines.back().find('>') != std::string::npos && lines.back().size() < 16)
        lines.pop_back();
    return lines;
}

}  // namespace

TEST_CASE("the real G2 MOT listing gives its 23 commands") {
    std::ifstream file(std::string(BIRDCAGE_TOOLS_TESTDATA) + "/g2-mot-help.txt", std::ios::binary);
    REQUIRE(file);
    std::stringstream contents;
    contents << file.rdbuf();
    const std::string text = contents.str();
    const auto entries = probe::parse_help(lines_of(text));
    std::vector<std::string> names;
    for (const auto& entry : entries)
        names.push_back(entry.name);
    CHECK(names == std::vector<std::string>{"a",         "azscan", "azscanwxp", "e",    "ela2s", "elminmaxhome",
                                            "els2a",     "h",      "l",         "life", "ma",    "motorboth",
                                            "motorlife", "mv",     "p",         "pid",  "r",     "sd",
                                            "sp",        "sw",     "v",         "vms",  "w"});
    // The description runs to the end of the line, its own ` - ` and brackets included.
    const auto ela2s = std::find_if(entries.begin(), entries.end(), [](const auto& e) { return e.name == "ela2s"; });
    REQUIRE(ela2s != entries.end());
    CHECK(ela2s->description == "Elevation Law Test - Angle to Steps [angle]");
}

TEST_CASE("listing rows: the old Enter layout and dashes and spaces but no headers or usage lines") {
    CHECK(probe::parse_help_line("Enter <mot> - Motors")->name == "mot");
    CHECK(probe::parse_help_line("Enter <mv> - Max velocity [<motor> <v>]")->description ==
          "Max velocity [<motor> <v>]");
    CHECK(probe::parse_help_line("mot - Motor menu")->name == "mot");
    CHECK(probe::parse_help_line("  d   Display [<idx>]")->description == "Display [<idx>]");
    CHECK_FALSE(probe::parse_help_line("Available commands:"));
    CHECK_FALSE(probe::parse_help_line("help [<command>]"));
    CHECK_FALSE(probe::parse_help_line("Enter <command> - one of these"));
    CHECK_FALSE(probe::parse_help_line(""));
}

TEST_CASE("every generated listing layout gives every command of the same menu") {
    for (const auto variant : {sim::Variant::travler_hal000, sim::Variant::travler_hal205, sim::Variant::travler_pro,
                               sim::Variant::carryout2003, sim::Variant::carryout_g2}) {
        for (std::uint32_t seed = 1; seed <= 24; ++seed) {
            const sim::Dialect dialect = sim::draw_dialect(variant, seed);
            INFO(sim::variant_name(variant) << " seed " << seed << "\n" << dialect.description);
            // The same console in the old documented layout says which commands there are.
            sim::Options described = dialect.options;
            described.help_layout = sim::HelpLayout::described;
            const auto expected = lower_names(probe::parse_help(root_listing(described)));
            REQUIRE(!expected.empty());
            const auto listing = root_listing(dialect.options);
            INFO("listing:\n"
                 << [&] {
                        std::string all;
                        for (const auto& line : listing)
                            all += line + "\n";
                        return all;
                    }());
            const auto got = lower_names(probe::parse_help(listing));
            for (const auto& word : expected) {
                if (word == "?" || word == "q")
                    continue;  // the old layout lists them; a generated one may not
                INFO("missing: " << word);
                CHECK(got.count(word) == 1);
            }
        }
    }
}
