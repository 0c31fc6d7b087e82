// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The hazard rule: which console command words move the dish, release its motors, stream without
// a prompt, change its state, write NVS, reboot it or kill its shell, per variant and menu
// (docs/firmware.md §15). Every program that talks to a console judges its words here: the
// backend's session (through hazard_check), birdcage-probe, and the emulator's hazard counter.
//
// Pure and self-contained: it reads only the VariantId enumeration (no function of variants.cpp),
// so the emulator links this one file and nothing else of the core.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "firmware/variants.hpp"

namespace birdcage {

enum class HazardKind : std::uint8_t {
    none,           // reads, lists, enters a menu: harmless
    moves,          // drives a motor (or may, with defaults nobody documents)
    releases,       // energises or releases the steppers (the dish may drop or lose its position)
    streams,        // prints without a prompt until interrupted (some never stop, some leave the menu)
    changes_state,  // changes a setting, the LNB, the tuner, a register or a task
    writes_nvs,     // writes NVS or EEPROM (persistent)
    reboots,        // restarts the firmware
    kills_shell,    // ends the console until a power cycle
};
std::string_view hazard_kind_name(HazardKind kind);

// What a caller asks the console for beyond reading. Each request lets through exactly one
// well-formed shape of command and nothing else: a move request lets `a 0 180` through but never
// a bare `g`, an `e` or a `life`.
enum HazardRequest : std::uint32_t {
    request_nothing = 0,
    request_move = 1u << 0,         // `a <id> <deg>` (also `+d`/`-d`), `g <az> <el> [<sk>]` in a motor menu
    request_home = 1u << 1,         // `h <id>` with id 0, 1 or `*` in a motor menu
    request_search_stop = 1u << 2,  // `kill Search` in OS, bare `s` in `ngsearch`
    request_lnb_supply = 1u << 3,   // DVB `lnbdc odu` / `lnbdc stb`
    request_nvs_write =
        1u << 4,  // NVS `e <idx> <value>` and `s`, EEPROM `ee <idx> <value>`: only where a user allowed it
};
using HazardRequests = std::uint32_t;

// What the backend's controller asks for: its moves, homes, search stop and LNB switch. NVS writes
// are added only where the user allowed them.
constexpr HazardRequests backend_requests = request_move | request_home | request_search_stop | request_lnb_supply;

struct HazardRuling {
    HazardKind kind = HazardKind::none;
    std::string_view word;    // the rule's command word
    std::string_view reason;  // what the word does, with its docs/firmware.md section
    // The request that makes exactly this command legitimate (its well-formed shape); nothing =
    // no caller may send it (only a user's explicit --force).
    HazardRequest granted_by = request_nothing;
    bool hazard() const { return kind != HazardKind::none; }
};

// The rule's verdict on `command` (a whole console line) sent at `menu` ("root", "mot", "nvs",
// "eeprom", ...; empty = unknown) of `variant` (nullopt = not known yet). Where the menu or the
// variant is unknown, the rules of every menu and variant apply: the strictest reading.
// classify_command() reports the first rule the command falls under, granted or not;
// judge_command() only the first one that `requests` does not grant (kind none when none is left).
HazardRuling classify_command(std::optional<VariantId> variant, std::string_view menu, std::string_view command);
HazardRuling judge_command(std::optional<VariantId> variant, std::string_view menu, std::string_view command,
                           HazardRequests requests);

}  // namespace birdcage
