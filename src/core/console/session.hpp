// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console session: every byte to the dish passes through transact(), which runs the hazard guard,
// handles stale input, writes the command and frames the output until the prompt.
#pragma once

#include <chrono>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/span.hpp"
#include "console/console_events.hpp"
#include "console/framer.hpp"
#include "console/synchroniser.hpp"
#include "console/transport.hpp"
#include "firmware/hazards.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

struct Reply {
    std::vector<std::string> lines;  // reply lines, without echo, prompt and unsolicited lines
    std::string prompt;              // the prompt that ended the reply; empty if none was seen
};

// For variants whose prompt is unknown: the reply is complete once this returns true for the
// lines so far (and the line has then been idle for the profile's quiet gap).
using ReplyComplete = std::function<bool(Span<const std::string>)>;

class ConsoleSession {
public:
    ConsoleSession(Transport& transport, const FirmwareProfile& profile, LogSink log);

    Result<Reply> transact(std::string_view command, std::chrono::milliseconds timeout);
    Result<Reply> transact(std::string_view command, std::chrono::milliseconds timeout, const ReplyComplete& complete);

    // Brings the console to a confirmed prompt (ConsoleSynchroniser) and adopts it; boot output
    // heard meanwhile counts as for transact(). The only way an open path starts talking.
    Result<ConsoleSnapshot> synchronise(const SyncSettings& settings);

    // Sends a bare line ending and waits for a prompt; learns which menu we are in.
    // Errc::timeout when no prompt arrived (always the case on variants without known prompts).
    Status resync(std::chrono::milliseconds timeout);

    // Listens without sending for `duration`, or until `stop` returns true for a line or a prompt.
    // Unsolicited lines are handled as in transact(). Reply::lines holds every line received,
    // boot and fault lines included. With a `stop` that never matched: Errc::timeout.
    Result<Reply> listen(std::chrono::milliseconds duration, const std::function<bool(const std::string&)>& stop = {});

    // Which menu the console is in: "root", "mot", ...; empty when unknown.
    const std::string& menu() const { return menu_; }
    const std::string& last_prompt() const { return last_prompt_; }
    bool reboot_seen() const { return reboot_seen_; }
    // Clears reboot_seen(), last_boot_line() and just_booted().
    void clear_reboot_seen() {
        reboot_seen_ = false;
        last_boot_line_.clear();
        just_booted_ = false;
    }
    // The latest output is the firmware's documented ready line (FirmwareProfile::ready_markers),
    // heard by transact() or listen(): the dish has just booted, is at its root and takes input.
    // While this holds, transact() sends nothing and fails at once: whatever it was asked is void
    // (a booting dish drops its input), and the caller's recovery must stop the TV search first.
    bool just_booted() const { return just_booted_; }
    // The most recent boot line seen anywhere (transact, listen or stale input).
    const std::string& last_boot_line() const { return last_boot_line_; }
    // The last bytes the console sent, raw (line noise and text the framer dropped included): for
    // decisions that must not miss evidence whatever shape it arrived in.
    const std::string& recent_output() const { return recent_output_; }

    void set_allow_nvs_write(bool allow) { allow_nvs_write_ = allow; }
    // What the session's owner asks the console for (hazards.hpp): the hazard rule lets through only
    // the well-formed commands of these requests. Nothing until the owner says (the controller asks
    // for backend_requests; detection asks for nothing).
    void set_requests(HazardRequests requests) { requests_ = requests; }
    HazardRequests requests() const { return requests_; }
    // The controller reports the homing state it learnt from position replies; the guard uses it.
    void set_axes_unhomed(bool unhomed) { axes_unhomed_ = unhomed; }
    // The caller learnt which menu the console is in by other means (e.g. its `?` listing).
    void set_menu(std::string menu) { menu_ = std::move(menu); }
    // The console synchroniser confirmed this prompt: the menu follows from it, and whatever the
    // framer held back from before the synchronisation is void.
    void adopt_prompt(const std::string& prompt);

    const FirmwareProfile& profile() const { return profile_; }

    // Where the knowledge read from replies goes (console_events.hpp): the session reports fault
    // lines and menu/prompt changes itself; the parts that parse replies report through report().
    void set_event_sink(ConsoleEventSink sink) { events_ = std::move(sink); }
    void report(const ConsoleEvent& event) const {
        if (events_) {
            events_(event);
        }
    }

private:
    struct Collected {
        std::vector<std::string> lines;
        std::vector<std::string> faults;
        std::vector<std::string> everything;  // lines, boot lines and fault lines, in order
        std::string prompt;
    };
    enum class ReadOutcome { data, timeout, failed };

    ReadOutcome read_some(Collected& into, Deadline deadline, Status& failure);
    void note_raw(std::string_view bytes);
    void handle_event(const FrameEvent& event, Collected& into);
    Status drain_stale(Collected& stale);
    void note_prompt(const std::string& prompt);
    void note_menu_after(std::string_view command);
    void report_if_reached(const std::string& menu_before, const std::string& prompt_before) const;

    Transport& transport_;
    const FirmwareProfile& profile_;
    LogSink log_;
    ConsoleFramer framer_;
    std::string menu_;
    std::string last_prompt_;
    bool reboot_seen_ = false;
    bool just_booted_ = false;
    std::string last_boot_line_;
    static constexpr std::size_t recent_output_limit = 8192;
    std::string recent_output_;
    bool allow_nvs_write_ = false;
    HazardRequests requests_ = request_nothing;
    bool axes_unhomed_ = false;
    ConsoleEventSink events_;
};

}  // namespace birdcage
