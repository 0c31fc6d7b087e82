// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Raw console output read as the synchroniser needs it (console/synchroniser.hpp): console text
// told from line noise, the prompt a reply ends with, and the signs of a wrong baud rate. Pure.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/words.hpp"

namespace birdcage {

// A line of console text rather than line noise: an idle RS-485 bus can produce random bytes
// without end, a third of them printable by chance, and once in a while a CR or LF among them. A
// dish never prints unprintable bytes, so a line needs (almost) none to count as text.
bool is_text_line(std::size_t text_bytes, std::size_t noise_bytes);

// The length of the prompt `line` starts with when the rest of it is line noise (mostly
// unprintable bytes, as a noisy idle bus sends after the prompt); 0 otherwise. A prompt followed
// by text with a stray noise byte in it is no prompt: the console is still printing.
std::size_t prompt_before_noise(std::string_view line);

// The text lines of `raw` (is_text_line), noise bytes removed; empty and noise lines dropped.
std::vector<std::string> printable_lines(std::string_view raw);

// The prompt the output ends with, as its documented text (`TRK>` for `WG TRK> `): its last
// non-empty line, if that line has a prompt's shape (framer.hpp, prompt_shape()), is free of noise
// bytes, and is followed by nothing but line endings. Empty if none.
std::string trailing_prompt(std::string_view output);

// The last `count` non-empty lines of `output`, each quoted and escaped, for error messages.
std::string quoted_tail(std::string_view output, std::size_t count);

// True when `raw` looks like a console read at the wrong baud rate: mostly bytes outside
// printable ASCII, or printable bytes with no line structure and no prompt.
bool looks_like_wrong_baud(std::string_view raw);

}  // namespace birdcage
