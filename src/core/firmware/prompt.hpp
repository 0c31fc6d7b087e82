// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What a console prompt looks like: the one rule every program that reads a console uses (the
// backend's framer and synchroniser, birdcage-probe). docs/firmware.md documents a prompt's text
// (`TRK>`, `MOT>`, §6.3) on the G2 only; what a firmware build prints around it is open on every
// variant, so a prompt is known by its shape rather than its exact bytes.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace birdcage {

// A prompt is its documented text, an optional run of uppercase letters, digits or '_' followed by
// '>' (`TRK>`, `A3981>`, `>`), with an optional decoration before it (at most 12 printable
// characters, no '<', not ending in a letter or digit: `WG `, `[G2]`, `dish:`) and up to two of
// `$#:%>~` after it, then at most one space. `Enter <a3981> - ...` and `mot>` (an echo, a listing
// word) are not prompts.
struct PromptShape {
    std::string_view documented;  // `TRK>` of `WG TRK> `: what the menus are known by
    std::string_view decorated;   // the prompt as printed, without its trailing space
};
// `text` as a whole is a prompt (one trailing space allowed).
std::optional<PromptShape> prompt_shape(std::string_view text);
bool looks_like_prompt(std::string_view text);
// The length of the prompt `text` starts with (`TRK>`, `WG TRK>`, `[G2]MOT>$`), its trailing space
// not counted; 0 when it starts with none. `documented`, if given, receives its documented text.
std::size_t leading_prompt_length(std::string_view text, std::string_view* documented = nullptr);
// The documented text of the prompt `text` is (`TRK>` for `[G2]TRK>`); empty when it is none.
std::string prompt_text(std::string_view text);
// The word of the prompt `text` is (`MOT` for `dish:MOT> `, empty for a bare `>`); nullopt when
// `text` is no prompt.
std::optional<std::string> prompt_word(std::string_view text);

}  // namespace birdcage
