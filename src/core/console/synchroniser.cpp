// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/synchroniser.hpp"

#include <algorithm>
#include <array>

#include "console/framer.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr std::size_t recent_limit = 8192;  // bytes of output kept for the give-up message and recent_output()
constexpr std::size_t lines_quoted = 4;
constexpr std::size_t baud_sample = 256;  // bytes judged by the wrong-baud check

bool contains_any(std::string_view line, Span<const std::string_view> markers) {
    return std::any_of(markers.begin(), markers.end(),
                       [&](std::string_view marker) { return line.find(marker) != std::string_view::npos; });
}

std::string seconds_text(std::chrono::milliseconds ms) {
    return std::to_string(ms.count() / 1000) + " s";
}

// The auto-detect profile stands for every variant: name each rate with the variants using it.
std::string usual_baud_text(const FirmwareProfile& profile) {
    if (&profile != &probe_profile()) {
        return std::to_string(profile.baud);
    }
    std::vector<std::pair<int, std::string>> rates;
    for (const FirmwareProfile& row : all_profiles()) {
        auto same = std::find_if(rates.begin(), rates.end(), [&](const auto& r) { return r.first == row.baud; });
        if (same == rates.end()) {
            rates.emplace_back(row.baud, std::string(row.short_name));
        } else {
            same->second += ", " + std::string(row.short_name);
        }
    }
    std::string text;
    for (const auto& [baud, names] : rates) {
        text += (text.empty() ? "" : " or ") + std::to_string(baud) + " (" + names + ")";
    }
    return text;
}

}  // namespace

SyncSettings console_sync_settings(const FirmwareProfile& profile, std::chrono::milliseconds budget) {
    SyncSettings settings;
    settings.line_ending = profile.line_ending;
    settings.boot_markers = profile.reboot_markers;
    settings.boot_complete_markers = profile.boot_complete_markers;
    settings.ready_markers = profile.ready_markers;
    settings.budget = budget;
    if (profile.prompt_known()) {
        settings.expected = "the console's prompt (" + std::string(profile.root_prompt) + " at the root, " +
                            std::string(profile.motor_prompt) + " in the motor menu, or another submenu's)";
    } else {
        // Undocumented prompts: `?` lists the menu on every variant (docs/firmware.md 2, 8.1).
        settings.probe_command = "?";
        settings.expected = "a prompt (WORD>) after a line ending, or the same answer to ? twice";
    }
    settings.usual_baud = usual_baud_text(profile);
    return settings;
}

ConsoleSynchroniser::ConsoleSynchroniser(Transport& transport, SyncSettings settings, LogSink log, DishClock clock)
    : transport_(transport),
      settings_(std::move(settings)),
      log_(std::move(log)),
      clock_(std::move(clock)),
      next_progress_(settings_.progress_interval) {}

Clock::time_point ConsoleSynchroniser::now() const {
    return std::max(clock_.now(), virtual_now_);
}

ConsoleSynchroniser::Heard ConsoleSynchroniser::collect(std::chrono::milliseconds first_byte_within,
                                                        std::chrono::milliseconds gap, Clock::time_point limit) {
    Heard heard;
    std::array<char, 512> buffer{};
    Clock::time_point wait_until = std::min(limit, now() + first_byte_within);
    // The line being received: where it starts, its printable and its noise bytes.
    std::size_t line_start = 0;
    std::size_t line_text = 0;
    std::size_t line_noise = 0;
    std::size_t lines_end = 0;  // the end of the last line of text
    for (;;) {
        const auto got = transport_.read(buffer.data(), buffer.size(), wait_until);
        if (!got) {
            if (got.status.code != Errc::timeout) {
                heard.failed = true;
                heard.failure = got.status;
                return heard;
            }
            virtual_now_ = std::max(virtual_now_, wait_until);
            return heard;
        }
        const std::string_view bytes(buffer.data(), got.value);
        emit(log_, LogLevel::trace, "RES " + escape_bytes(bytes));
        heard.raw.append(bytes);
        // Only the console's text keeps a reply open: a line of text when its line ending arrives,
        // or a clean prompt being the line so far. Line noise never does, however long it lasts,
        // so "quiet" comes on a line that is never silent.
        bool spoke = false;
        for (std::size_t i = heard.raw.size() - bytes.size(); i < heard.raw.size(); ++i) {
            const char c = heard.raw[i];
            if (is_line_end(c)) {
                const std::string_view ended = std::string_view(heard.raw).substr(line_start, i - line_start);
                if (const std::size_t prompt = prompt_before_noise(ended)) {
                    lines_end = line_start + prompt;  // a prompt after the ready line: at the root, as it says
                } else if (is_text_line(line_text, line_noise)) {
                    lines_end = i + 1;
                    spoke = true;
                    heard.ready_line_last = contains_any(ended, settings_.ready_markers);
                }
                line_start = i + 1;
                line_text = 0;
                line_noise = 0;
            } else if (is_text_byte(static_cast<unsigned char>(c))) {
                ++line_text;
            } else {
                ++line_noise;
            }
        }
        // Where the text ends within the line being received: a clean line is text (a prompt, or
        // a line still arriving, which hides any prompt before it); a prompt followed by noise
        // bytes is the prompt (a dish never prints an unprintable byte, so its prompt ended
        // there, as the framer's rule 3c says); other lines count as for is_text_line.
        const std::string_view line = std::string_view(heard.raw).substr(line_start);
        const std::size_t previous_end = heard.text_end;
        heard.text_end = lines_end;
        if (line_noise == 0 && line_text > 0) {
            heard.text_end = heard.raw.size();
            spoke = spoke || looks_like_prompt(line);
        } else if (const std::size_t prompt = line_noise > 0 ? prompt_before_noise(line) : 0) {
            heard.text_end = line_start + prompt;
            spoke = spoke || heard.text_end > previous_end;
        } else if (is_text_line(line_text, line_noise)) {
            heard.text_end = heard.raw.size();
        }
        if (line_text > 0 && !looks_like_prompt(std::string_view(heard.raw).substr(line_start))) {
            heard.ready_line_last = false;  // more text follows the ready line
        }
        // The dish has just booted and takes input: every moment waited now lets its TV search
        // swing it further.
        if (heard.ready_line_last) {
            return heard;
        }
        if (spoke) {
            wait_until = std::min(limit, now() + gap);
        }
        if (now() >= limit) {
            return heard;
        }
    }
}

bool ConsoleSynchroniser::booting() const {
    return boot_in_progress_;
}

void ConsoleSynchroniser::end_boot_on(const std::string& answer, const std::string& last_boot_line) {
    if (!booting()) {
        return;
    }
    boot_in_progress_ = false;
    emit(log_, LogLevel::verbose,
         "the console answered " + answer + " after a quiet line: the dish has booted (its last boot output \"" +
             escape_bytes(last_boot_line) + "\" was no completion line we know)");
}

void ConsoleSynchroniser::absorb(std::string_view raw, ConsoleSnapshot& snapshot) {
    if (raw.empty()) {
        return;
    }
    for (char c : raw) {
        if (!is_line_end(c) && !is_text_byte(static_cast<unsigned char>(c))) {
            ++noise_bytes_;
        }
    }
    bytes_heard_ += raw.size();
    recent_.append(raw);
    if (recent_.size() > recent_limit) {
        recent_.erase(0, recent_.size() - recent_limit);
    }
    for (std::string& line : printable_lines(raw)) {
        const bool complete = contains_any(line, settings_.boot_complete_markers);
        if (complete || contains_any(line, settings_.boot_markers)) {
            boot_in_progress_ = !complete;
            snapshot.boot_heard = true;
            snapshot.last_boot_line = line;
            emit(log_, LogLevel::verbose, "dish boot output: " + line);
        }
        snapshot.heard.push_back(std::move(line));
    }
    check_baud(raw);
}

void ConsoleSynchroniser::check_baud(std::string_view raw) {
    if (baud_warned_) {
        return;
    }
    const std::string_view sample =
        std::string_view(recent_).substr(recent_.size() > baud_sample ? recent_.size() - baud_sample : 0);
    if (!looks_like_wrong_baud(sample) && !looks_like_wrong_baud(raw)) {
        return;
    }
    baud_warned_ = true;
    emit(log_, LogLevel::warning,
         "the console's replies look like a wrong baud rate (" + std::to_string(noise_bytes_) + " of " +
             std::to_string(bytes_heard_) + " bytes unprintable, e.g. \"" + escape_bytes(sample.substr(0, 48)) + "\")" +
             (settings_.usual_baud.empty()
                  ? std::string()
                  : "; this dish usually runs at " + settings_.usual_baud + " baud (rotctld -s)") +
             "; also check the wiring (a swapped RX pair garbles at the right rate)");
}

Status ConsoleSynchroniser::write(std::string_view bytes) {
    emit(log_, LogLevel::trace, "CMD " + escape_bytes(bytes));
    return transport_.write(bytes, now() + settings_.reply_window);
}

// What the console has shown so far, for the waiting messages: they must never say "nothing"
// of a console that printed its boot log or answers every poke with a prompt not recognised.
std::string ConsoleSynchroniser::shown_so_far(const ConsoleSnapshot& snapshot) const {
    std::string shown = snapshot.last_boot_line.empty()
                            ? std::string("no boot output")
                            : "last boot output \"" + escape_bytes(snapshot.last_boot_line) + "\"";
    const std::string last = quoted_tail(recent_, 1);
    if (last.empty()) {
        return shown + ", nothing else heard";
    }
    if (snapshot.last_boot_line.empty() || last != "\"" + escape_bytes(snapshot.last_boot_line) + "\"") {
        shown += "; the console last showed " + last;
    }
    if (pokes_ > 0) {
        shown += "; " + std::to_string(answered_pokes_) + " of " + std::to_string(pokes_) + " pokes answered";
    }
    return shown;
}

void ConsoleSynchroniser::report_progress(const ConsoleSnapshot& snapshot, Clock::time_point started) {
    const auto elapsed = std::chrono::duration_cast<std::chrono::milliseconds>(now() - started);
    if (!announced_wait_) {
        announced_wait_ = true;
        std::string what;
        if (!snapshot.last_boot_line.empty()) {
            what = "the dish is booting (\"" + escape_bytes(snapshot.last_boot_line) + "\"); waiting for it to finish";
        } else if (const std::string last = quoted_tail(recent_, 1); !last.empty()) {
            what = "the console shows no prompt confirmed yet (it last showed " + last + "); waiting for one";
        } else {
            what = "the console does not answer yet; waiting for the dish to finish booting";
        }
        emit(log_, LogLevel::warning, what + " (up to " + seconds_text(settings_.budget) + ")");
        return;
    }
    if (elapsed < next_progress_) {
        return;
    }
    // The milestone crossed (30 s, 60 s, ...): the rounds between reports are not aligned to it.
    std::chrono::milliseconds milestone{0};
    while (next_progress_ <= elapsed) {
        milestone = next_progress_;
        next_progress_ += settings_.progress_interval;
    }
    emit(log_, LogLevel::warning,
         "still waiting for the dish to boot: " + seconds_text(milestone) + "; " + shown_so_far(snapshot));
}

Status ConsoleSynchroniser::give_up(const ConsoleSnapshot& snapshot, std::string_view why) const {
    std::string seen = quoted_tail(recent_, lines_quoted);
    if (seen.empty()) {
        seen = "nothing (the line stayed silent: check power, wiring and baud" +
               (settings_.usual_baud.empty() ? std::string() : ", usually " + settings_.usual_baud) + ")";
    } else if (noise_bytes_ > 0) {
        seen += " (" + std::to_string(noise_bytes_) + " of " + std::to_string(bytes_heard_) + " bytes unprintable)";
    }
    return Status{Errc::timeout, std::string(why) + " within " + seconds_text(snapshot.waited) + ": expected " +
                                     settings_.expected + "; the console showed " + seen};
}

Result<ConsoleSnapshot> ConsoleSynchroniser::synchronise() {
    ConsoleSnapshot snapshot;
    const Clock::time_point started = now();
    // However small the budget (a recovery slice), a console that is up gets its chance: three
    // rounds of quiet, poke and reply confirm a prompt even if the first reply was stale.
    const auto floor = 3 * (settings_.quiet_gap + settings_.reply_window + settings_.quiet_gap);
    const Clock::time_point limit =
        started + std::max(settings_.budget, std::chrono::duration_cast<std::chrono::milliseconds>(floor));
    auto fail_io = [&](const Status& status) { return Result<ConsoleSnapshot>{std::move(snapshot), status}; };
    auto waited = [&] { return std::chrono::duration_cast<std::chrono::milliseconds>(now() - started); };

    // Stale input: evidence (boot lines) but never a prompt.
    Heard stale = collect(0ms, 0ms, now());
    if (stale.failed) {
        return fail_io(stale.failure);
    }
    absorb(stale.raw, snapshot);
    auto ready = [&](const Heard& heard) {
        if (!heard.ready_line_last) {
            return false;
        }
        snapshot.ready_line = snapshot.last_boot_line;
        snapshot.waited = waited();
        emit(log_, LogLevel::verbose,
             "the dish printed its ready line \"" + escape_bytes(snapshot.ready_line) +
                 "\": in sync at its root without a poke, after " + seconds_text(snapshot.waited));
        return true;
    };
    if (ready(stale)) {
        return {std::move(snapshot), Status::ok()};
    }
    if (booting()) {
        report_progress(snapshot, started);  // opened mid-boot: say so at once
    }

    std::string candidate;                  // a prompt seen once; a second poke must end on it too
    std::vector<std::string> probe_answer;  // the probe's reply once; a second must repeat it
    while (now() < limit) {
        // Let the console finish what it is saying; unsolicited output voids a candidate.
        const Heard unsolicited =
            collect(booting() ? settings_.boot_listen : settings_.quiet_gap, settings_.quiet_gap, limit);
        if (unsolicited.failed) {
            return fail_io(unsolicited.failure);
        }
        absorb(unsolicited.raw, snapshot);
        if (ready(unsolicited)) {
            return {std::move(snapshot), Status::ok()};
        }
        if (unsolicited.text_end > 0) {
            candidate.clear();
            probe_answer.clear();
            // A dish that prints its boot log for minutes is waited for too: say so.
            if (booting()) {
                report_progress(snapshot, started);
            }
            continue;
        }
        if (now() >= limit) {
            break;
        }

        if (Status written = write(settings_.line_ending); !written) {
            return fail_io(written);
        }
        const Heard reply = collect(settings_.reply_window, settings_.quiet_gap, limit);
        if (reply.failed) {
            return fail_io(reply.failure);
        }
        ++pokes_;
        answered_pokes_ += reply.text_end > 0 ? 1 : 0;
        absorb(reply.raw, snapshot);
        if (ready(reply)) {
            return {std::move(snapshot), Status::ok()};
        }
        // A prompt counts even while boot output seemed to be in progress: the line was quiet
        // (for boot_listen, when booting) before each of the two pokes, and a booting dish does
        // not answer them. So whatever the last boot line said -- one we do not know may follow
        // the completion marker -- two pokes answered at the same prompt mean the dish is up.
        if (std::string prompt = trailing_prompt(reply.text()); !prompt.empty()) {
            if (prompt == candidate) {
                end_boot_on("two pokes at " + prompt, snapshot.last_boot_line);
                snapshot.prompt = std::move(prompt);
                snapshot.waited = waited();
                emit(log_, LogLevel::verbose,
                     "console in sync at prompt " + snapshot.prompt + " after " + seconds_text(snapshot.waited));
                return {std::move(snapshot), Status::ok()};
            }
            candidate = std::move(prompt);
            continue;
        }
        candidate.clear();

        // While booting this point is reached only after the line was quiet for boot_listen.
        if (!settings_.probe_command.empty()) {
            const std::string probe = std::string(settings_.probe_command) + std::string(settings_.line_ending);
            if (Status written = write(probe); !written) {
                return fail_io(written);
            }
            const Heard answer = collect(settings_.reply_window, settings_.quiet_gap, limit);
            if (answer.failed) {
                return fail_io(answer.failure);
            }
            const std::size_t first_new = snapshot.heard.size();
            absorb(answer.raw, snapshot);
            if (ready(answer)) {
                return {std::move(snapshot), Status::ok()};
            }
            if (std::string prompt = trailing_prompt(answer.text()); !prompt.empty()) {
                candidate = std::move(prompt);  // the next bare line ending confirms it
                continue;
            }
            std::vector<std::string> lines(snapshot.heard.begin() + static_cast<std::ptrdiff_t>(first_new),
                                           snapshot.heard.end());
            lines.erase(std::remove(lines.begin(), lines.end(), std::string(settings_.probe_command)),
                        lines.end());  // the echo
            const bool clean = !lines.empty() && std::none_of(lines.begin(), lines.end(), [&](const std::string& l) {
                return contains_any(l, settings_.boot_markers) || contains_any(l, settings_.boot_complete_markers);
            });
            if (clean && lines == probe_answer) {
                end_boot_on("\"" + std::string(settings_.probe_command) + "\" the same twice", snapshot.last_boot_line);
                snapshot.probe_reply = std::move(lines);
                snapshot.waited = waited();
                emit(log_, LogLevel::verbose,
                     "console in sync without a prompt: \"" + std::string(settings_.probe_command) +
                         "\" answered the same twice, after " + seconds_text(snapshot.waited));
                return {std::move(snapshot), Status::ok()};
            }
            probe_answer = clean ? std::move(lines) : std::vector<std::string>{};
            if (clean) {
                continue;  // ask once more at once
            }
        }
        report_progress(snapshot, started);
    }
    snapshot.waited = waited();
    return {std::move(snapshot), give_up(snapshot, "no prompt confirmed")};
}

}  // namespace birdcage
