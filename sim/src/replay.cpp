// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "replay.hpp"

#include <utility>

namespace birdcage::sim {
namespace {

// Context in a failure report: this many chunks before the divergence.
constexpr std::size_t context_chunks = 3;

}  // namespace

Replayer::Replayer(Transcript transcript, ReplayMode mode, std::string source, std::vector<std::string> position_reads)
    : transcript_(std::move(transcript)),
      mode_(mode),
      source_(std::move(source)),
      position_reads_(std::move(position_reads)) {
    // Until the recording shows a prompt, a poke after the dish's boot output is answered with the
    // first prompt it shows at all: the root it comes up in.
    for (const TranscriptEntry& entry : transcript_.entries) {
        if (entry.direction != Direction::dish_to_host)
            continue;
        note_prompt(entry.bytes);
        if (!last_prompt_.empty())
            break;
    }
    pump();
}

std::string Replayer::receive(std::string_view bytes) {
    if (fell_back_)
        return std::string(bytes);
    if (failure_)
        return {};
    input_.append(bytes);
    pump();
    return std::exchange(fallback_bytes_, {});
}

void Replayer::advance(double dt) {
    now_ += dt;
    pump();
}

std::string Replayer::take_output() {
    return std::exchange(output_, {});
}

void Replayer::pump() {
    while (replaying() && next_ < transcript_.entries.size()) {
        const TranscriptEntry& entry = transcript_.entries[next_];
        if (entry.direction == Direction::dish_to_host) {
            const double due = last_event_ + entry.delay_ms / 1000.0;
            if (now_ < due)
                return;
            output_ += entry.bytes;
            note_prompt(entry.bytes);
            if (!last_read_.empty())
                last_read_reply_ += entry.bytes;
            last_event_ = due;
            ++next_;
            continue;
        }
        // Host chunks are matched as a byte stream: how the client's writes were split does not matter.
        std::size_t used = 0;
        while (used < input_.size() && matched_ < entry.bytes.size() && input_[used] == entry.bytes[matched_]) {
            ++used;
            ++matched_;
        }
        if (matched_ < entry.bytes.size() && used < input_.size()) {
            // Every byte received since this chunk began, the matched ones once (not twice): a
            // repeated `a` shares its first byte with the `a 0 99.00` expected.
            input_ = entry.bytes.substr(0, matched_) + input_.substr(used);
            matched_ = 0;
            if (answer_poke() || answer_repeated_read())
                continue;
            diverge(std::exchange(input_, {}), "");
            return;
        }
        input_.erase(0, used);
        if (matched_ < entry.bytes.size())
            return;  // wait for the rest of the command
        matched_ = 0;
        last_event_ = now_;
        note_read(entry.bytes);
        ++next_;
    }
    while (replaying() && next_ == transcript_.entries.size() && !input_.empty())
        if (!answer_poke() && !answer_repeated_read())
            diverge(std::exchange(input_, {}), "the transcript has ended");
}

// A client that does not trust a single line pokes the console (a bare line ending, or `?` where
// prompts are unknown) until it has seen the same prompt twice; how many pokes a recording holds
// depends on timing, not on the dish. An unrecorded poke is therefore answered the way the
// docs/firmware.md says a console answers it (6.1: a bare line ending at a prompt prints the prompt
// again, here the last prompt recorded, or before any the first one the recording shows) and
// the recording goes on. While recorded dish output is still due (the dish is busy, e.g. booting)
// a poke gets no answer: a booting dish ignores its input. `?` is never answered from nothing; it
// is ignored the same way.
bool Replayer::answer_poke() {
    static constexpr std::string_view pokes[] = {"\r\n", "\r", "\n", "?\r\n", "?\r", "?\n"};
    for (std::string_view poke : pokes) {
        if (input_.compare(0, poke.size(), poke) != 0)
            continue;
        input_.erase(0, poke.size());
        const bool busy =
            next_ < transcript_.entries.size() && transcript_.entries[next_].direction == Direction::dish_to_host;
        if (poke.front() != '?' && !busy && !last_prompt_.empty())
            output_ += "\r\n" + last_prompt_;
        ++pokes_answered_;
        return true;
    }
    return false;
}

// How many position reads a recording holds depends on timing too: a client that wants two readings
// a span of time apart before it trusts the dish at rest reads again where the recorded client, on
// a faster or slower clock, went on. A position read repeated right after the recorded one (no
// other command between) is answered with the reply recorded for it, the dish still where that
// reply says; only reads, which change nothing on the dish, are answered this way.
bool Replayer::answer_repeated_read() {
    if (last_read_.empty() || last_read_reply_.empty() || input_.compare(0, last_read_.size(), last_read_) != 0)
        return false;
    const bool busy =
        next_ < transcript_.entries.size() && transcript_.entries[next_].direction == Direction::dish_to_host;
    if (busy)
        return false;
    input_.erase(0, last_read_.size());
    output_ += last_read_reply_;
    ++reads_repeated_;
    return true;
}

// After a host chunk has been matched: whether it is a position read (a word of position_reads_
// and a line ending), whose reply answer_repeated_read() may send again.
void Replayer::note_read(std::string_view chunk) {
    last_read_.clear();
    last_read_reply_.clear();
    const std::size_t end = chunk.find_first_of("\r\n");
    if (end == std::string_view::npos || chunk.find_first_not_of("\r\n", end) != std::string_view::npos)
        return;
    for (const std::string& read : position_reads_) {
        if (chunk.substr(0, end) == read) {
            last_read_ = chunk;
            return;
        }
    }
}

// The prompt a recorded dish chunk ends with (`WORD>`, after its last line ending), if any.
void Replayer::note_prompt(std::string_view bytes) {
    const std::size_t line_start = bytes.find_last_of("\r\n");
    const std::string_view tail = bytes.substr(line_start == std::string_view::npos ? 0 : line_start + 1);
    if (!tail.empty() && tail.back() == '>' && tail.find_first_of(" <") == std::string_view::npos)
        last_prompt_ = tail;
}

void Replayer::diverge(std::string received, const std::string& why) {
    input_.clear();
    matched_ = 0;
    if (mode_ == ReplayMode::lenient) {
        fell_back_ = true;
        fallback_bytes_ = std::move(received);
        return;
    }
    const auto& entries = transcript_.entries;
    std::string report = "replay of " + source_ + " failed: ";
    if (next_ < entries.size()) {
        const TranscriptEntry& expected = entries[next_];
        report += "unexpected command at line " + std::to_string(expected.line_number) + "\n";
        for (std::size_t i = next_ > context_chunks ? next_ - context_chunks : 0; i < next_; ++i)
            report += "  line " + std::to_string(entries[i].line_number) + ":  " + format_entry(entries[i]) + "\n";
        report += "  expected:  > " + escape_chunk(expected.bytes) + "\n";
    } else {
        report += "unexpected bytes after the last line (" + why + ")\n";
    }
    report += "  received:  > " + escape_chunk(received) + "\n";
    failure_ = std::move(report);
}

}  // namespace birdcage::sim
