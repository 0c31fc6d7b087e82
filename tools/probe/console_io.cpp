// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "probe/console_io.hpp"

#include <array>
#include <iostream>

#include "console/fd_transport.hpp"
#include "console/serial_port_transport.hpp"
#include "firmware/hazards.hpp"
#include "firmware/menus.hpp"
#include "firmware/prompt.hpp"

namespace probe {
namespace {

using birdcage::Clock;

std::string last_line(std::string_view text) {
    const std::size_t end = text.find_last_of("\r\n");
    return std::string(end == std::string_view::npos ? text : text.substr(end + 1));
}

}  // namespace

std::unique_ptr<birdcage::Transport> open_port(const std::string& path, int baud, bool force_fd, std::string& error) {
    if (!force_fd && !birdcage::is_pseudo_terminal(path)) {
        auto serial = birdcage::SerialPortTransport::open(path, baud);
        if (serial)
            return std::move(serial.value);
        error = serial.status.message;
    }
    auto fd = birdcage::FdTransport::open(path, baud);
    if (fd)
        return std::move(fd.value);
    error += (error.empty() ? "" : "; ") + fd.status.message;
    return nullptr;
}

std::optional<birdcage::PortLock> take_port(const std::string& path) {
    const auto holders = birdcage::other_port_holders(path);
    if (!holders.empty()) {
        std::string who;
        for (const auto& holder : holders)
            who += (who.empty() ? "" : ", ") + std::string("PID ") + std::to_string(holder.pid) +
                   (holder.program.empty() ? "" : " (" + holder.program + ")");
        std::cerr << "birdcage-probe: " << path << " is busy: " << who
                  << " has it open; stop it first (e.g. the rotctld service) so that no two programs talk to the dish "
                     "at once\n";
        return std::nullopt;
    }
    auto lock = birdcage::PortLock::acquire(path);
    if (!lock) {
        std::cerr << "birdcage-probe: " << path << " is busy: " << lock.status.message << '\n';
        return std::nullopt;
    }
    if (!lock.value.note().empty())
        std::cerr << "birdcage-probe: " << lock.value.note() << '\n';
    return std::move(lock.value);
}

std::optional<std::string> trailing_prompt(std::string_view text) {
    std::string line = last_line(text);
    if (!birdcage::prompt_word(line))
        return std::nullopt;
    while (!line.empty() && line.back() == ' ')
        line.pop_back();
    return line;
}

Reply read_reply(birdcage::Transport& port, std::chrono::milliseconds timeout) {
    Reply reply;
    const auto deadline = Clock::now() + timeout;
    std::array<char, 512> buffer{};
    for (;;) {
        const bool prompt_seen = trailing_prompt(reply.raw).has_value();
        const auto wait_until = prompt_seen ? std::min(deadline, Clock::now() + quiet_after_prompt) : deadline;
        const auto got = port.read(buffer.data(), buffer.size(), wait_until);
        if (!got)
            break;
        reply.raw.append(buffer.data(), got.value);
    }
    reply.prompt = trailing_prompt(reply.raw);
    return reply;
}

std::vector<std::string> reply_lines(const Reply& reply, std::string_view command) {
    std::vector<std::string> lines;
    std::string text = reply.raw;
    if (reply.prompt)
        text.resize(text.size() - last_line(text).size());
    std::size_t start = 0;
    bool echo_skipped = command.empty();
    while (start <= text.size()) {
        const std::size_t end = text.find_first_of("\r\n", start);
        std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
        start = end == std::string::npos ? text.size() + 1 : end + 1;
        if (line.empty())
            continue;
        if (!echo_skipped && (line == command || line.ends_with(">" + std::string(command)))) {
            echo_skipped = true;
            continue;
        }
        lines.push_back(line);
    }
    return lines;
}

std::string Guard::refusal(std::string_view command, std::string_view menu) const {
    if (force_)
        return {};
    const auto ruling = birdcage::judge_command(variant_, menu, command, requests_);
    if (!ruling.hazard())
        return {};
    return "refused by the hazard rule: `" + std::string(ruling.word) + "` " +
           std::string(birdcage::hazard_kind_name(ruling.kind)) + " (" + std::string(ruling.reason) + ")";
}

std::string menu_shown_by(std::string_view prompt) {
    if (const auto word = birdcage::prompt_word(prompt)) {
        if (birdcage::is_root_prompt_word(*word))
            return "root";
        if (const auto* menu = birdcage::menu_with_prompt_word(*word))
            return std::string(menu->word);
    }
    return {};  // unknown: the hazard rule applies every menu's rules
}

std::string Probe::menu() const {
    if (const auto known = menu_of_prompt.find(prompt); known != menu_of_prompt.end())
        return known->second;
    return menu_shown_by(prompt);
}

std::optional<Reply> Probe::send(const std::string& command) {
    if (const std::string why = guard.refusal(command, menu()); !why.empty()) {
        refused.emplace_back(command, why);
        return std::nullopt;
    }
    port.discard_input();
    if (!port.write(command + line_ending, Clock::now() + reply_timeout))
        return std::nullopt;
    sent.push_back(command);
    Reply reply = read_reply(port, reply_timeout);
    if (reply.prompt)
        prompt = *reply.prompt;
    return reply;
}

}  // namespace probe
