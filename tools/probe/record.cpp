// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "probe/record.hpp"

#include <poll.h>
#include <termios.h>
#include <unistd.h>
#include <algorithm>
#include <array>
#include <fstream>
#include <iostream>

#include "birdcage_sim/transcript.hpp"
#include "probe/console_io.hpp"

namespace probe {
namespace {

using birdcage::Clock;

// Raw mode while recording from a terminal, restored on every exit path.
class RawTerminal {
public:
    RawTerminal() {
        if (!::isatty(STDIN_FILENO) || ::tcgetattr(STDIN_FILENO, &saved_) != 0)
            return;
        termios raw = saved_;
        ::cfmakeraw(&raw);
        raw.c_oflag |= OPOST | ONLCR;  // keep our own messages readable
        active_ = ::tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
    }
    ~RawTerminal() {
        if (active_)
            ::tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
    }
    RawTerminal(const RawTerminal&) = delete;
    RawTerminal& operator=(const RawTerminal&) = delete;
    bool active() const { return active_; }

private:
    termios saved_{};
    bool active_ = false;
};

}  // namespace

int run_record(const std::string& path, int baud, const birdcage::FirmwareProfile& profile,
               std::optional<birdcage::VariantId> rule_variant, bool force_fd, bool force, const std::string& output,
               const std::string& source) {
    auto lock = take_port(path);
    if (!lock)
        return 3;  // busy: said on stderr
    std::string error;
    auto port = open_port(path, baud, force_fd, error);
    if (!port) {
        std::cerr << "birdcage-probe: cannot open " << path << ": " << error << '\n';
        return 1;
    }
    std::ofstream file(output, std::ios::binary);
    if (!file) {
        std::cerr << "birdcage-probe: cannot write " << output << '\n';
        return 1;
    }
    birdcage::sim::TranscriptRecorder transcript(
        {{"Variant", std::string(profile.short_name)},
         {"Firmware", "(fill in: the version the dish reports)"},
         {"Serial", std::to_string(baud) + " 8N1"},
         {"Source", source},
         {"Notes", "(fill in: what the dish was doing, what you typed and why)"}});
    const auto start = Clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

    if (const auto exclusive = lock->make_exclusive(); !exclusive)
        std::cerr << "birdcage-probe: " << exclusive.message << "\r\n";
    // A person typing a well-formed move or homing means it; nothing else the rule names goes out
    // without --force.
    const Guard guard(rule_variant, force, birdcage::request_move | birdcage::request_home);
    const RawTerminal terminal;
    std::cerr << "birdcage-probe: recording " << path << " to " << output
              << (terminal.active() ? " (Ctrl-] to stop)" : "") << "\r\n";
    std::string typed;  // input not yet sent; lines go out whole, after the guard has seen them
    std::string heard;  // dish output, for the prompt the guard judges against
    // Piped input arrives all at once: each line waits for the reply to the previous one (its
    // prompt, or reply_timeout), so the guard judges it in the menu the dish is really in.
    std::optional<Clock::time_point> awaiting_reply_until;
    bool input_open = true;
    std::optional<Clock::time_point> closing_at;
    std::array<char, 512> buffer{};
    for (;;) {
        if (input_open) {
            pollfd stdin_poll{STDIN_FILENO, POLLIN, 0};
            if (::poll(&stdin_poll, 1, 10) > 0) {
                const ssize_t count = ::read(STDIN_FILENO, buffer.data(), buffer.size());
                if (count <= 0)
                    input_open = false;
                const std::string_view bytes(buffer.data(), count > 0 ? static_cast<std::size_t>(count) : 0);
                if (const std::size_t stop = bytes.find('\x1d'); stop != std::string_view::npos) {  // Ctrl-]
                    input_open = false;
                    typed.clear();  // a half-typed line is dropped, not sent
                    closing_at = Clock::now();
                } else {
                    typed.append(bytes);
                }
            }
        }
        if (awaiting_reply_until && Clock::now() >= *awaiting_reply_until)
            awaiting_reply_until.reset();
        const std::size_t line_end = typed.find_first_of("\r\n");
        if (!awaiting_reply_until && line_end != std::string::npos) {
            const std::string line = typed.substr(0, line_end);
            const bool crlf = typed[line_end] == '\r' && line_end + 1 < typed.size() && typed[line_end + 1] == '\n';
            typed.erase(0, line_end + (crlf ? 2 : 1));
            const auto prompt = trailing_prompt(heard);
            if (const std::string why = guard.refusal(line, menu_shown_by(prompt.value_or(""))); !why.empty()) {
                std::cerr << "\r\nbirdcage-probe: not sent: " << why << " (--force sends it)\r\n";
                transcript.comment("refused by birdcage-probe: " + birdcage::sim::escape_chunk(line) + " (" + why +
                                   ")");
            } else {
                const std::string wire = line + std::string(profile.line_ending);
                transcript.add(birdcage::sim::Direction::host_to_dish, wire, seconds());
                heard.clear();
                awaiting_reply_until = Clock::now() + reply_timeout;
                if (!port->write(wire, Clock::now() + 2s)) {
                    std::cerr << "birdcage-probe: write failed\r\n";
                    break;
                }
            }
        }
        if (!input_open && !closing_at && typed.find_first_of("\r\n") == std::string::npos && !awaiting_reply_until)
            closing_at = Clock::now() + 300ms;  // the dish may still be talking
        const auto got = port->read(buffer.data(), buffer.size(), Clock::now() + 10ms);
        if (got) {
            const std::string_view bytes(buffer.data(), got.value);
            transcript.add(birdcage::sim::Direction::dish_to_host, bytes, seconds());
            heard.append(bytes);
            if (heard.size() > 4096)
                heard.erase(0, heard.size() - 4096);
            std::cout.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            std::cout.flush();
            if (trailing_prompt(heard))
                awaiting_reply_until.reset();
            if (closing_at)
                closing_at = std::max(*closing_at, Clock::now() + 300ms);
        } else if (got.status.code != birdcage::Errc::timeout) {
            std::cerr << "\r\nbirdcage-probe: " << got.status.message << "\r\n";
            break;
        }
        if (closing_at && Clock::now() >= *closing_at)
            break;
    }
    file << transcript.text();
    std::cerr << "\r\nbirdcage-probe: wrote " << output << "\r\n";
    return 0;
}

}  // namespace probe
