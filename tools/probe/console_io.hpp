// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe's side of the line: opening the port, reading a reply up to its prompt, and the
// one gate every word passes on its way out (the core's hazard rule, docs/firmware.md §15).
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "console/port_lock.hpp"
#include "console/transport.hpp"
#include "firmware/hazards.hpp"
#include "firmware/variants.hpp"

namespace probe {

using namespace std::chrono_literals;

constexpr auto reply_timeout = 3000ms;     // one command's reply, up to its prompt
constexpr auto quiet_after_prompt = 80ms;  // a prompt only counts if nothing follows it

// libserialport cannot open ptys: ptys (or --fd) get FdTransport; real ports try libserialport
// first and fall back to a plain fd.
std::unique_ptr<birdcage::Transport> open_port(const std::string& path, int baud, bool force_fd, std::string& error);

// The port for this program alone, or nullopt after saying on stderr who holds it: another
// process with the device open (found in /proc: stock rotctld takes no lock), a UUCP lock file
// (/run/lock/LCK..<device>, or $BIRDCAGE_LOCK_DIR) naming a live process, or an flock.
std::optional<birdcage::PortLock> take_port(const std::string& path);

// The unterminated text after the last line ending, when it has a prompt's shape (a decoration,
// a word, `>`; src/core/firmware/menus.hpp), without trailing blanks.
std::optional<std::string> trailing_prompt(std::string_view text);

struct Reply {
    std::string raw;
    std::optional<std::string> prompt;
};
Reply read_reply(birdcage::Transport& port, std::chrono::milliseconds timeout);
// Reply lines without the echo of `command`, the prompt and empty lines.
std::vector<std::string> reply_lines(const Reply& reply, std::string_view command);

// The menu a prompt shows by itself: "root" for a documented root prompt word (`TRK`), the menu's
// word for a documented menu's prompt word (`MOT` -> "mot", `EE` -> "eeprom"), else empty (unknown).
std::string menu_shown_by(std::string_view prompt);

// The one way a word reaches the dish: judged by the core's hazard rule for the menu the console
// is in, asking for nothing (the probe never moves, releases, streams, writes or reboots).
class Guard {
public:
    // variant: what --variant names; nullopt = every variant's rules (the strictest). requests:
    // what the person behind it asks for (the probe: nothing; record: the moves a user types).
    Guard(std::optional<birdcage::VariantId> variant, bool force,
          birdcage::HazardRequests requests = birdcage::request_nothing)
        : variant_(variant), force_(force), requests_(requests) {}
    // Empty when the command may go out; otherwise why not.
    std::string refusal(std::string_view command, std::string_view menu) const;

private:
    std::optional<birdcage::VariantId> variant_;
    bool force_;
    birdcage::HazardRequests requests_;
};

// A console conversation that knows which menu it is in: prompts it has seen are named by the
// menu entered to reach them ("root" for the root prompt); an unnamed prompt is an unknown menu.
struct Probe {
    Probe(birdcage::Transport& transport, const Guard& hazard_guard) : port(transport), guard(hazard_guard) {}

    birdcage::Transport& port;
    const Guard& guard;
    std::string line_ending = "\r";
    std::string prompt;  // the prompt the console showed last
    std::map<std::string, std::string> menu_of_prompt;
    std::vector<std::pair<std::string, std::string>> refused;
    std::vector<std::string> sent;  // every word that went out, in order

    std::string menu() const;
    // Sends `command` if the guard lets it; nullopt when refused (recorded) or the write failed.
    std::optional<Reply> send(const std::string& command);
};

}  // namespace probe
