// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Firmware auto-detection at open: identifies the variant from any evidence the console offers
// (boot and version lines, prompt shapes, `?` listings in any layout), ranks it per candidate, and
// never sends a documented hazard: no moves, no NVS access, and `q` only where a submenu was
// positively recognised (see detect.cpp).
#pragma once

#include <chrono>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "base/log.hpp"
#include "console/transport.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

struct Detection {
    VariantId variant{};
    std::string evidence;        // what identified it, for get_info and the debug log
    // The console looked like the root of `variant`, which this other variant's inner console also
    // looks like (FirmwareProfile::also_shown_inside: a Trav'ler Pro left inside its ODU console):
    // the caller should keep within that variant's limits too.
    std::optional<VariantId> maybe_inside;
};

// The words of a `?` listing, whatever its layout: one command per line or all on one line, with
// or without descriptions, `Enter <cmd> - ...`, any separator, any case. Lower case.
struct HelpListing {
    std::set<std::string> commands;   // words in a command's place
    std::set<std::string> words;      // every word, descriptions included
};
HelpListing parse_help_listing(const std::vector<std::string>& lines);

// Everything the console has shown so far.
struct ConsoleEvidence {
    std::vector<std::string> lines;   // boot lines and any other output
    std::string prompt;               // confirmed prompt, empty if none
    HelpListing help;
};

struct VariantScore {
    VariantId variant{};
    int score = 0;
    std::vector<std::string> reasons;   // e.g. `? lists a3981`, `boot line "Ant ID - 12-IN G2"`
};
// Every variant's score, best first.
std::vector<VariantScore> rank_evidence(const ConsoleEvidence& evidence);

// The winner when it is clear (score >= 4, ahead of the next by >= 3); nullopt when unsure.
std::optional<VariantScore> clear_winner(const std::vector<VariantScore>& ranking);

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout);

}  // namespace birdcage
