// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The dialect generator (dialect.hpp) and the renderer of generated `?` listings. Every draw
// comes from one std::mt19937 seeded with the seed, read through the helpers below rather than
// std::*_distribution (whose output the standard leaves to the library), so that a seed means the
// same console everywhere.
#include "birdcage_sim/dialect.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <random>
#include <sstream>

#include "birdcage_sim/console.hpp"
#include "birdcage_sim/motor.hpp"
#include "birdcage_sim/transcript.hpp"
#include "engine.hpp"

namespace birdcage::sim {
namespace {

class Draw {
public:
    explicit Draw(std::uint32_t seed) : engine_(seed ^ 0xd1a1ec75u) {}
    double unit() { return static_cast<double>(engine_()) / 4294967296.0; }  // [0, 1)
    double uniform(double low, double high) { return low + (high - low) * unit(); }
    std::size_t below(std::size_t count) { return static_cast<std::size_t>(engine_() % count); }
    int integer(int low, int high) { return low + static_cast<int>(below(static_cast<std::size_t>(high - low + 1))); }
    bool chance(double probability) { return unit() < probability; }
    template <typename T>
    T pick(std::initializer_list<T> choices) {
        return *(choices.begin() + below(choices.size()));
    }
    // One of `choices` with the given relative weights.
    template <typename T>
    T weighted(std::initializer_list<std::pair<T, double>> choices) {
        double total = 0.0;
        for (const auto& choice : choices)
            total += choice.second;
        double at = unit() * total;
        for (const auto& choice : choices) {
            if (at < choice.second)
                return choice.first;
            at -= choice.second;
        }
        return (choices.end() - 1)->first;
    }

private:
    std::mt19937 engine_;
};

std::string with_case(std::string text, TextCase text_case) {
    for (char& c : text) {
        if (text_case == TextCase::upper)
            c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (text_case == TextCase::lower)
            c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return text;
}

std::string replace_all(std::string text, std::string_view from, std::string_view to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

std::vector<std::string> split_on_spaces(std::string_view text) {
    std::vector<std::string> tokens;
    std::string token;
    for (const char c : text) {
        if (c == ' ') {
            if (!token.empty())
                tokens.push_back(std::exchange(token, {}));
        } else {
            token.push_back(c);
        }
    }
    if (!token.empty())
        tokens.push_back(token);
    return tokens;
}

// `head` then `tail`'s words, continuing on new lines (indented) where a line would pass `width`.
// The head is never broken: the firmware wraps the text after it, as terminals of its era did.
std::vector<std::string> wrapped(std::string head, std::string_view tail, std::size_t width, std::size_t indent,
                                 std::string_view joiner = " ") {
    std::vector<std::string> lines;
    std::string line = std::move(head);
    bool line_has_tail = false;
    for (const std::string& token : split_on_spaces(tail)) {
        if (width > 0 && line_has_tail && line.size() + joiner.size() + token.size() > width) {
            lines.push_back(line);
            line = std::string(indent, ' ') + token;
        } else {
            line += (line_has_tail ? std::string(joiner) : std::string()) + token;
        }
        line_has_tail = true;
    }
    lines.push_back(line);
    return lines;
}

std::string fixed(double value, int decimals = 2) {
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

}  // namespace

std::vector<std::string> render_help(const HelpGrammar& grammar, std::string_view menu_name,
                                     std::vector<HelpEntry> entries) {
    if (grammar.list_quit)
        entries.push_back({"q", "Quit this menu"});  // INVENTED descriptions
    if (grammar.list_help)
        entries.push_back({"?", "This list"});
    if (grammar.sorted)
        std::stable_sort(entries.begin(), entries.end(),
                         [](const HelpEntry& a, const HelpEntry& b) { return a.word < b.word; });
    std::vector<std::string> words;
    std::size_t width = 0;
    for (const HelpEntry& entry : entries) {
        words.push_back(grammar.word_open + with_case(entry.word, grammar.word_case) + grammar.word_close);
        width = std::max(width, words.back().size());
    }
    const std::string menu(menu_name);
    std::vector<std::string> lines;
    for (const std::string& title : grammar.title_lines)
        lines.push_back(replace_all(title, "{menu}", menu));

    switch (grammar.arrangement) {
        case HelpArrangement::rows:
            for (std::size_t i = 0; i < entries.size(); ++i) {
                std::string head =
                    replace_all(grammar.numbering, "#", std::to_string(i + 1)) + grammar.row_prefix + words[i];
                if (!grammar.descriptions) {
                    lines.push_back(head);
                    continue;
                }
                if (grammar.pad_words)
                    head += std::string(width - words[i].size(), ' ');
                head += grammar.separator;
                const std::string description = with_case(entries[i].description, grammar.description_case);
                for (std::string& line : wrapped(head, description, grammar.wrap_width, grammar.continuation_indent))
                    lines.push_back(std::move(line));
            }
            break;
        case HelpArrangement::packed: {
            std::string all;
            for (const std::string& word : words)
                all += (all.empty() ? "" : " ") + word;
            // Words never contain spaces, so the separator joins the same tokens wrapped() splits.
            const std::string label =
                grammar.label.empty() ? std::string() : replace_all(grammar.label, "{menu}", menu) + " ";
            std::vector<std::string> packed =
                wrapped(label, all, grammar.wrap_width, grammar.continuation_indent, grammar.packed_separator);
            for (std::string& line : packed)
                lines.push_back(std::move(line));
            break;
        }
        case HelpArrangement::columns: {
            const std::size_t per_line = std::max<std::size_t>(grammar.columns, 1);
            std::string line;
            for (std::size_t i = 0; i < words.size(); ++i) {
                const bool last_in_line = (i + 1) % per_line == 0 || i + 1 == words.size();
                line += words[i];
                if (!last_in_line)
                    line += std::string(std::max(grammar.column_width, words[i].size() + 1) - words[i].size(), ' ');
                if (last_in_line)
                    lines.push_back(std::exchange(line, {}));
            }
            break;
        }
    }
    for (const std::string& footer : grammar.footer_lines)
        lines.push_back(replace_all(replace_all(footer, "{menu}", menu), "{n}", std::to_string(entries.size())));
    return lines;
}

namespace {

bool is_travler(Variant variant) {
    return variant == Variant::travler_hal000 || variant == Variant::travler_hal205 || variant == Variant::travler_pro;
}

// --- the `?` listing grammar ---------------------------------------------------------------

HelpGrammar draw_help(Draw& draw, std::ostringstream& said) {
    HelpGrammar g;
    g.arrangement = draw.weighted<HelpArrangement>(
        {{HelpArrangement::rows, 5}, {HelpArrangement::packed, 3}, {HelpArrangement::columns, 2}});
    if (draw.chance(0.55)) {
        if (draw.chance(0.2))
            g.title_lines.push_back("");
        std::string title =
            draw.pick<const char*>({"Commands", "Available commands", "Command list", "{menu} commands", "{menu} menu",
                                    "Menu {menu}", "Help", "Valid commands", "Commands for {menu}"});
        title += draw.pick<const char*>({"", ":", " -", "...", " ---"});
        title = with_case(title,
                          draw.weighted<TextCase>({{TextCase::as_is, 6}, {TextCase::upper, 2}, {TextCase::lower, 1}}));
        if (draw.chance(0.3))
            title = draw.pick<const char*>({"*** ", "== ", "-- ", "  "}) + title;
        g.title_lines.push_back(title);
        if (draw.chance(0.3))
            g.title_lines.push_back(std::string(title.size(), draw.pick({'-', '=', '~'})));
        if (draw.chance(0.4))
            g.title_lines.push_back("");
    }
    g.word_case = draw.weighted<TextCase>({{TextCase::as_is, 7}, {TextCase::upper, 3}});
    g.list_quit = draw.chance(0.7);
    g.list_help = draw.chance(0.4);
    g.sorted = draw.chance(0.3);
    g.wrap_width = draw.chance(0.35) ? static_cast<std::size_t>(draw.integer(20, 60)) : 0;
    g.continuation_indent = static_cast<std::size_t>(draw.pick({0, 2, 4, 8, 12, 16}));
    const char* brackets = "";
    switch (g.arrangement) {
        case HelpArrangement::rows:
            g.descriptions = draw.chance(0.7);
            if (draw.chance(0.25))
                g.numbering = draw.pick<const char*>({"#. ", "#) ", "[#] ", "#: ", "# "});
            g.row_prefix = draw.weighted<const char*>(
                {{"", 5}, {"  ", 2}, {"    ", 1}, {"- ", 1}, {"* ", 1}, {"Enter ", 1}, {"\t", 1}});
            // `<word>` only with a description after it: a listing line ending in `>` would be a
            // prompt to any reader, firmware authors included.
            brackets =
                g.descriptions
                    ? draw.weighted<const char*>({{"", 6}, {"<>", 2}, {"[]", 1}, {"()", 1}, {"''", 1}, {"\"\"", 1}})
                    : draw.weighted<const char*>({{"", 6}, {"[]", 1}, {"()", 1}, {"''", 1}});
            g.separator = draw.pick<const char*>({" - ", " : ", ": ", " -- ", "\t", "  ", " = ", " ... ", " "});
            g.pad_words = draw.chance(0.5);
            g.description_case =
                draw.weighted<TextCase>({{TextCase::as_is, 6}, {TextCase::upper, 1}, {TextCase::lower, 2}});
            break;
        case HelpArrangement::packed:
            g.descriptions = false;
            g.label = g.title_lines.empty() || draw.chance(0.3)
                          ? draw.pick<const char*>({"", "Commands:", "Cmds:", "{menu}:", "Available:", "Commands are:",
                                                    "Valid:", "{menu} menu -"})
                          : "";
            g.packed_separator = draw.pick<const char*>({" ", "  ", ", ", " | ", ",", " / "});
            brackets = draw.weighted<const char*>({{"", 6}, {"[]", 1}, {"()", 1}, {"''", 1}});
            break;
        case HelpArrangement::columns:
            g.descriptions = false;
            g.columns = static_cast<std::size_t>(draw.integer(2, 6));
            g.column_width = static_cast<std::size_t>(draw.integer(8, 16));
            brackets = draw.weighted<const char*>({{"", 6}, {"[]", 1}, {"()", 1}});
            break;
    }
    const std::string pair = brackets;
    if (pair.size() == 2) {
        g.word_open = pair.substr(0, 1);
        g.word_close = pair.substr(1, 1);
    }
    if (draw.chance(0.35))
        g.footer_lines.push_back(
            draw.pick<const char*>({"help [<command>]", "Type a command name", "q = quit, ? = help", "{n} commands",
                                    "Enter a command", "End of list"}));
    const char* arrangement = g.arrangement == HelpArrangement::rows     ? "rows"
                              : g.arrangement == HelpArrangement::packed ? "packed"
                                                                         : "columns";
    said << "help.arrangement: " << arrangement << "\n"
         << "help.title_lines: " << g.title_lines.size() << "\n"
         << "help.label: \"" << g.label << "\"\n"
         << "help.numbering: \"" << g.numbering << "\"\n"
         << "help.prefix: " << escape_chunk(g.row_prefix) << "\n"
         << "help.brackets: \"" << g.word_open << g.word_close << "\"\n"
         << "help.upper_case_words: " << (g.word_case == TextCase::upper ? "yes" : "no") << "\n"
         << "help.descriptions: " << (g.descriptions ? "yes" : "no") << "\n"
         << "help.separator: " << escape_chunk(g.separator) << "\n"
         << "help.padded: " << (g.pad_words ? "yes" : "no") << "\n"
         << "help.packed_separator: \"" << g.packed_separator << "\"\n"
         << "help.columns: " << g.columns << " x " << g.column_width << "\n"
         << "help.wrap_width: " << g.wrap_width << " (indent " << g.continuation_indent << ")\n"
         << "help.lists_q_and_?: " << g.list_quit << g.list_help << ", sorted: " << g.sorted << "\n"
         << "help.footer_lines: " << g.footer_lines.size() << "\n";
    return g;
}

// --- the boot log ----------------------------------------------------------------------------

std::string hex4(Draw& draw) {
    char text[8];
    std::snprintf(text, sizeof text, "%04X", static_cast<unsigned>(draw.below(65536)));
    return text;
}

// A banner or self-test line. Words that are evidence elsewhere (variant names, HAL versions,
// the documented markers) are left out: an invented line must not answer the question it poses.
std::string banner_line(Draw& draw) {
    // One draw per statement: the order of draws inside one expression is up to the compiler, and
    // a seed must mean the same console wherever it is built.
    std::vector<std::string> parts;
    auto add = [&parts](std::string part) { parts.push_back(std::move(part)); };
    switch (draw.below(7)) {
        case 0:
            add(draw.pick<const char*>({"Winegard ", "WINEGARD ", "Winegard Company "}));
            add(draw.pick<const char*>({"Satellite Antenna", "Mobile Antenna", "Antenna Controller", "Tracker"}));
            break;
        case 1:
            add("Copyright (c) " + std::to_string(2000 + draw.integer(3, 16)) + " Winegard Co.");
            break;
        case 2: {
            char stamp[48];
            const char* month = draw.pick<const char*>({"Jan", "Mar", "Jun", "Sep", "Nov"});
            const int day = draw.integer(1, 28), year = 2000 + draw.integer(3, 16);
            const int hour = draw.integer(0, 23), minute = draw.integer(0, 59), second = draw.integer(0, 59);
            std::snprintf(stamp, sizeof stamp, "%s %2d %d %02d:%02d:%02d", month, day, year, hour, minute, second);
            add(draw.pick<const char*>({"Build ", "Built ", "Compiled "}));
            add(stamp);
            break;
        }
        case 3:
            add(draw.pick<const char*>({"CPU ", "MCU: ", "Processor "}));
            add(draw.pick<const char*>({"ColdFire", "ARM7", "STM32", "H8S", "MSP430"}));
            add(" @ " + std::to_string(draw.pick({8, 16, 24, 48, 72})) + " MHz");
            break;
        case 4:
            add(draw.pick<const char*>({"RAM ", "SRAM ", "Memory "}));
            add(std::to_string(draw.pick({16, 32, 64, 128})) + "K ");
            add(draw.pick<const char*>({"OK", "ok", "passed"}));
            break;
        case 5: {
            const int major = draw.integer(0, 9), minor = draw.integer(0, 99);
            char version[32];
            std::snprintf(version, sizeof version, "Version %d.%02d", major, minor);
            add(version);
            break;
        }
        default:
            add(draw.pick<const char*>({"*****************************", "-----------------------------", "Starting...",
                                        "Power on reset", "Watchdog reset"}));
            break;
    }
    std::string line;
    for (const std::string& part : parts)
        line += part;
    return line;
}

std::string status_line(Draw& draw) {
    const std::string subsystem =
        draw.pick<const char*>({"Flash", "EEPROM", "Tuner", "LNB", "GPS", "Compass", "Inclinometer", "Watchdog", "RTC",
                                "Motor driver", "Limit switch", "Tracker task"});
    switch (draw.below(5)) {
        case 0:
            return subsystem + " self test" + draw.pick<const char*>({"... OK", ": PASS", " passed", " ok"});
        case 1:
            return "Init " + subsystem + draw.pick<const char*>({"... done", " ok", "... OK"});
        case 2: {
            const bool code = draw.chance(0.5);
            return "Checking " + subsystem +
                   (code ? ": 0x" + hex4(draw) : std::string(draw.pick<const char*>({": OK", "... not found"})));
        }
        case 3:
            return subsystem + draw.pick<const char*>({" ready", " started", " timeout, continuing", ": none"});
        default: {
            const std::string verb = draw.pick<const char*>({"Task ", "Starting task ", "Spawn "});
            return verb + draw.pick<const char*>({"ui", "track", "shell", "tuner", "idle", "monitor"});
        }
    }
}

// The documented boot's length, for the silence budget: the pauses and calibration moves of
// variants.cpp from the worst start pose, at the drawn motor's speed.
double documented_boot_seconds(Variant variant, const Options& o) {
    AxisParams az = profile_for(variant).az, el = profile_for(variant).el;
    if (o.motor.az_velocity)
        az.max_velocity = *o.motor.az_velocity;
    if (o.motor.el_velocity)
        el.max_velocity = *o.motor.el_velocity;
    if (o.motor.accel)
        az.max_accel = el.max_accel = *o.motor.accel;
    az.startup_delay = el.startup_delay = o.motor.startup_delay;
    switch (variant) {
        case Variant::carryout_g2:
            // The captured boot does not home and takes g2_boot_seconds (§6.2), plus a line gap for
            // each of the at most 8 extra lines drawn below.
            if (o.g2_console == G2Console::captured)
                return std::max(o.g2_boot_seconds, 0.1 + 24 * o.boot_line_gap + o.late_boot_line_delay) +
                       8 * o.boot_line_gap;
            return 0.5 + Axis::move_time(el, 65.0) + Axis::move_time(az, 446.66) + Axis::move_time(az, 23.33) +
                   12 * o.boot_line_gap + o.late_boot_line_delay;
        case Variant::carryout2003:
            return 2.0 + Axis::move_time(el, 70.0) + Axis::move_time(az, 360.0);
        default:
            return 2.0 + Axis::move_time(az, 360.0) + Axis::move_time(el, 80.0);
    }
}

std::size_t documented_boot_lines(Variant variant, const Options& o) {
    switch (variant) {
        case Variant::carryout_g2:
            // §6.2, as variants.cpp prints them: the captured boot's 25 lines (no homing), or the
            // reconstruction's 12 with boot homing.
            return o.g2_console == G2Console::captured ? 25 : 12;
        case Variant::carryout2003:
            return 0;  // a blank screen (§8.1)
        case Variant::travler_pro:
            return 0;  // nothing documented; variants.cpp prints none
        default:
            return 1;  // NoGPS / No LNB Voltage (§3.2, §4.2)
    }
}

std::vector<ExtraBootLine> draw_boot(Draw& draw, Variant variant, const Options& o, std::ostringstream& said) {
    const std::size_t documented = documented_boot_lines(variant, o);
    std::vector<ExtraBootLine> extras;
    if (documented > 0) {
        const int banners = draw.integer(0, 3);
        for (int i = 0; i < banners; ++i)
            extras.push_back({0, banner_line(draw), 0.0});
        if (variant == Variant::carryout_g2) {
            const int middle = draw.integer(0, 3);
            for (int i = 0; i < middle; ++i)
                extras.push_back({static_cast<std::size_t>(draw.integer(1, static_cast<int>(documented) - 1)),
                                  status_line(draw), 0.0});
        } else {
            const int self_tests = draw.integer(0, 3);
            for (int i = 0; i < self_tests; ++i)
                extras.push_back({0, status_line(draw), 0.0});
        }
        // After the completion marker: status lines the notes do not show, e.g. one more after
        // the G2's `Loc Startup: IDU NOT Present`.
        const int after = variant == Variant::carryout_g2 ? draw.weighted<int>({{0, 4}, {1, 4}, {2, 2}})
                                                          : draw.weighted<int>({{0, 5}, {1, 3}, {2, 2}});
        for (int i = 0; i < after; ++i)
            extras.push_back({documented, status_line(draw), 0.0});
    }
    std::stable_sort(extras.begin(), extras.end(), [](const ExtraBootLine& a, const ExtraBootLine& b) {
        return a.before_documented < b.before_documented;
    });
    // Silences: pure ones somewhere in the log, and the gaps before the extra lines.
    const int pure = draw.integer(1, 3);
    for (int i = 0; i < pure; ++i)
        extras.push_back({static_cast<std::size_t>(draw.integer(0, static_cast<int>(documented))), "", 0.0});
    // Total boot 1..90 s: the documented part plus a drawn budget spread unevenly over the gaps
    // (cubed weights: mostly short gaps, a few silences of several seconds).
    const double base = documented_boot_seconds(variant, o);
    const double floor = std::max(base, 1.0) + 0.5;
    const double total = floor >= 90.0 ? floor : std::exp(draw.uniform(std::log(floor), std::log(90.0)));
    const double budget = std::max(0.0, total - base);
    std::vector<double> weights;
    double sum = 0.0;
    for (std::size_t i = 0; i < extras.size(); ++i) {
        const double u = draw.unit();
        weights.push_back(u * u * u);
        sum += weights.back();
    }
    for (std::size_t i = 0; i < extras.size(); ++i)
        extras[i].silence_before = sum > 0.0 ? budget * weights[i] / sum : 0.0;
    std::stable_sort(extras.begin(), extras.end(), [](const ExtraBootLine& a, const ExtraBootLine& b) {
        return a.before_documented < b.before_documented;
    });
    said << "boot.drawn_total_s: " << fixed(std::max(total, base), 1) << " (documented part about " << fixed(base, 1)
         << ")\n";
    for (const ExtraBootLine& extra : extras)
        said << "boot.extra: before documented line " << extra.before_documented << " of " << documented << ", after "
             << fixed(extra.silence_before) << " s quiet: \"" << extra.text << "\"\n";
    return extras;
}

// --- the motor -------------------------------------------------------------------------------

void draw_motor(Draw& draw, Variant variant, Options& o, std::ostringstream& said) {
    const VariantProfile& profile = profile_for(variant);
    if (is_travler(variant)) {
        // §3.4: about 6 s for 10 degrees and 13.5 s for 90. A start-up delay, speed and
        // acceleration are drawn until the whole moves land within 20% of both (the brief's
        // tolerance is 25%; the margin keeps every draw clearly inside).
        for (int attempt = 0; attempt < 20000; ++attempt) {
            AxisParams axis = profile.az;
            axis.startup_delay = draw.uniform(0.0, 3.0);
            axis.max_velocity = draw.uniform(6.0, 40.0);
            axis.max_accel = std::exp(draw.uniform(std::log(0.5), std::log(12.0)));
            const double t10 = Axis::move_time(axis, 10.0), t90 = Axis::move_time(axis, 90.0);
            if (std::fabs(t10 / 6.0 - 1.0) <= 0.2 && std::fabs(t90 / 13.5 - 1.0) <= 0.2) {
                o.motor.startup_delay = axis.startup_delay;
                o.motor.az_velocity = o.motor.el_velocity = axis.max_velocity;
                o.motor.accel = axis.max_accel;
                said << "motor.fit: 10 deg in " << fixed(t10) << " s, 90 deg in " << fixed(t90) << " s\n";
                break;
            }
        }
    } else if (variant == Variant::carryout_g2) {
        // Read from its NVS (§6.4): varied a little.
        o.motor.startup_delay = draw.uniform(0.0, 0.3);
        o.motor.az_velocity = profile.az.max_velocity * draw.uniform(0.95, 1.05);
        o.motor.el_velocity = profile.el.max_velocity * draw.uniform(0.95, 1.05);
        o.motor.accel = profile.az.max_accel * draw.uniform(0.9, 1.1);
    } else {
        // §8.5 gives only ~3 one-degree steps per second in scans: INVENTED ranges.
        o.motor.startup_delay = draw.uniform(0.0, 1.0);
        o.motor.az_velocity = o.motor.el_velocity = draw.uniform(6.0, 14.0);
        o.motor.accel = draw.uniform(10.0, 40.0);
    }
    said << "motor.startup_delay_s: " << fixed(o.motor.startup_delay) << "\n"
         << "motor.velocity_deg_s: " << fixed(o.motor.az_velocity.value_or(profile.az.max_velocity)) << " az, "
         << fixed(o.motor.el_velocity.value_or(profile.el.max_velocity)) << " el\n"
         << "motor.accel_deg_s2: " << fixed(o.motor.accel.value_or(profile.az.max_accel)) << "\n";
}

const char* line_ending_name(LineEnding ending) {
    switch (ending) {
        case LineEnding::crlf:
            return "crlf";
        case LineEnding::lf:
            return "lf";
        case LineEnding::lfcr:
            return "lfcr";
        case LineEnding::cr:
            return "cr";
    }
    return "?";
}

}  // namespace

Dialect draw_dialect(Variant variant, std::uint32_t seed) {
    Draw draw(seed);
    Dialect dialect;
    Options& o = dialect.options;
    o.variant = variant;
    o.seed = seed;
    std::ostringstream said;
    said << "variant: " << variant_name(variant) << "\nseed: " << seed << "\n";

    // Line discipline. The G2's echo and CR LF have evidence (§6.1) and stay; elsewhere they are
    // open (§14 HAL0.2, HAL0.6, CO.5).
    if (variant != Variant::carryout_g2) {
        o.echo = draw.chance(0.7);
        o.line_ending = draw.weighted<LineEnding>(
            {{LineEnding::crlf, 4}, {LineEnding::lf, 3}, {LineEnding::lfcr, 2}, {LineEnding::cr, 1}});
        o.prompt_style = draw.chance(0.6) ? PromptStyle::named : PromptStyle::bare;
        if (draw.chance(0.25))
            o.prompt_prefix = draw.pick<const char*>({"dish ", "ant:", "#", "$ ", "~", "dish:"});
    }
    // The G2 prints no space after its prompts (`TRK>nvs`, §6.1).
    if (variant != Variant::carryout_g2)
        o.prompt_space = draw.chance(0.4);
    // The G2 is mostly the captured console, whose error text, decimals and indentation are known
    // (§6.3); one in four draws is the reconstruction, where they stay open.
    const bool captured_g2 = variant == Variant::carryout_g2 && draw.chance(0.75);
    if (variant == Variant::carryout_g2)
        o.g2_console = captured_g2 ? G2Console::captured : G2Console::reconstructed;
    if (!captured_g2) {
        o.unknown_command_reply = draw.pick<const char*>({"Unknown command", "", "?", "Invalid command",
                                                          "Bad command: type ? for help", "ERR", "Command not found"});
        o.position_decimals = draw.weighted<int>({{2, 7}, {1, 1}, {3, 2}});
        o.position_indent = draw.chance(0.2) ? draw.integer(1, 4) : 0;
    }
    if (is_travler(variant) && draw.chance(0.2))
        o.travler_position_layout = TravlerPositionLayout::line_per_axis;
    if (variant == Variant::travler_hal205) {
        o.hal205_boot_marker = draw.chance(0.5) ? BootMarker::no_gps : BootMarker::no_lnb_voltage;
        o.hal205_accepts_mot = draw.chance(0.3);
    }
    if (variant == Variant::carryout_g2)
        said << "g2_console: " << (captured_g2 ? "captured" : "reconstructed") << "\n";
    said << "echo: " << (o.echo ? "yes" : "no") << "\nline_ending: " << line_ending_name(o.line_ending)
         << "\nprompt: " << (o.prompt_style == PromptStyle::named || variant == Variant::carryout_g2 ? "named" : "bare")
         << ", prefix \"" << o.prompt_prefix << "\", space " << (o.prompt_space ? "yes" : "no")
         << "\nunknown_command_reply: \""
         << o.unknown_command_reply.value_or(captured_g2 ? "Invalid command" : "Unknown command")
         << "\"\nposition: " << o.position_decimals << " decimals, indent "
         << o.position_indent.value_or(captured_g2 ? 4 : 0) << ", "
         << (o.travler_position_layout == TravlerPositionLayout::one_line ? "one line" : "line per axis") << "\n";
    if (variant == Variant::travler_hal205)
        said << "hal205: marker " << (o.hal205_boot_marker == BootMarker::no_gps ? "NoGPS" : "No LNB Voltage")
             << ", accepts mot " << (o.hal205_accepts_mot ? "yes" : "no") << "\n";

    // The G2's listing is documented (§6.3); the others are drawn from the grammar.
    if (variant != Variant::carryout_g2) {
        o.help_layout = HelpLayout::generated;
        o.help_grammar = draw_help(draw, said);
    } else {
        said << (captured_g2 ? "help: captured (`Available commands:`, §6.3)\n"
                             : "help: reconstructed (`Enter <cmd> - ...`, §6.3)\n");
    }

    draw_motor(draw, variant, o, said);

    o.boot_line_gap = draw.uniform(0.0, 0.3);
    if (variant == Variant::carryout_g2)
        o.late_boot_line_delay = draw.uniform(0.05, 2.0);
    if (captured_g2) {
        // What the captures leave open on their own console (§6.2, §6.4): the boot's length
        // ("~10 s") and whether moves settle past the target.
        o.g2_boot_seconds = draw.uniform(8.0, 12.0);
        o.g2_overshoot = draw.chance(0.3);
        said << "g2: boot " << fixed(o.g2_boot_seconds, 1) << " s, overshoot " << (o.g2_overshoot ? "yes" : "no")
             << "\n";
    }
    o.pace_at_line_rate = draw.chance(0.5);
    said << "boot.line_gap_s: " << fixed(o.boot_line_gap, 3)
         << "\nboot.late_line_delay_s: " << fixed(o.late_boot_line_delay, 3)
         << "\nline_rate_pacing: " << (o.pace_at_line_rate ? "yes" : "no") << "\n";
    o.boot_extra = draw_boot(draw, variant, o, said);

    // Asynchronous lines once booted (the G2 prints some, §6.2, §6.3): sometimes, never often.
    if (draw.chance(0.35)) {
        o.idle_line = draw.pick<const char*>({"GPS: no fix", "LNB 13V", "LNB 18V", "Tracker idle", "Sleep timer reset",
                                              "Temp 41C", "Signal lost", "Heartbeat"});
        o.idle_line_period = draw.uniform(3.0, 60.0);
    }
    said << "async_line: \"" << o.idle_line << "\" every " << fixed(o.idle_line_period, 1) << " s\n";

    // Prompt decorations on every variant and every menu, the G2 included: its documented prompt
    // text stays, a tag before it or marks after its '>' are what another build may add. Drawn
    // last, so every earlier draw of a seed stays what it was.
    if (o.prompt_prefix.empty() && draw.chance(0.25))
        o.prompt_prefix = draw.pick<const char*>({"WG ", "[WG]", "dish:", "ant ", "#", "(wg) "});
    if (draw.chance(0.2))
        o.prompt_suffix = draw.pick<const char*>({">", "$", ":", "#"});
    said << "prompt_decoration: before \"" << o.prompt_prefix << "\", after \"" << o.prompt_suffix << "\"\n";
    // What a Trav'ler's power-up calibration moves is not documented (§3.2, §5.2, §14 HAL0.9): each
    // reading of the switch, after the decorations for the same reason.
    if (is_travler(variant)) {
        o.travler_boot_moves =
            draw.pick({TravlerBootMoves::park, TravlerBootMoves::home_return, TravlerBootMoves::none});
        said << "travler_boot_moves: " << travler_boot_moves_name(o.travler_boot_moves) << "\n";
    }
    // Whether a bare root's submenus name themselves is as open as the root's own prompt (§14
    // HAL0.1, CO.2): drawn last, for the same reason.
    if (o.prompt_style == PromptStyle::bare && draw.chance(0.4)) {
        o.prompt_style = PromptStyle::bare_root;
        said << "prompt_submenus: named (`MOT>` behind a bare root)\n";
    }
    dialect.description = said.str();
    return dialect;
}

std::string describe_console(const Dialect& dialect) {
    std::ostringstream out;
    out << dialect.description;
    Options booting = dialect.options;
    booting.already_booted = false;
    Console console(booting);
    out << "--- boot log (simulated seconds, from power-on at az " << booting.start_az << " el " << booting.start_el
        << ")\n";
    std::string pending;
    for (int step = 0; step < 20000 && (console.booting() || step < 10); ++step) {
        console.advance(0.05);
        const std::string bytes = console.take_output();
        if (!bytes.empty())
            out << fixed(console.time()) << "  " << escape_chunk(bytes) << "\n";
    }
    out << "boot over at " << fixed(console.time()) << " s\n";
    Options up = dialect.options;
    up.already_booted = true;
    Console ready(up);
    ready.feed("?\r");
    ready.advance(1.0);
    out << "--- `?` at the root\n" << escape_chunk(ready.take_output()) << "\n";
    return out.str();
}

}  // namespace birdcage::sim
