// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console framer: turns the byte stream of a menu shell into lines, prompts and noise reports.
// Pure: no I/O, no clock. Framing rules are listed at the top of src/core/console/framer.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "birdcage/firmware/variants.hpp"

namespace birdcage {

struct FrameEvent {
    enum class Kind {
        line,        // a complete reply line, line terminator stripped
        echo,        // the echo of the command we sent (dropped from replies)
        prompt,      // `WORD>` at the end of the output seen so far, or on a line of its own
        boot_line,   // unsolicited: the dish is (re)booting (profile reboot/boot-complete markers)
        fault_line,  // unsolicited: `AZ MOTOR STALLED`, `EL MOTOR STALLED`, `EL Motor Home Failure`
        noise,       // bytes dropped as garbage (text holds them, escaped by the consumer)
    };
    Kind kind;
    std::string text;

    bool operator==(const FrameEvent&) const = default;
};

class ConsoleFramer {
public:
    explicit ConsoleFramer(const FirmwareProfile& profile);

    // The next complete line equal to `command` (optionally after a leading prompt) is an echo.
    void expect_echo(std::string_view command);

    // Feeds one chunk as it arrived. A prompt is recognised only at the end of a chunk (nothing
    // followed it yet), as a whole line, or at the start of a line that runs into line noise.
    std::vector<FrameEvent> feed(std::string_view bytes);

    // The unterminated text held back so far (for diagnostics).
    const std::string& partial_line() const { return partial_; }

    // Drops the partial line and any pending echo expectation.
    void reset();

private:
    void finish_line(std::vector<FrameEvent>& events);
    void flush_noise(std::vector<FrameEvent>& events);
    void end_prompt_at_noise(std::vector<FrameEvent>& events);

    const FirmwareProfile& profile_;
    std::string partial_;
    std::string noise_;
    std::string expected_echo_;
    bool echo_pending_ = false;
};

// A prompt known by its shape (framing rule 3 in framer.cpp): its documented text, an optional run
// of uppercase letters, digits or '_' followed by '>' (`TRK>`), with an optional decoration before
// it (at most 12 characters, no '<', not ending in a letter or digit: `WG `, `[G2]`, `dish:`) and up
// to two of `$#:%>~` after it, then at most one space. `Enter <a3981> - ...` and `mot>` are not.
struct PromptShape {
    std::string_view documented;   // `TRK>` of `WG TRK> `: what the menus are known by
    std::string_view decorated;    // the prompt as printed, without its trailing space
};
std::optional<PromptShape> prompt_shape(std::string_view text);
bool looks_like_prompt(std::string_view text);
// The length of the prompt `text` starts with (`TRK>`, `WG TRK>`, `[G2]MOT>$`), its trailing space
// not counted; 0 when it starts with none. `documented`, if given, receives its documented text.
std::size_t leading_prompt_length(std::string_view text, std::string_view* documented = nullptr);
// The documented text of the prompt `text` is (`TRK>` for `[G2]TRK>`); empty when it is none.
std::string prompt_text(std::string_view text);

}  // namespace birdcage
