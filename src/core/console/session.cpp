// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/session.hpp"

#include <algorithm>
#include <array>

#include "firmware/protocol.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

// Bounds the stale-input drain so a streaming console (ADC `m`, DVB `agc`) cannot hold us forever.
constexpr int max_stale_reads = 64;

// Commands that enter a submenu of the same name (docs/firmware.md 3.3, 4.3, 5.3, 6.3, 8.3). Used only
// where the firmware's prompts are unknown and the menu must be inferred from what we sent.
constexpr std::array<std::string_view, 16> submenu_commands{"a3981",  "adc",  "dipswitch", "dvb",      "eeprom", "gpio",
                                                            "latlon", "mot",  "motor",     "ngsearch", "nvs",    "odu",
                                                            "os",     "peak", "step",      "target"};

}  // namespace

ConsoleSession::ConsoleSession(Transport& transport, const FirmwareProfile& profile, LogSink log)
    : transport_(transport), profile_(profile), log_(std::move(log)), framer_(profile) {}

Result<ConsoleSnapshot> ConsoleSession::synchronise(const SyncSettings& settings) {
    framer_.reset();
    just_booted_ = false;  // the synchroniser reports a ready line itself (ConsoleSnapshot::ready_line)
    ConsoleSynchroniser synchroniser(transport_, settings, log_);
    auto synced = synchroniser.synchronise();
    note_raw(synchroniser.recent_output());
    if (synced.value.boot_heard) {
        reboot_seen_ = true;
        last_boot_line_ = synced.value.last_boot_line;
        menu_.clear();
    }
    if (synced && !synced.value.prompt.empty()) {
        adopt_prompt(synced.value.prompt);
    }
    return synced;
}

void ConsoleSession::adopt_prompt(const std::string& prompt) {
    framer_.reset();
    note_prompt(prompt);
}

// A prompt seen again in the same menu is no news; one after the menu was forgotten (a boot line,
// a timeout) is.
void ConsoleSession::report_if_reached(const std::string& menu_before, const std::string& prompt_before) const {
    if (menu_ != menu_before || last_prompt_ != prompt_before) {
        report(ConsoleEvent::menu_reached(menu_, last_prompt_));
    }
}

void ConsoleSession::note_prompt(const std::string& prompt) {
    const std::string menu_before = menu_, prompt_before = last_prompt_;
    last_prompt_ = prompt;
    while (!last_prompt_.empty() && last_prompt_.back() == ' ') {
        last_prompt_.pop_back();
    }
    menu_ = menu_for_prompt(profile_, last_prompt_);
    report_if_reached(menu_before, prompt_before);
}

void ConsoleSession::note_menu_after(std::string_view command) {
    const std::string menu_before = menu_;
    if (command == "q") {
        // Behind the Pro's ODU tunnel nobody knows whether `q` lands on the ODU or the IDU root.
        menu_ = profile_.has(quirk_odu_tunnel) ? std::string() : std::string("root");
    } else if (std::find(submenu_commands.begin(), submenu_commands.end(), command) != submenu_commands.end()) {
        menu_ = std::string(command);
    }
    report_if_reached(menu_before, last_prompt_);
}

void ConsoleSession::handle_event(const FrameEvent& event, Collected& into) {
    // A prompt after the ready line is the root's; any other output means the dish has moved on.
    if (event.kind != FrameEvent::Kind::prompt && event.kind != FrameEvent::Kind::noise) {
        just_booted_ =
            event.kind == FrameEvent::Kind::boot_line &&
            std::any_of(profile_.ready_markers.begin(), profile_.ready_markers.end(),
                        [&](std::string_view marker) { return event.text.find(marker) != std::string::npos; });
    }
    switch (event.kind) {
        case FrameEvent::Kind::line:
            into.lines.push_back(event.text);
            into.everything.push_back(event.text);
            break;
        case FrameEvent::Kind::echo:
            break;
        case FrameEvent::Kind::prompt:
            into.prompt = event.text;
            note_prompt(event.text);
            break;
        case FrameEvent::Kind::boot_line:
            reboot_seen_ = true;
            last_boot_line_ = event.text;
            menu_.clear();  // wherever we were, a booting dish ends up at its root (or mid-boot)
            into.everything.push_back(event.text);
            emit(log_, LogLevel::verbose, "dish boot output: " + event.text);
            break;
        case FrameEvent::Kind::fault_line:
            into.faults.push_back(event.text);
            into.everything.push_back(event.text);
            emit(log_, LogLevel::warning, "dish reported: " + event.text);
            report(ConsoleEvent::fault_line(event.text));
            break;
        case FrameEvent::Kind::noise:
            emit(log_, LogLevel::verbose,
                 "dropped " + std::to_string(event.text.size()) + " noise byte(s): " + escape_bytes(event.text));
            break;
    }
}

void ConsoleSession::note_raw(std::string_view bytes) {
    recent_output_.append(bytes);
    if (recent_output_.size() > recent_output_limit) {
        recent_output_.erase(0, recent_output_.size() - recent_output_limit);
    }
}

ConsoleSession::ReadOutcome ConsoleSession::read_some(Collected& into, Deadline deadline, Status& failure) {
    std::array<char, 512> buffer{};
    const auto got = transport_.read(buffer.data(), buffer.size(), deadline);
    if (!got) {
        if (got.status.code == Errc::timeout) {
            return ReadOutcome::timeout;
        }
        failure = got.status;
        return ReadOutcome::failed;
    }
    const std::string_view bytes(buffer.data(), got.value);
    emit(log_, LogLevel::trace, "RES " + escape_bytes(bytes));
    note_raw(bytes);
    for (const auto& event : framer_.feed(bytes)) {
        handle_event(event, into);
    }
    return ReadOutcome::data;
}

Status ConsoleSession::drain_stale(Collected& stale) {
    for (int i = 0; i < max_stale_reads; ++i) {
        Status failure;
        switch (read_some(stale, Clock::now(), failure)) {
            case ReadOutcome::data:
                continue;
            case ReadOutcome::failed:
                return failure;
            case ReadOutcome::timeout:
                i = max_stale_reads;
                break;
        }
    }
    for (const auto& line : stale.lines) {
        emit(log_, LogLevel::verbose, "stale output ignored: " + line);
    }
    if (!framer_.partial_line().empty()) {
        emit(log_, LogLevel::verbose, "stale partial line ignored: " + escape_bytes(framer_.partial_line()));
    }
    framer_.reset();
    return Status::ok();
}

Result<Reply> ConsoleSession::transact(std::string_view command, std::chrono::milliseconds timeout) {
    return transact(command, timeout, ReplyComplete{});
}

Result<Reply> ConsoleSession::transact(std::string_view command, std::chrono::milliseconds timeout,
                                       const ReplyComplete& complete) {
    const HazardContext context{menu_, allow_nvs_write_, axes_unhomed_, requests_};
    if (Status refused = hazard_check(profile_, command, context); !refused) {
        emit(log_, LogLevel::warning, refused.message);
        return {{}, refused};
    }

    Collected collected;
    if (Status drained = drain_stale(collected); !drained) {
        return {{}, drained};
    }
    // Stale lines and prompts are not part of this reply (a stale prompt must not end it early);
    // stale faults still count.
    collected.lines.clear();
    collected.everything.clear();
    collected.prompt.clear();
    auto lost_to_boot = [&](std::string_view when) {
        return Result<Reply>{
            {collected.lines, collected.prompt},
            Status{Errc::timeout, "the dish has just booted (\"" + last_boot_line_ + "\" " + std::string(when) + " \"" +
                                      escape_bytes(command) + "\"): its TV search must be stopped first"}};
    };
    if (just_booted_) {
        return lost_to_boot("before");
    }

    const Deadline deadline = Clock::now() + timeout;
    const std::string wire = std::string(command) + std::string(profile_.line_ending);
    framer_.expect_echo(command);
    emit(log_, LogLevel::trace, "CMD " + escape_bytes(wire));
    if (Status written = transport_.write(wire, deadline); !written) {
        return {{}, written};
    }

    // A recognised prompt ends the reply on every variant. Where prompts are undocumented the reply
    // also ends once it is complete and the line has been quiet for the profile's gap.
    Deadline quiet_until = Clock::now() + profile_.quiet_gap;
    for (;;) {
        if (!collected.prompt.empty()) {
            break;
        }
        const bool satisfied = !complete || complete(collected.lines);
        const bool may_end_quietly = !profile_.prompt_known() && satisfied;
        const Deadline wait_until = may_end_quietly ? std::min(deadline, quiet_until) : deadline;
        Status failure;
        const ReadOutcome outcome = read_some(collected, wait_until, failure);
        if (outcome == ReadOutcome::data) {
            if (just_booted_) {
                return lost_to_boot("arrived instead of the reply to");  // the boot dropped the command
            }
            quiet_until = Clock::now() + profile_.quiet_gap;
            continue;
        }
        if (outcome == ReadOutcome::failed) {
            return {{collected.lines, collected.prompt}, failure};
        }
        if (may_end_quietly) {
            break;
        }
        return {{collected.lines, collected.prompt},
                Status{Errc::timeout, "no " + std::string(profile_.prompt_known() ? "prompt" : "complete reply") +
                                          " after \"" + escape_bytes(command) + "\" within " +
                                          std::to_string(timeout.count()) + " ms"}};
    }
    if (collected.prompt.empty()) {
        note_menu_after(command);
    }

    Reply reply{std::move(collected.lines), collected.prompt};
    if (!collected.faults.empty()) {
        return {std::move(reply), Status{Errc::protocol, "dish reported: " + collected.faults.front()}};
    }
    return {std::move(reply), Status::ok()};
}

Status ConsoleSession::resync(std::chrono::milliseconds timeout) {
    auto reply = transact("", timeout);
    if (!reply) {
        return reply.status;
    }
    if (reply.value.prompt.empty()) {
        return Status{Errc::timeout, "no prompt after a bare line ending"};
    }
    return Status::ok();
}

Result<Reply> ConsoleSession::listen(std::chrono::milliseconds duration,
                                     const std::function<bool(const std::string&)>& stop) {
    Collected collected;
    const Deadline deadline = Clock::now() + duration;
    std::size_t checked = 0;
    for (;;) {
        Status failure;
        const ReadOutcome outcome = read_some(collected, deadline, failure);
        if (outcome == ReadOutcome::failed) {
            return {{collected.everything, collected.prompt}, failure};
        }
        if (outcome == ReadOutcome::timeout) {
            break;
        }
        if (stop) {
            for (; checked < collected.everything.size(); ++checked) {
                if (stop(collected.everything[checked])) {
                    return {{collected.everything, collected.prompt}, Status::ok()};
                }
            }
            if (!collected.prompt.empty() && stop(collected.prompt)) {
                return {{collected.everything, collected.prompt}, Status::ok()};
            }
        }
    }
    if (stop) {
        return {{collected.everything, collected.prompt}, Status{Errc::timeout, "nothing awaited arrived"}};
    }
    return {{collected.everything, collected.prompt}, Status::ok()};
}

}  // namespace birdcage
