// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What the console showed, read for auto-detection (console/detect.hpp): the words of a `?` listing
// in any layout, each variant's score from the clue table (firmware/variants.hpp), and the G2 clues
// that decide whether detection may send `q`. Pure: nothing here talks to the dish.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/clues.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

// The words of a `?` listing, whatever its layout: one command per line or all on one line, with
// or without descriptions, `Enter <cmd> - ...`, any separator, any case. Lower case.
struct HelpListing {
    std::set<std::string> commands;  // words in a command's place
    std::set<std::string> words;     // every word, descriptions included
};
HelpListing parse_help_listing(const std::vector<std::string>& lines);

// Everything the console has shown so far.
struct ConsoleEvidence {
    std::vector<std::string> lines;  // boot lines and any other output
    std::string prompt;              // confirmed prompt, empty if none
    HelpListing help;
};

struct VariantScore {
    VariantId variant{};
    int score = 0;
    std::vector<std::string> reasons;  // e.g. `? lists a3981`, `boot line "Ant ID - 12-IN G2"`
};
// Every variant's score, best first.
std::vector<VariantScore> rank_evidence(const ConsoleEvidence& evidence);

// A clear winner scores at least winning_score, ahead of the next by at least winning_margin.
inline constexpr int winning_score = 4;
inline constexpr int winning_margin = 3;
// The winner when it is clear; nullopt when unsure.
std::optional<VariantScore> clear_winner(const std::vector<VariantScore>& ranking);

// The evidence for firmware whose root `q` kills its shell (the G2, docs/firmware.md 6.5).
int q_killer_score(const std::vector<VariantScore>& ranking);
// The listing names a command some variant lists at its root.
bool names_a_root_command(const HelpListing& help);
// The root prompt of a firmware whose root `q` kills its shell (`TRK>`): other firmware may share the shape.
bool is_g2_root_shape(std::string_view prompt);
// A command of the G2's root listing that no other firmware lists (the G2's listing clues).
bool names_a_g2_only_command(const HelpListing& help);
// A G2-only command named anywhere in what the console printed (listings, descriptions, stray
// lines): a console that ever showed one may be a G2, whatever its latest listing says.
bool g2_command_heard(const std::vector<std::string>& lines);
// Any G2 clue (a boot line, a G2-only command or prompt; not the shared `TRK>` shape) anywhere in
// the raw output, even run into noise or a prompt.
bool g2_text_in(std::string_view raw);
// The one root where detection may send `q`: a listing that positively shows a Trav'ler (or Pro
// ODU) root, mot, os and nvs, with no G2-only command.
bool shows_travler_root(const HelpListing& help);

// What a position query drew, by the documented reply formats (docs/firmware.md 3.3, 6.3).
ProbeAnswer position_answer(const std::vector<std::string>& lines);

}  // namespace birdcage
