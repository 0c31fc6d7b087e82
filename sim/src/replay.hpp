// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Transcript replay: answers each expected host chunk with the recorded dish chunks, at the
// recorded timing in simulated time. Pure (no I/O, no clock) so that it can be driven by tests
// and by the emulator's console thread alike.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"

namespace birdcage::sim {

class Replayer {
public:
    // `source` names the transcript in failure reports. `position_reads`: the commands (without
    // line ending) that only read the dish's position, which may be repeated (see replay.cpp).
    Replayer(Transcript transcript, ReplayMode mode, std::string source, std::vector<std::string> position_reads = {});

    // Bytes from the client. While replaying they are matched against the transcript; returns the
    // bytes the model console must handle instead (non-empty only once lenient mode fell back).
    std::string receive(std::string_view bytes);
    void advance(double dt);    // simulated seconds
    std::string take_output();  // recorded dish bytes now due

    // False once the replay has failed (strict) or handed over to the model console (lenient).
    bool replaying() const { return !failure_ && !fell_back_; }
    bool fell_back() const { return fell_back_; }
    const std::optional<std::string>& failure() const { return failure_; }
    // Every chunk of the transcript has been matched or sent.
    bool complete() const { return next_ == transcript_.entries.size(); }
    // Unrecorded pokes (bare line endings, `?`) answered from the firmware facts (see replay.cpp).
    std::size_t pokes_answered() const { return pokes_answered_; }
    // Unrecorded repetitions of a position read answered with its last recorded reply.
    std::size_t reads_repeated() const { return reads_repeated_; }

private:
    void pump();
    bool answer_poke();
    bool answer_repeated_read();
    void note_read(std::string_view chunk);
    void note_prompt(std::string_view bytes);
    void diverge(std::string received, const std::string& why);

    Transcript transcript_;
    ReplayMode mode_;
    std::string source_;
    std::size_t next_ = 0;     // the entry being waited for
    std::size_t matched_ = 0;  // bytes of a host entry matched so far
    std::string input_;        // client bytes not yet matched
    std::string output_;
    double now_ = 0.0;
    double last_event_ = 0.0;  // when the previous chunk was sent or completely received
    std::optional<std::string> failure_;
    bool fell_back_ = false;
    std::string last_prompt_;  // the prompt the recorded dish output last ended with
    std::size_t pokes_answered_ = 0;
    std::vector<std::string> position_reads_;
    std::string last_read_;        // the position read last matched, with its line ending...
    std::string last_read_reply_;  // ...and the dish chunks recorded after it
    std::size_t reads_repeated_ = 0;
    std::string fallback_bytes_;
};

}  // namespace birdcage::sim
