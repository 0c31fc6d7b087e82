// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "firmware/menus.hpp"

#include <array>
#include <cctype>

namespace birdcage {
namespace {

// docs/firmware.md: §6.3 (the G2's twelve root submenus and their prompts), §3.3 and §5.3 (`mot`,
// `nvs`, `os` on the Trav'lers), §4.3 (`motor`, `ngsearch`), §5.1 (`odu`), §8.3 (`target`, `motor`,
// `dvb`, `os`, `nvs`). Prompt words outside §6.3 are not documented; a console that shows its menu's
// name in its prompt (as the G2 does) is recognised by it.
constexpr std::array<MenuFact, 16> menus{{
    {"a3981", "A3981", "q"},
    {"adc", "ADC", "q"},
    {"dipswitch", "DIPSWITCH", "q"},
    {"dvb", "DVB", "q"},
    {"eeprom", "EE", "q"},
    {"gpio", "GPIO", "q"},
    {"latlon", "LATLON", "q"},
    {"mot", "MOT", "q"},
    {"motor", "MOTOR", "q"},
    {"ngsearch", "NGSEARCH", "q"},
    {"nvs", "NVS", "q"},
    {"odu", "", "q", true},
    {"os", "OS", "q"},
    {"peak", "PEAK", "q"},
    {"step", "STEP", "q"},
    {"target", "TARGET", "q"},
}};

bool same_word(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) {
            return false;
        }
    }
    return true;
}

}  // namespace

Span<const MenuFact> documented_menus() {
    return menus;
}

const MenuFact* menu_entered_by(std::string_view word) {
    for (const MenuFact& menu : menus) {
        if (same_word(menu.word, word)) {
            return &menu;
        }
    }
    return nullptr;
}

const MenuFact* menu_with_prompt_word(std::string_view prompt_word) {
    if (prompt_word.empty()) {
        return nullptr;
    }
    for (const MenuFact& menu : menus) {
        if (!menu.prompt_word.empty() && same_word(menu.prompt_word, prompt_word)) {
            return &menu;
        }
    }
    return nullptr;
}

bool is_root_prompt_word(std::string_view prompt_word) {
    return same_word(prompt_word, "TRK");
}

}  // namespace birdcage
