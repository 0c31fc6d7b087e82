// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "rotctld_client.hpp"

#include "hamlib_compat.h"

#include <hamlib/rotator.h>

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>

namespace birdcage::tui {

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kConnectTimeoutMs = 3000;

// Hamlib writes its debug lines to stderr, which is the screen under curses: they go nowhere.
int discard_debug(enum rig_debug_level_e, rig_ptr_t, const char*, va_list) { return 0; }

void quiet_hamlib() {
    static std::once_flag once;
    std::call_once(once, [] {
        rig_set_debug(RIG_DEBUG_NONE);
        rig_set_debug_callback(discard_debug, nullptr);
    });
}

// The socket's peer has closed it: readable with nothing to read. Between commands rotctld
// sends nothing, so any readable socket here is an end of stream or an error.
bool socket_closed(int fd) {
    if (fd < 0) {
        return true;
    }
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0) {
        return false;
    }
    if ((p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        return true;
    }
    char byte = 0;
    const ssize_t got = ::recv(fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
    return got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
}

} // namespace

std::string error_text(int code) {
    // rigerror2: the message alone (4.5's rigerror appends its debug trace).
    std::string text = rigerror2(code);
    if (const auto nl = text.find_first_of("\r\n"); nl != std::string::npos) {
        text.resize(nl);
    }
    return text;
}

namespace {

std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\r' || s.back() == '\n' || s.back() == ' ' || s.back() == '\t')) {
        s.pop_back();
    }
    std::size_t start = 0;
    while (start < s.size() && (s[start] == ' ' || s[start] == '\t')) {
        ++start;
    }
    return s.substr(start);
}

// "Can Park:\tY" -> true
bool caps_flag(const std::string& line, const char* key, bool& flag) {
    if (line.rfind(key, 0) != 0) {
        return false;
    }
    flag = trim(line.substr(std::strlen(key))) == "Y";
    return true;
}

} // namespace

RotctldClient::RotctldClient(std::string host, int port, std::chrono::milliseconds timeout)
    : host_(std::move(host)), port_(port), timeout_(timeout) {
    address_ = (host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_) + ":" + std::to_string(port_);
    quiet_hamlib();
}

RotctldClient::~RotctldClient() { disconnect(); }

bool RotctldClient::connect(std::string* why) {
    disconnect();
    // The text connection first: when rotctld is not there, its errno says so plainly.
    if (!text_connect(why)) {
        return false;
    }
    // Something else may listen there: a rotctld answers `p` at once (a value or an RPRT line).
    probing_ = true;
    const Reply hello = ask("p");
    probing_ = false;
    if (text_fd_ < 0 || hello.code == -RIG_EIO) {
        *why = "no rotctld answers at " + address_;
        disconnect();
        return false;
    }
    ROT* rot = rot_init(ROT_MODEL_NETROTCTL);
    if (rot == nullptr) {
        *why = "Hamlib has no NET rotator (model 2)";
        disconnect();
        return false;
    }
    rot_set_conf(rot, rot_token_lookup(rot, "rot_pathname"), address_.c_str());
    // A reply can take long (a homing `R`, another client's long RSSI reading): only a dead link
    // should end the wait, and that shows as a closed socket, not as a timeout.
    // Opening is quick with a rotctld: something else listening there must not hold us for long.
    WG_ROTPORT(rot)->timeout = kConnectTimeoutMs;
    WG_ROTPORT(rot)->retry = 0;
    if (const int code = rot_open(rot); code != RIG_OK) {
        *why = "cannot open Hamlib's NET rotator on " + address_ + ": " + error_text(code);
        rot_cleanup(rot);
        disconnect();
        return false;
    }
    WG_ROTPORT(rot)->timeout = static_cast<int>(timeout_.count());
    rot_ = rot;
    open_fds_[0] = WG_ROTPORT(rot)->fd;
    return true;
}

bool RotctldClient::text_connect(std::string* why) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = getaddrinfo(host_.c_str(), std::to_string(port_).c_str(), &hints, &found); rc != 0) {
        *why = std::string("cannot resolve ") + host_ + ": " + gai_strerror(rc);
        return false;
    }
    int error = 0;
    for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
        const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) {
            error = errno;
            continue;
        }
        // Non-blocking, with a deadline: a host that is down would otherwise hold the worker (and
        // so quitting) for the kernel's two minutes of SYN retries.
        ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
        int rc = ::connect(fd, a->ai_addr, a->ai_addrlen);
        if (rc != 0 && errno == EINPROGRESS) {
            pollfd p{fd, POLLOUT, 0};
            if (::poll(&p, 1, kConnectTimeoutMs) == 1) {
                socklen_t length = sizeof error;
                ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length);
                rc = error == 0 ? 0 : -1;
            } else {
                error = ETIMEDOUT;
            }
        } else if (rc != 0) {
            error = errno;
        }
        if (rc == 0) {
            ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
            text_fd_ = fd;
            open_fds_[1] = fd;
            break;
        }
        ::close(fd);
    }
    freeaddrinfo(found);
    if (text_fd_ < 0) {
        *why = std::string("cannot connect to ") + address_ + ": " + std::strerror(error);
        return false;
    }
    pending_.clear();
    return true;
}

void RotctldClient::interrupt() {
    for (auto& fd : open_fds_) {
        if (const int f = fd.load(); f >= 0) {
            ::shutdown(f, SHUT_RDWR);
        }
    }
}

void RotctldClient::disconnect() {
    open_fds_[0] = -1;
    open_fds_[1] = -1;
    if (rot_ != nullptr) {
        rot_close(rot_);
        rot_cleanup(rot_);
        rot_ = nullptr;
    }
    if (text_fd_ >= 0) {
        ::close(text_fd_);
        text_fd_ = -1;
    }
    pending_.clear();
}

bool RotctldClient::peer_closed() const {
    return rot_ == nullptr || socket_closed(WG_ROTPORT(rot_)->fd) || socket_closed(text_fd_);
}

int RotctldClient::get_position(double& az, double& el) {
    if (rot_ == nullptr) return -RIG_EIO;
    azimuth_t a = 0;
    elevation_t e = 0;
    const int code = rot_get_position(rot_, &a, &e);
    if (code == RIG_OK) {
        az = static_cast<double>(a);
        el = static_cast<double>(e);
    }
    return code;
}

int RotctldClient::set_position(double az, double el) {
    if (rot_ == nullptr) return -RIG_EIO;
    return rot_set_position(rot_, static_cast<azimuth_t>(az), static_cast<elevation_t>(el));
}

int RotctldClient::stop() { return rot_ == nullptr ? -RIG_EIO : rot_stop(rot_); }
int RotctldClient::park() { return rot_ == nullptr ? -RIG_EIO : rot_park(rot_); }
int RotctldClient::reset() { return rot_ == nullptr ? -RIG_EIO : rot_reset(rot_, ROT_RESET_ALL); }

std::string RotctldClient::get_info(int& code) {
    // Asked here, not through Hamlib: 4.5.4's NET rotator reads at most 64 bytes of the reply,
    // and the Winegard backend's `_` is a paragraph.
    const Reply r = ask("_");
    code = r.code;
    return r.code == 0 && !r.values.empty() ? r.values.front() : std::string();
}

Limits RotctldClient::limits() const {
    Limits l;
    if (rot_ != nullptr) {
        const auto* state = WG_ROTSTATE(rot_);
        l.min_az = static_cast<double>(state->min_az);
        l.max_az = static_cast<double>(state->max_az);
        l.min_el = static_cast<double>(state->min_el);
        l.max_el = static_cast<double>(state->max_el);
    }
    return l;
}

bool RotctldClient::read_line(std::string& line) {
    const auto deadline = Clock::now() + (probing_ ? std::chrono::milliseconds(kConnectTimeoutMs) : timeout_);
    for (;;) {
        if (const auto nl = pending_.find('\n'); nl != std::string::npos) {
            line = pending_.substr(0, nl);
            pending_.erase(0, nl + 1);
            return true;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) {
            return false;
        }
        pollfd p{text_fd_, POLLIN, 0};
        if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) {
            continue;
        }
        char buffer[1024];
        const ssize_t got = ::recv(text_fd_, buffer, sizeof buffer, 0);
        if (got <= 0) {
            return false;
        }
        pending_.append(buffer, static_cast<std::size_t>(got));
    }
}

Reply RotctldClient::ask(const std::string& command) {
    Reply reply = ask_lines(command);
    for (auto& line : reply.values) {
        if (const auto colon = line.find(':'); colon != std::string::npos) {
            line = trim(line.substr(colon + 1));
        }
    }
    return reply;
}

Reply RotctldClient::ask_lines(const std::string& command) {
    Reply reply;
    if (text_fd_ < 0) {
        reply.code = -RIG_EIO;
        return reply;
    }
    const std::string line = "+" + command + "\n";
    if (::send(text_fd_, line.data(), line.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(line.size())) {
        reply.code = -RIG_EIO;
        return reply;
    }
    // Extended replies: "<command>: <args>", then the value lines, then "RPRT n".
    bool header = true;
    std::string got;
    while (read_line(got)) {
        got = trim(got);
        if (got.rfind("RPRT ", 0) == 0) {
            reply.code = std::atoi(got.c_str() + 5);
            return reply;
        }
        if (header) {
            header = false;
            continue;
        }
        reply.values.push_back(got);
    }
    // Cut off mid-reply: the stream is out of step and can only be reopened.
    open_fds_[1] = -1;
    ::close(text_fd_);
    text_fd_ = -1;
    reply.code = -RIG_EIO;
    return reply;
}

int RotctldClient::get_status(std::string& flags) {
    // Hamlib 4.5's NET rotator has no get_status: asked here. The reply names the flags
    // ("Status flags: MOVING ..."), empty when the rotator is idle.
    const Reply r = ask("s");
    if (r.code == 0) {
        flags = r.values.empty() ? std::string() : r.values.front();
    }
    return r.code;
}

RotatorCaps RotctldClient::caps() {
    RotatorCaps c;
    // Not `+\\dump_caps`: Hamlib 4.5.4's rotctld does not take a long command after `+` and reads
    // the rest of the line as one-letter commands. The plain reply ends with its RPRT line too.
    const std::string line = "\\dump_caps\n";
    if (text_fd_ < 0 || ::send(text_fd_, line.data(), line.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(line.size())) {
        return c;
    }
    std::string got, mfg, model;
    bool in_levels = false;
    while (read_line(got)) {
        got = trim(got);
        if (got.rfind("RPRT ", 0) == 0) {
            break;
        }
        // "Extra levels:", then per level its name alone on a line and "Label:", "Range:" lines.
        if (got.rfind("Extra levels:", 0) == 0) {
            in_levels = true;
            continue;
        }
        if (in_levels && got.find(':') == std::string::npos) {
            c.levels.push_back({got, "", ""});
            continue;
        }
        if (in_levels && !c.levels.empty() && got.rfind("Label:", 0) == 0) c.levels.back().label = trim(got.substr(6));
        if (in_levels && !c.levels.empty() && got.rfind("Range:", 0) == 0) c.levels.back().range = trim(got.substr(6));
        if (in_levels && got.rfind("Get parameters:", 0) == 0) in_levels = false;
        if (got.rfind("Mfg name:", 0) == 0) mfg = trim(got.substr(9));
        if (got.rfind("Model name:", 0) == 0) model = trim(got.substr(11));
        if (got.rfind("Backend version:", 0) == 0) c.backend = trim(got.substr(16));
        caps_flag(got, "Can Park:", c.can_park) || caps_flag(got, "Can Reset:", c.can_reset) ||
            caps_flag(got, "Can get Status:", c.can_status);
    }
    c.model = trim(mfg + " " + model);
    return c;
}

std::optional<std::vector<std::string>> RotctldClient::ext_levels() {
    const Reply r = ask("v ?");
    if (r.code != 0) {
        return std::nullopt;
    }
    std::vector<std::string> names;
    for (const auto& v : r.values) {
        std::istringstream words(v);
        for (std::string w; words >> w;) {
            names.push_back(w);
        }
    }
    if (names.empty()) {
        return std::nullopt;
    }
    return names;
}

int RotctldClient::get_level(const std::string& name, double& value) {
    const Reply r = ask("v " + name);
    if (r.code == 0 && !r.values.empty()) {
        value = std::atof(r.values.back().c_str());
    }
    return r.code == 0 && r.values.empty() ? -RIG_EPROTO : r.code;
}

int RotctldClient::set_level(const std::string& name, double value) {
    char number[32];
    std::snprintf(number, sizeof number, "%g", value);
    return ask("V " + name + " " + number).code;
}

std::string squeeze_flags(const std::string& flags) {
    // Hamlib 4.5.4 names several flags alike (MOVING_AZ and MOVING_EL are both "MOVING", so a
    // G2 homing reads "BUSY MOVING BUSY MOVING"): each name once.
    std::istringstream words(flags);
    std::vector<std::string> seen;
    std::string text;
    for (std::string w; words >> w;) {
        if (std::find(seen.begin(), seen.end(), w) != seen.end()) continue;
        seen.push_back(w);
        text += (text.empty() ? "" : " ") + w;
    }
    return text.empty() ? "idle" : text;
}

} // namespace birdcage::tui
