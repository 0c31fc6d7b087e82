// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The dialect generator: a seed is a console, byte for byte; every drawn console still speaks the
// documented commands in the documented formats; and the drawn consoles really differ.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <regex>
#include <set>
#include <string>

#include "birdcage_sim/console.hpp"
#include "birdcage_sim/dialect.hpp"

using namespace birdcage::sim;

namespace {

const Variant kVariants[] = {Variant::travler_hal000, Variant::travler_hal205, Variant::travler_pro,
                             Variant::carryout2003, Variant::carryout_g2};

// Advance in small steps until the console has booted, collecting its output.
std::string boot(Console& console, double limit = 400.0) {
    std::string output;
    while (console.booting() && console.time() < limit) {
        console.advance(0.05);
        output += console.take_output();
    }
    console.advance(1.0);  // what line-rate pacing still holds back
    return output + console.take_output();
}

std::string settle(Console& console, double max_seconds = 120.0) {
    std::string output;
    for (double t = 0.0; t < max_seconds && (console.moving() || t < 0.5); t += 0.05) {
        console.advance(0.05);
        output += console.take_output();
    }
    return output;
}

std::string send(Console& console, std::string_view line) {
    console.feed(line);
    console.feed("\r");
    return settle(console);
}

std::string lower(std::string text) {
    for (char& c : text)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

// The command word appears as a token of its own (any non-alphanumeric neighbours).
bool lists_word(const std::string& listing, const std::string& word) {
    return std::regex_search(lower(listing), std::regex("(^|[^a-z0-9])" + word + "($|[^a-z0-9])"));
}

std::vector<std::string> root_words(Variant variant) {
    switch (variant) {
        case Variant::travler_hal000:
            return {"mot", "nvs", "os", "stow", "reboot"};
        case Variant::travler_hal205:
            return {"motor", "ngsearch", "nvs", "os", "stow", "reboot"};
        case Variant::travler_pro:
            return {"odu"};
        case Variant::carryout2003:
            return {"target", "motor", "dvb", "os", "nvs"};
        case Variant::carryout_g2:
            return {"a3981", "adc", "dvb", "mot", "nvs", "os"};  // and reconstructed: reboot, stow
    }
    return {};
}

// The console after `power-on -> boot -> ? -> motor menu -> a -> move -> a`, every byte.
std::string scripted_session(const Options& options) {
    Console console(options);
    std::string bytes = boot(console);
    bytes += send(console, "?");
    if (options.variant == Variant::travler_pro)
        bytes += send(console, "odu");
    const char* motor = options.variant == Variant::travler_hal205 ? "motor"
                        : options.variant == Variant::carryout2003 ? "target"
                                                                   : "mot";
    bytes += send(console, motor);
    bytes += send(console, "?");
    if (options.variant == Variant::carryout2003) {
        bytes += send(console, "g 150 40");
    } else {
        bytes += send(console, "a");
        bytes += send(console, "a 0 150");
        bytes += send(console, "a 1 40");
        bytes += send(console, "a");
    }
    bytes += send(console, "nonsense");
    console.advance(70.0);
    return bytes + console.take_output();
}

Options booting(Dialect dialect) {
    dialect.options.already_booted = false;
    return dialect.options;
}

}  // namespace

TEST_CASE("dialect: a seed is a console, byte for byte", "[dialect]") {
    for (const Variant variant : kVariants) {
        for (const std::uint32_t seed : {1u, 7u, 4242u}) {
            const Dialect first = draw_dialect(variant, seed), again = draw_dialect(variant, seed);
            INFO(variant_name(variant) << " seed " << seed);
            CHECK(first.description == again.description);
            CHECK(describe_console(first) == describe_console(again));
            const std::string session = scripted_session(booting(first));
            CHECK(session == scripted_session(booting(again)));
            CHECK(session.size() > 100);
        }
        // Another seed, another console (descriptions name the seed, so compare the bytes).
        CHECK(scripted_session(booting(draw_dialect(variant, 1))) !=
              scripted_session(booting(draw_dialect(variant, 2))));
    }
}

TEST_CASE("dialect: every drawn console keeps the documented words, markers and formats", "[dialect]") {
    const std::regex travler_position(R"(AZ = *[0-9.]+\s+EL = *[0-9.]+)");
    const std::regex g2_position(R"(Angle\[0\] = [0-9.-]+\s+Angle\[1\] = [0-9.-]+)");
    const std::regex carryout_live(R"(az = *[0-9]+ +el = *[0-9]+)");
    for (const Variant variant : kVariants) {
        for (std::uint32_t seed = 1; seed <= 40; ++seed) {
            const Dialect dialect = draw_dialect(variant, seed);
            INFO(describe_console(dialect));
            Console console(booting(dialect));
            const std::string boot_log = boot(console);
            REQUIRE_FALSE(console.booting());
            // Total boot 1..90 simulated seconds.
            CHECK(console.time() >= 1.0);
            CHECK(console.time() <= 90.0);
            switch (variant) {
                case Variant::carryout_g2: {
                    const auto complete = boot_log.find("Boot Complete"),
                               loc = boot_log.find("Loc Startup: IDU NOT Present");
                    CHECK(complete != std::string::npos);
                    CHECK(loc != std::string::npos);
                    CHECK(complete < loc);
                    if (dialect.options.g2_console == G2Console::captured) {
                        CHECK(boot_log.find(std::string("\x01\x00", 2) + "Bootloader version: 1.01\r\n") !=
                              std::string::npos);
                        CHECK(boot_log.find("\r\nGPS Not Found\r\n") > loc);
                    } else {
                        CHECK(boot_log.find("Bootloader v1.01") != std::string::npos);
                    }
                    break;
                }
                case Variant::travler_hal205:
                    CHECK((boot_log.find("NoGPS") != std::string::npos ||
                           boot_log.find("No LNB Voltage") != std::string::npos));
                    break;
                case Variant::carryout2003:
                    CHECK(boot_log.find_first_not_of(" \r\n") == std::string::npos);
                    break;
                case Variant::travler_hal000:
                    CHECK(boot_log.find("NoGPS") != std::string::npos);
                    break;
                case Variant::travler_pro:
                    CHECK(boot_log.find_first_not_of(" \r\n") == std::string::npos);
                    break;
            }
            // The commands on a console that is up with its search stopped (the backend's job).
            Console up(dialect.options);
            up.advance(0.1);
            up.take_output();
            const std::string listing = send(up, "?");
            for (const std::string& word : root_words(variant)) {
                INFO("listing: " << listing << " word " << word);
                CHECK(lists_word(listing, word));
            }
            // The prompt ends the output: its '>', then the marks drawn after it (sim/README.md, "Dialects").
            CHECK(listing.substr(0, listing.find_last_not_of(' ') + 1).ends_with(">" + dialect.options.prompt_suffix));
            if (variant == Variant::travler_pro)
                send(up, "odu");
            if (variant == Variant::carryout2003) {
                send(up, "target");
                const std::string live = send(up, "g 150 40");
                CHECK(std::regex_search(live, carryout_live));
                CHECK(up.position().az == Approx(150.0).margin(0.1));
                CHECK(up.position().el == Approx(40.0).margin(0.1));
                continue;
            }
            send(up, variant == Variant::travler_hal205 ? "motor" : "mot");
            send(up, "a 0 150");
            send(up, "a 1 40");
            const std::string position = send(up, "a");
            INFO("a: " << position);
            CHECK(std::regex_search(position, variant == Variant::carryout_g2 ? g2_position : travler_position));
            CHECK(up.position().az == Approx(150.0).margin(0.1));
            CHECK(up.position().el == Approx(40.0).margin(0.1));
            CHECK(up.hazards() == 0);
        }
    }
}

TEST_CASE("dialect: the Trav'ler motors still meet the documented whole-move timings", "[dialect]") {
    // docs/firmware.md §3.4: about 6 s for 10 degrees and 13.5 s for 90, here within 25%.
    for (const Variant variant : {Variant::travler_hal000, Variant::travler_hal205, Variant::travler_pro}) {
        double longest_delay = 0.0;
        for (std::uint32_t seed = 1; seed <= 30; ++seed) {
            Options options = draw_dialect(variant, seed).options;
            options.start_az = 100.0;
            Console console(options);
            if (variant == Variant::travler_pro)
                send(console, "odu");
            send(console, variant == Variant::travler_hal205 ? "motor" : "mot");
            for (const double distance : {10.0, 90.0}) {
                const double start_az = console.position().az;
                console.feed("a 0 " + std::to_string(start_az + distance) + "\r");
                const double t0 = console.time();
                double last_motion = t0;
                for (double t = 0.0; t < 40.0; t += 0.01) {
                    console.advance(0.01);
                    if (console.moving())
                        last_motion = console.time();
                }
                const double took = last_motion - t0;
                const double documented = distance == 10.0 ? 6.0 : 13.5;
                INFO(variant_name(variant) << " seed " << seed << ": " << distance << " deg took " << took << " s");
                CHECK(std::fabs(took / documented - 1.0) <= 0.25);
                console.take_output();
            }
            longest_delay = std::max(longest_delay, options.motor.startup_delay);
        }
        CHECK(longest_delay > 1.5);  // start-up delays really are drawn
    }
}

TEST_CASE("dialect: the drawn consoles really differ", "[dialect]") {
    for (const Variant variant : {Variant::travler_hal000, Variant::travler_hal205, Variant::carryout2003}) {
        std::set<std::string> shapes, line_endings;
        std::set<std::size_t> listing_lines, extra_boot_lines;
        double shortest_boot = 1e9, longest_boot = 0.0;
        unsigned without_echo = 0, with_async = 0;
        for (std::uint32_t seed = 100; seed < 200; ++seed) {
            const Dialect dialect = draw_dialect(variant, seed);
            Options up = dialect.options;
            Console console(up);
            console.advance(0.1);
            console.take_output();
            std::string listing = send(console, "?");
            // The shape: letters and digits erased, punctuation, spacing and line breaks kept.
            std::string shape = std::regex_replace(listing, std::regex("[A-Za-z0-9]+"), "w");
            shapes.insert(shape);
            listing_lines.insert(static_cast<std::size_t>(std::count(listing.begin(), listing.end(), '\n')) +
                                 static_cast<std::size_t>(std::count(listing.begin(), listing.end(), '\r')));
            line_endings.insert(std::to_string(static_cast<int>(up.line_ending)));
            extra_boot_lines.insert(std::count_if(up.boot_extra.begin(), up.boot_extra.end(),
                                                  [](const ExtraBootLine& e) { return !e.text.empty(); }));
            without_echo += up.echo ? 0 : 1;
            with_async += up.idle_line.empty() ? 0 : 1;
            Console powered(booting(dialect));
            boot(powered);
            shortest_boot = std::min(shortest_boot, powered.time());
            longest_boot = std::max(longest_boot, powered.time());
        }
        INFO(variant_name(variant));
        CHECK(shapes.size() >= 60);
        CHECK(listing_lines.size() >= 8);
        CHECK(line_endings.size() == 4);
        if (variant != Variant::carryout2003)
            CHECK(extra_boot_lines.size() >= 5);
        CHECK(without_echo >= 10);
        CHECK(with_async >= 15);
        CHECK(longest_boot >= 60.0);
        CHECK(shortest_boot <= 25.0);
    }
}

TEST_CASE("dialect: one G2 in three or more has a line after its last documented boot line", "[dialect]") {
    unsigned with_late_line = 0, captured = 0;
    std::set<std::string> boot_logs;
    for (std::uint32_t seed = 1; seed <= 60; ++seed) {
        const Dialect dialect = draw_dialect(Variant::carryout_g2, seed);
        Console console(booting(dialect));
        const std::string log = boot(console);
        boot_logs.insert(std::regex_replace(log, std::regex("[0-9]"), "d"));
        // The captured boot ends with `GPS Not Found` (§6.2), the reconstruction with `Loc Startup: ...`.
        const bool is_captured = dialect.options.g2_console == G2Console::captured;
        captured += is_captured ? 1 : 0;
        const std::string last = is_captured ? "GPS Not Found\r\n" : "Loc Startup: IDU NOT Present\r\n";
        const auto found = log.rfind(last);
        REQUIRE(found != std::string::npos);
        const std::string after = log.substr(found + last.size());
        with_late_line += after.find_first_not_of("TRK>\r\n ") != std::string::npos ? 1 : 0;
    }
    CHECK(with_late_line >= 20);
    CHECK(boot_logs.size() >= 50);
    CHECK(captured >= 35);  // three in four draws are the captured console
    CHECK(captured <= 55);
}
