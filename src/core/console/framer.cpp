// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console framing. The consoles are line-oriented menu shells that print a prompt and wait.
// Assumptions (each is what makes the state machine below sufficient):
//  1. A line ends at CR or LF. CR LF, LF CR and runs of terminators yield no empty lines: an empty
//     line carries no information, so empty lines are never reported.
//  2. Reply text is printable ASCII (0x20-0x7E) plus TAB. Any other byte (NUL, 0x80-0xFF, other
//     controls, BS, DEL) is line noise (RS-485 idle bus, wrong baud, swapped pair): it is removed
//     from the line and reported as a noise event, never interpreted.
//  3. A prompt is its documented text, an optional run of [A-Z0-9_] followed by '>' (`TRK>`,
//     `MOT>`, `A3981>`, `>`), known by its shape rather than its exact bytes: a short decoration
//     may stand before it (a product tag such as `WG `, `[G2]`, `dish:`, ending in neither a
//     letter nor a digit) and up to two of `$#:%>~` after it, then at most one space
//     (prompt_shape(), src/core/firmware/prompt.hpp: the one rule, which birdcage-probe
//     uses too). The documented text is what the framer reports: a console that tags its
//     prompts is in the same menus. The firmware prints it last and then waits, so it is recognised only
//     (a) as the whole unterminated line at the end of a chunk, when nothing followed it yet, or
//     (b) as a whole line of its own, or (c) as the start of a line that runs into an unprintable
//     byte (noise read in the same chunk as the prompt: a dish never prints such a byte, so its
//     line ended at the prompt; printable noise between the two is noise too). Help lines such
//     as `Enter <a3981> - ...` contain '>' but are not prompts: the whole line does not match.
//  4. The firmware echoes typed characters (G2 evidence, docs/firmware.md 6.1; unknown elsewhere).
//     The first complete line equal to the command sent, optionally preceded by a prompt
//     (`TRK>nvs`), is the echo. A console that does not echo simply never produces that line.
//  5. Lines containing a profile boot marker are boot lines; `MOTOR STALLED` and
//     `Motor Home Failure` lines are fault lines. Both can arrive at any time, unsolicited.
#include "console/framer.hpp"

#include "firmware/words.hpp"

#include <array>
#include <optional>

namespace birdcage {
namespace {

constexpr std::array<std::string_view, 2> fault_markers{"MOTOR STALLED", "Motor Home Failure"};

bool contains_any(std::string_view line, Span<const std::string_view> markers) {
    for (auto marker : markers) {
        if (line.find(marker) != std::string_view::npos) {
            return true;
        }
    }
    return false;
}

}  // namespace

ConsoleFramer::ConsoleFramer(const FirmwareProfile& profile) : profile_(profile) {}

void ConsoleFramer::expect_echo(std::string_view command) {
    expected_echo_ = std::string(command);
    echo_pending_ = !command.empty();
}

void ConsoleFramer::reset() {
    partial_.clear();
    noise_.clear();
    expected_echo_.clear();
    echo_pending_ = false;
}

void ConsoleFramer::flush_noise(std::vector<FrameEvent>& events) {
    if (!noise_.empty()) {
        events.push_back({FrameEvent::Kind::noise, noise_});
        noise_.clear();
    }
}

void ConsoleFramer::finish_line(std::vector<FrameEvent>& events) {
    std::string line;
    line.swap(partial_);
    if (line.empty()) {
        return;
    }
    if (echo_pending_) {
        const std::string_view after_prompt = std::string_view(line).substr(leading_prompt_length(line));
        if (line == expected_echo_ || after_prompt == expected_echo_) {
            echo_pending_ = false;
            events.push_back({FrameEvent::Kind::echo, line});
            return;
        }
    }
    if (looks_like_prompt(line)) {
        events.push_back({FrameEvent::Kind::prompt, prompt_text(line)});
    } else if (contains_any(line, profile_.reboot_markers) || contains_any(line, profile_.boot_complete_markers)) {
        events.push_back({FrameEvent::Kind::boot_line, line});
    } else if (contains_any(line, fault_markers)) {
        events.push_back({FrameEvent::Kind::fault_line, line});
    } else {
        events.push_back({FrameEvent::Kind::line, line});
    }
}

void ConsoleFramer::end_prompt_at_noise(std::vector<FrameEvent>& events) {
    const std::size_t length = leading_prompt_length(partial_);
    if (length == 0) {
        return;
    }
    std::string_view after = std::string_view(partial_).substr(length);
    // Our command's echo after the prompt (`TRK>nvs`) may still be arriving.
    if (echo_pending_ && std::string_view(expected_echo_).substr(0, after.size()) == after) {
        return;
    }
    std::string prompt = prompt_text(std::string_view(partial_).substr(0, length));
    if (!after.empty() && after.front() == ' ') {
        after.remove_prefix(1);
    }
    flush_noise(events);
    events.push_back({FrameEvent::Kind::prompt, std::move(prompt)});
    noise_ += after;
    partial_.clear();
}

std::vector<FrameEvent> ConsoleFramer::feed(std::string_view bytes) {
    std::vector<FrameEvent> events;
    for (char c : bytes) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '\r' || c == '\n') {
            finish_line(events);
        } else if (is_text_byte(byte)) {
            partial_ += c;
        } else {
            end_prompt_at_noise(events);
            noise_ += c;
        }
    }
    flush_noise(events);
    if (looks_like_prompt(partial_)) {
        events.push_back({FrameEvent::Kind::prompt, prompt_text(partial_)});
        partial_.clear();
    }
    return events;
}

}  // namespace birdcage
