// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console framer: turns the byte stream of a menu shell into lines, prompts and noise reports.
// Pure: no I/O, no clock. Framing rules are listed at the top of src/core/console/framer.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/prompt.hpp"  // the prompt rule the framer applies
#include "firmware/variants.hpp"

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

    bool operator==(const FrameEvent& other) const { return kind == other.kind && text == other.text; }
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

}  // namespace birdcage
