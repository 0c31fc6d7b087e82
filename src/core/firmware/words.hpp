// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A console line as the firmware's shells read it: words separated by blanks (space, TAB, CR, LF).
// Part of the hazard rule's library (birdcage_hazards), so that the rule and the reply parsers
// split a line the same way and the emulator still links that library alone.
#pragma once

#include <string_view>
#include <vector>

namespace birdcage {

// A byte a console prints as text (printable ASCII or TAB), and a line end.
inline bool is_text_byte(unsigned char byte) {
    return (byte >= 0x20 && byte < 0x7f) || byte == '\t';
}
inline bool is_line_end(char c) {
    return c == '\r' || c == '\n';
}

std::vector<std::string_view> split_words(std::string_view text);

}  // namespace birdcage
