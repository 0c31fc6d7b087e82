// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console synchroniser: brings an unknown console (booting, idle, inside a submenu, noisy) to a
// known prompt before anything else is sent. Every open path uses it (each variant's initialise and
// re-initialise, auto-detect, birdcage-probe). It only ever sends line endings and, where the
// caller allows, one harmless probe command (`?`): never anything the hazard guard would refuse.
//
// It never trusts a single line: it drains stale input, waits until the console has been quiet,
// sends a line ending, waits for quiet again and takes the prompt only from the END of that reply
// (a stale `TRK>` followed by a late boot line is no prompt), and acts on a prompt only once two
// consecutive pokes ended on the same one. "Quiet" means no console text: line noise (random
// bytes from an idle RS-485 bus, which may never stop) neither keeps a reply open nor hides a
// prompt it follows.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "base/clock.hpp"
#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/span.hpp"
#include "console/raw_output.hpp"
#include "console/transport.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

struct SyncSettings {
    std::string_view line_ending = "\r";
    // A line containing one of these: the dish is (re)booting. Until a line with a completion
    // marker follows, the console is poked only after boot_listen of quiet (a booting dish ignores
    // its input, and a real boot has silences of several seconds). Two pokes answered at the same
    // prompt end the boot whatever its last line was: firmware may print lines we do not know after
    // its completion marker.
    Span<const std::string_view> boot_markers;
    Span<const std::string_view> boot_complete_markers;
    // The firmware's documented last boot line (FirmwareProfile::ready_markers): heard as the latest
    // output, it ends the synchronisation at once, no poke sent. The console is then at its root,
    // just booted, and takes input (docs/firmware.md 3.6).
    Span<const std::string_view> ready_markers;
    // Sent after a line ending drew no prompt, to tell a live prompt-less console from a silent
    // one; empty: never. Must be harmless in every menu of every variant (`?`).
    std::string_view probe_command;
    std::chrono::milliseconds quiet_gap{250};      // silence that ends a reply
    std::chrono::milliseconds reply_window{1200};  // how long a poke waits for the first byte
    std::chrono::milliseconds boot_listen{5000};   // listen this long while boot output is in progress
    std::chrono::milliseconds budget{60000};       // give up after this (the boot timeout)
    std::chrono::milliseconds progress_interval{30000};
    // For the messages: what the caller expects ("a prompt (TRK> or MOT>)") and the usual baud
    // rate(s) of what it expects ("115200"), named when the replies look like a wrong baud rate.
    std::string expected = "a console prompt";
    std::string usual_baud;
};

// What the console showed once it was in sync.
struct ConsoleSnapshot {
    std::string prompt;                    // confirmed on two consecutive pokes; trailing spaces stripped
    std::vector<std::string> probe_reply;  // lines answering probe_command, when it proved the console live
    std::vector<std::string> heard;        // every printable line heard, oldest first (boot lines included)
    std::string last_boot_line;            // empty when no boot output was heard
    std::string ready_line;                // the ready line that ended the synchronisation (no prompt then)
    bool boot_heard = false;
    std::chrono::milliseconds waited{0};
};

class ConsoleSynchroniser {
public:
    // Its budgets are link time (the serial line's deadlines), so `clock` is the steady clock but
    // for tests, which freeze it (DishClock::manual). A read that times out advances the
    // synchroniser's own notion of time to that read's deadline, so a transport that times out at
    // once (a test fake) still spends the budget in a bounded number of reads.
    ConsoleSynchroniser(Transport& transport, SyncSettings settings, LogSink log, DishClock clock = {});

    Result<ConsoleSnapshot> synchronise();
    // The last bytes heard, raw (noise included), oldest first.
    const std::string& recent_output() const { return recent_; }

private:
    struct Heard {
        std::string raw;           // every byte, as received
        std::size_t text_end = 0;  // raw up to the end of its last text line or clean prompt (noise after it ignored)
        std::string_view text() const { return std::string_view(raw).substr(0, text_end); }
        bool failed = false;
        Status failure;
        bool ready_line_last = false;  // the latest text was a complete ready line (SyncSettings::ready_markers)
    };

    Clock::time_point now() const;
    // Reads until `first_byte_within` passes with nothing, or the line has been quiet for `gap`
    // after the last byte; never past `limit`.
    Heard collect(std::chrono::milliseconds first_byte_within, std::chrono::milliseconds gap, Clock::time_point limit);
    void absorb(std::string_view raw, ConsoleSnapshot& snapshot);
    bool booting() const;
    // A console that answers the same way twice after a quiet line has booted, whatever its last
    // boot line was (a completion line this backend does not know): ends the boot and says why.
    void end_boot_on(const std::string& answer, const std::string& last_boot_line);
    Status write(std::string_view bytes);
    void report_progress(const ConsoleSnapshot& snapshot, Clock::time_point started);
    std::string shown_so_far(const ConsoleSnapshot& snapshot) const;
    void check_baud(std::string_view raw);
    Status give_up(const ConsoleSnapshot& snapshot, std::string_view why) const;

    Transport& transport_;
    SyncSettings settings_;
    LogSink log_;
    DishClock clock_;
    Clock::time_point virtual_now_{};
    bool boot_in_progress_ = false;
    bool announced_wait_ = false;
    bool baud_warned_ = false;
    std::chrono::milliseconds next_progress_{0};
    std::size_t bytes_heard_ = 0;
    std::size_t noise_bytes_ = 0;
    std::size_t pokes_ = 0;           // bare line endings sent
    std::size_t answered_pokes_ = 0;  // of which drew console text
    std::string recent_;              // the tail of everything heard, for the give-up message
};

// The settings every open path uses for `profile` (a variant's row, or the auto-detect profile):
// its boot lines, `?` as the liveness probe where its prompts are undocumented, its baud rate.
SyncSettings console_sync_settings(const FirmwareProfile& profile, std::chrono::milliseconds budget);

}  // namespace birdcage
