// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe's reading of `?` listings: every command a listing names, with its description
// where the layout gives one.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace probe {

struct HelpEntry {
    std::string name;
    std::string description;
};

// One row of a listing: `Enter <cmd> - Description` (the emulator's old G2 layout), `cmd - Description`,
// or the word, two or more spaces, the description (the real G2's `   ela2s         Elevation Law
// Test - Angle to Steps [angle]`: the word ends at the first blank, whatever the description holds).
// Headers (`Available commands:`), usage lines (`help [<command>]`) and placeholders are not rows.
std::optional<HelpEntry> parse_help_line(std::string_view line);

// Every command of a listing, in its order: the rows above, then any further command word the
// core's layout-agnostic reader (the backend detector's, which also reads packed, numbered and
// column layouts) finds, without a description.
std::vector<HelpEntry> parse_help(const std::vector<std::string>& lines);

}  // namespace probe
