// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The hazard rule's table (docs/firmware.md §15 gives each row's reason in prose). Standalone on
// purpose: the emulator links this library alone (sim/README.md), so it calls nothing of the core
// beyond its own library (the word splitter, firmware/words.cpp).
#include "firmware/hazards.hpp"

#include "firmware/words.hpp"

#include <array>
#include <charconv>
#include <cstddef>
#include <vector>

namespace birdcage {
namespace {

// How many arguments make the word a hazard.
enum class Arguments : std::uint8_t {
    any,   // bare or with arguments
    bare,  // only bare (with arguments it reads or is harmless)
    some,  // only with arguments (bare it reads)
    two_or_more,
};

// The well-formed shape a request grants (HazardRequest); none = never granted.
enum class Shape : std::uint8_t {
    none,
    axis_move,
    goto_move,
    home,
    kill_search,
    stop_search,
    lnb_supply,
    indexed_write,
    save
};

// Which variants a row applies to.
enum VariantMask : std::uint8_t {
    hal000 = 1u << 0,
    hal205 = 1u << 1,
    pro = 1u << 2,
    carryout2003 = 1u << 3,
    g2 = 1u << 4,
    every_variant = 0x1f,
};

struct Rule {
    std::string_view word;
    std::string_view menus;  // space-separated session menu names; "*" = every menu
    std::uint8_t variants;
    Arguments arguments;
    HazardKind kind;
    Shape shape;
    std::string_view reason;
};

using K = HazardKind;
using A = Arguments;
using S = Shape;

// The motor menus: G2 and Trav'ler `mot`, HAL 2.05 and the 2003 Carryout `motor`, the Carryout's `target`.
constexpr std::string_view motor_menus = "mot motor target";

constexpr std::array rules{
    // ---- every menu -----------------------------------------------------------------------
    Rule{"reboot", "*", every_variant, A::any, K::reboots, S::none, "restarts the firmware (firmware.md 2, 6.5)"},
    Rule{"stow", "*", every_variant, A::any, K::moves, S::none,
         "folds the dish flat; can destroy a modified feed (firmware.md 3.5)"},
    Rule{"Q", "*", every_variant, A::any, K::kills_shell, S::none,
         "on the predecessor's never-send list (firmware.md 6.5)"},
    Rule{"q", "root", g2, A::bare, K::kills_shell, S::none,
         "q at the G2's root prompt (or where the menu is unknown) may end the shell until a power cycle (firmware.md "
         "6.5)"},
    Rule{"def", "*", every_variant, A::any, K::writes_nvs, S::none,
         "restores defaults without undo (DVB, EEPROM; firmware.md 6.3, 6.5)"},
    Rule{"inv", "*", every_variant, A::any, K::writes_nvs, S::none, "invalidates EEPROM entries (firmware.md 6.5)"},

    // ---- motor menus ----------------------------------------------------------------------
    Rule{"a", motor_menus, every_variant, A::some, K::moves, S::axis_move,
         "moves one motor: `a <id> <deg>` (firmware.md 2, 6.3)"},
    Rule{"g", motor_menus, every_variant, A::any, K::moves, S::goto_move,
         "moves both axes: `g <az> <el>` (firmware.md 2, 8.3)"},
    Rule{"h", motor_menus, every_variant, A::any, K::moves, S::home,
         "homes by stalling the motors: `h <id>` (firmware.md 6.4)"},
    Rule{"e", motor_menus, every_variant, A::any, K::releases, S::none, "energises the steppers (firmware.md 6.3)"},
    Rule{"r", motor_menus, every_variant, A::any, K::releases, S::none,
         "releases the steppers: the dish may drop (firmware.md 6.3)"},
    Rule{"p", motor_menus, every_variant, A::any, K::moves, S::none, "goes to a raw step position (firmware.md 6.3)"},
    Rule{"v", motor_menus, every_variant, A::any, K::moves, S::none, "turns a motor at a velocity (firmware.md 6.3)"},
    Rule{"vms", motor_menus, every_variant, A::any, K::moves, S::none,
         "turns a motor at a velocity for a time (firmware.md 6.3)"},
    Rule{"sd", motor_menus, every_variant, A::any, K::moves, S::none,
         "drives a motor into its stop (stall detection, firmware.md 6.3)"},
    Rule{"life", motor_menus, every_variant, A::any, K::moves, S::none,
         "motor life test: oscillates both axes (firmware.md 6.3)"},
    Rule{"motorlife", motor_menus, every_variant, A::any, K::moves, S::none, "motor life test (firmware.md 6.3)"},
    Rule{"motorboth", motor_menus, every_variant, A::any, K::moves, S::none,
         "motor life test of both axes (firmware.md 6.3)"},
    Rule{"azscan", motor_menus, every_variant, A::any, K::moves, S::none, "sky scan sweep (firmware.md 6.3)"},
    Rule{"azscanwxp", motor_menus, every_variant, A::any, K::moves, S::none,
         "sky scan sweep; hangs on unhomed axes (firmware.md 6.3, 6.5)"},
    Rule{"sp", motor_menus, every_variant, A::any, K::changes_state, S::none,
         "overwrites a position register (firmware.md 6.3)"},
    Rule{"sw", motor_menus, every_variant, A::any, K::changes_state, S::none,
         "sets the wrap reference (firmware.md 6.3)"},
    Rule{"w", motor_menus, every_variant, A::any, K::changes_state, S::none,
         "switches the wrap manager (firmware.md 6.3)"},
    Rule{"pid", motor_menus, every_variant, A::any, K::changes_state, S::none,
         "sets the PID gains; no read form (firmware.md 6.3)"},
    Rule{"ma", motor_menus, every_variant, A::some, K::changes_state, S::none,
         "with arguments sets the acceleration (firmware.md 6.3)"},
    Rule{"mv", motor_menus, every_variant, A::some, K::changes_state, S::none,
         "with arguments sets the velocity (firmware.md 6.3)"},

    // ---- G2 STEP: the raw-step mirror of MOT ----------------------------------------------
    Rule{"e", "step", g2, A::any, K::releases, S::none, "energises the steppers (firmware.md 6.3)"},
    Rule{"r", "step", g2, A::any, K::releases, S::none, "releases the steppers (firmware.md 6.3)"},
    Rule{"p", "step", g2, A::any, K::moves, S::none, "goes to a raw step position (firmware.md 6.3)"},
    Rule{"v", "step", g2, A::any, K::moves, S::none, "turns a motor at a velocity (firmware.md 6.3)"},
    Rule{"ma", "step", g2, A::some, K::changes_state, S::none,
         "with arguments sets the acceleration (firmware.md 6.3)"},
    Rule{"mv", "step", g2, A::some, K::changes_state, S::none, "with arguments sets the velocity (firmware.md 6.3)"},
    Rule{"pid", "step", g2, A::some, K::changes_state, S::none, "with arguments sets the PID gains (firmware.md 6.3)"},

    // ---- NVS and EEPROM -------------------------------------------------------------------
    Rule{"e", "nvs", every_variant, A::two_or_more, K::writes_nvs, S::indexed_write,
         "writes an NVS value (firmware.md 2, 6.3)"},
    Rule{"s", "nvs", every_variant, A::bare, K::writes_nvs, S::save, "saves NVS to flash (firmware.md 2, 6.3)"},
    Rule{"ee", "eeprom", g2, A::two_or_more, K::writes_nvs, S::indexed_write,
         "writes an EEPROM value (firmware.md 6.3)"},

    // ---- G2 DVB ---------------------------------------------------------------------------
    Rule{"ls", "dvb", g2, A::any, K::streams, S::none,
         "streams a lock scan; an interrupt drops to TRK> (firmware.md 6.3)"},
    Rule{"lnbv", "dvb", g2, A::any, K::streams, S::none, "streams the LNB voltage (firmware.md 6.3)"},
    Rule{"snr", "dvb", g2, A::any, K::streams, S::none, "streams the SNR (firmware.md 6.3)"},
    Rule{"agc", "dvb", g2, A::any, K::streams, S::none, "streams the AGC (firmware.md 6.3)"},
    Rule{"qls", "dvb", g2, A::any, K::streams, S::none, "streams the lock status (firmware.md 6.3)"},
    Rule{"nid", "dvb", g2, A::any, K::streams, S::none, "streams the network id (firmware.md 6.3)"},
    Rule{"stats", "dvb", g2, A::any, K::streams, S::none, "streams signal statistics (firmware.md 6.3)"},
    Rule{"lnbdc", "dvb", g2, A::any, K::changes_state, S::lnb_supply, "switches the LNB supply (firmware.md 6.3)"},
    Rule{"t", "dvb", g2, A::any, K::changes_state, S::none, "tunes a transponder (firmware.md 6.3)"},
    Rule{"e", "dvb", g2, A::two_or_more, K::changes_state, S::none, "edits a channel parameter (firmware.md 6.3)"},
    Rule{"send", "dvb", g2, A::any, K::changes_state, S::none, "sends a raw DiSEqC packet (firmware.md 6.3)"},

    // ---- G2 PEAK, ADC, GPIO, A3981 --------------------------------------------------------
    Rule{"ts", "peak", g2, A::any, K::streams, S::none,
         "switch toggle test that cannot be interrupted (firmware.md 6.5)"},
    Rule{"rssits", "peak", g2, A::any, K::streams, S::none,
         "streams RSSI each minute; an interrupt leaves the menu (firmware.md 6.3)"},
    Rule{"pw", "peak", g2, A::any, K::moves, S::none, "peaking sweep around a pointing (firmware.md 6.3)"},
    Rule{"psnr", "peak", g2, A::any, K::moves, S::none, "peaking sweep on the SNR (firmware.md 6.3)"},
    Rule{"pxy1", "peak", g2, A::any, K::moves, S::none, "cross-pattern peak search (firmware.md 6.3)"},
    Rule{"stb", "peak", g2, A::any, K::changes_state, S::none, "toggles the LNB polarity (firmware.md 6.3)"},
    Rule{"scan", "adc", g2, A::bare, K::moves, S::none,
         "bare, drives an unhomed azimuth towards 2147483647 and hangs the console (firmware.md 6.5)"},
    Rule{"scan", "adc", g2, A::some, K::streams, S::none, "an azimuth sweep that streams (firmware.md 6.3)"},
    Rule{"m", "adc", g2, A::any, K::streams, S::none, "streams the raw RSSI until q (firmware.md 6.3)"},
    Rule{"w", "gpio", g2, A::any, K::changes_state, S::none, "writes a GPIO pin (firmware.md 6.3)"},
    Rule{"dir", "gpio", g2, A::any, K::changes_state, S::none, "sets a GPIO pin's direction (firmware.md 6.3)"},
    Rule{"st", "a3981", g2, A::any, K::changes_state, S::none, "sets the stepper drivers' current (firmware.md 6.3)"},
    Rule{"reset", "a3981", g2, A::any, K::changes_state, S::none,
         "clears the stepper drivers' faults (firmware.md 6.3)"},

    // ---- Trav'ler search control ----------------------------------------------------------
    Rule{"kill", "os", hal000 | hal205 | pro, A::any, K::changes_state, S::kill_search,
         "ends a firmware task (firmware.md 3.3)"},
    Rule{"s", "ngsearch", hal205, A::bare, K::changes_state, S::stop_search, "stops the TV search (firmware.md 4.3)"},
};

// The command's words; a word beyond the last reads as empty, so a row can ask for any position.
struct Words {
    std::vector<std::string_view> items;
    std::size_t count() const { return items.size(); }
    std::string_view operator[](std::size_t i) const { return i < items.size() ? items[i] : std::string_view{}; }
};

// A console number: optional sign, digits, optional fraction.
bool is_number(std::string_view text) {
    if (!text.empty() && (text.front() == '+' || text.front() == '-')) {
        text.remove_prefix(1);
    }
    double value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, std::chars_format::fixed);
    return !text.empty() && error == std::errc{} && end == text.data() + text.size() &&
           (text.front() >= '0' && text.front() <= '9');
}

bool is_motor_id(std::string_view text) {
    return text == "0" || text == "1" || text == "2";
}

bool is_index(std::string_view text) {
    if (text.empty()) {
        return false;
    }
    for (char c : text) {
        if (c < '0' || c > '9') {
            return false;
        }
    }
    return true;
}

// Whether the command has the one shape a request grants, and which request that is.
HazardRequest granted_by(Shape shape, const Words& words) {
    const std::size_t args = words.count() - 1;
    switch (shape) {
        case S::none:
            return request_nothing;
        case S::axis_move:
            return args == 2 && is_motor_id(words[1]) && is_number(words[2]) ? request_move : request_nothing;
        case S::goto_move:
            return (args == 2 || args == 3) && is_number(words[1]) && is_number(words[2]) &&
                           (args == 2 || is_number(words[3]))
                       ? request_move
                       : request_nothing;
        case S::home:
            return args == 1 && (words[1] == "0" || words[1] == "1" || words[1] == "*") ? request_home
                                                                                        : request_nothing;
        case S::kill_search:
            return args == 1 && words[1] == "Search" ? request_search_stop : request_nothing;
        case S::stop_search:
            return args == 0 ? request_search_stop : request_nothing;
        case S::lnb_supply:
            return args == 1 && (words[1] == "odu" || words[1] == "stb") ? request_lnb_supply : request_nothing;
        case S::indexed_write:
            return args == 2 && is_index(words[1]) ? request_nvs_write : request_nothing;
        case S::save:
            return args == 0 ? request_nvs_write : request_nothing;
    }
    return request_nothing;
}

bool arguments_match(Arguments rule, std::size_t args) {
    switch (rule) {
        case A::any:
            return true;
        case A::bare:
            return args == 0;
        case A::some:
            return args > 0;
        case A::two_or_more:
            return args >= 2;
    }
    return true;
}

bool menu_matches(std::string_view menus, std::string_view menu) {
    if (menu.empty() || menus == "*") {
        return true;  // unknown menu: every menu's rules apply
    }
    std::size_t start = 0;
    while (start <= menus.size()) {
        const std::size_t end = menus.find(' ', start);
        const std::string_view name =
            menus.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
        if (name == menu) {
            return true;
        }
        if (end == std::string_view::npos) {
            break;
        }
        start = end + 1;
    }
    return false;
}

bool variant_matches(std::uint8_t variants, std::optional<VariantId> variant) {
    if (!variant) {
        return true;  // unknown variant: every variant's rules apply
    }
    std::uint8_t bit = 0;
    switch (*variant) {
        case VariantId::travler_hal000:
            bit = hal000;
            break;
        case VariantId::travler_hal205:
            bit = hal205;
            break;
        case VariantId::travler_pro:
            bit = pro;
            break;
        case VariantId::carryout2003:
            bit = carryout2003;
            break;
        case VariantId::carryout_g2:
            bit = g2;
            break;
    }
    return (variants & bit) != 0;
}

HazardRuling rule_on(std::optional<VariantId> variant, std::string_view menu, std::string_view command,
                     std::optional<HazardRequests> requests) {
    const Words words{split_words(command)};
    if (words.count() == 0) {
        return {};
    }
    for (const Rule& rule : rules) {
        if (rule.word != words[0] || !arguments_match(rule.arguments, words.count() - 1) ||
            !menu_matches(rule.menus, menu) || !variant_matches(rule.variants, variant)) {
            continue;
        }
        const HazardRequest grant = granted_by(rule.shape, words);
        if (requests && grant != request_nothing && (*requests & grant) != 0) {
            continue;  // the caller asked for exactly this
        }
        return HazardRuling{rule.kind, rule.word, rule.reason, grant};
    }
    return {};
}

}  // namespace

std::string_view hazard_kind_name(HazardKind kind) {
    switch (kind) {
        case K::none:
            return "none";
        case K::moves:
            return "moves";
        case K::releases:
            return "releases";
        case K::streams:
            return "streams";
        case K::changes_state:
            return "changes state";
        case K::writes_nvs:
            return "writes NVS";
        case K::reboots:
            return "reboots";
        case K::kills_shell:
            return "kills the shell";
    }
    return "none";
}

HazardRuling classify_command(std::optional<VariantId> variant, std::string_view menu, std::string_view command) {
    return rule_on(variant, menu, command, std::nullopt);
}

HazardRuling judge_command(std::optional<VariantId> variant, std::string_view menu, std::string_view command,
                           HazardRequests requests) {
    return rule_on(variant, menu, command, requests);
}

}  // namespace birdcage
