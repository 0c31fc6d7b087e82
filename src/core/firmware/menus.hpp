// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The console menus the firmware facts name (docs/firmware.md §3.3, §4.3, §5.1, §6.3, §8.3): the word
// that enters each from the root, the word its prompt shows, and the word that leaves it. A program
// that must know where a console is (birdcage-probe) looks the word of a prompt (prompt.hpp) up in
// this table and enters no word that is not in it.
#pragma once

#include <string>
#include <string_view>

#include "base/span.hpp"

namespace birdcage {

struct MenuFact {
    std::string_view word;  // entered from the root with it: "mot"
    std::string_view
        prompt_word;  // its prompt shows it: "MOT" (the G2's eeprom shows "EE"); empty = no prompt of its own
    std::string_view exit_word;  // leaves it for the root: "q" (§2)
    // The menu is a tunnel into another console (the Pro's `odu`, §5.1): its prompt is that
    // console's root, and where its exit word lands is not documented.
    bool tunnel = false;
};

// Every menu the firmware facts name, on any variant.
Span<const MenuFact> documented_menus();
// The menu entered with `word` (case-insensitive), or nullptr.
const MenuFact* menu_entered_by(std::string_view word);
// The menu whose prompt shows `prompt_word` (case-insensitive), or nullptr.
const MenuFact* menu_with_prompt_word(std::string_view prompt_word);
// A documented root prompt word: `TRK` (the G2's root, §6.3).
bool is_root_prompt_word(std::string_view prompt_word);

}  // namespace birdcage
