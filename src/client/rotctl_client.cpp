// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "rotctl_client.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace birdcage::rotctl {

using Clock = std::chrono::steady_clock;
using std::chrono::milliseconds;

milliseconds Backoff::next() {
    const milliseconds now = next_;
    next_ = std::min(next_ * 2, most_);
    return now;
}

Client::Client(std::string host, int port, Options options) : host_(std::move(host)), port_(port), options_(options) {
    address_ = (host_.find(':') != std::string::npos ? "[" + host_ + "]" : host_) + ":" + std::to_string(port_);
}

Client::~Client() {
    disconnect();
}

bool Client::connect(std::string* why) {
    std::string ignored;
    std::string& reason = why != nullptr ? *why : ignored;
    disconnect();
    if (!open_socket(&reason)) {
        return false;
    }
    if (options_.probe) {
        // A rotctld answers `p` at once (a value or an RPRT line); something else may not.
        probing_ = true;
        const Reply hello = ask("p", Shape::values(2));
        probing_ = false;
        if (!connected() || hello.code == code(Errc::io)) {
            reason = "no rotctld answers at " + address_;
            disconnect();
            return false;
        }
    }
    return true;
}

bool Client::reconnect(Backoff& backoff, const std::function<bool(milliseconds)>& wait, std::string* why) {
    for (;;) {
        if (connect(why)) {
            backoff.reset();
            return true;
        }
        if (!wait(backoff.next())) {
            return false;
        }
    }
}

bool Client::open_socket(std::string* why) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* found = nullptr;
    if (const int rc = getaddrinfo(host_.c_str(), std::to_string(port_).c_str(), &hints, &found); rc != 0) {
        *why = "cannot resolve " + host_ + ": " + gai_strerror(rc);
        return false;
    }
    int error = 0;
    for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
        const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
        if (fd < 0) {
            error = errno;
            continue;
        }
        ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
        int rc = ::connect(fd, a->ai_addr, a->ai_addrlen);
        if (rc != 0 && errno == EINPROGRESS) {
            pollfd p{fd, POLLOUT, 0};
            if (::poll(&p, 1, static_cast<int>(options_.connect_timeout.count())) == 1) {
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
            // One short line a command: Nagle would hold each for the previous reply's ACK.
            const int one = 1;
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            fd_ = fd;
            open_fd_ = fd;
            break;
        }
        ::close(fd);
    }
    freeaddrinfo(found);
    if (fd_ < 0) {
        *why = "cannot connect to " + address_ + ": " + std::strerror(error);
        return false;
    }
    pending_.clear();
    return true;
}

void Client::interrupt() {
    if (const int f = open_fd_.load(); f >= 0) {
        ::shutdown(f, SHUT_RDWR);
    }
}

void Client::disconnect() {
    open_fd_ = -1;
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    pending_.clear();
}

bool Client::peer_closed() const {
    if (fd_ < 0) {
        return true;
    }
    // Between commands rotctld sends nothing: a readable socket is an end of stream or an error.
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 0) <= 0) {
        return false;
    }
    if ((p.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
        return true;
    }
    char byte = 0;
    const ssize_t got = ::recv(fd_, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
    return got == 0 || (got < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
}

bool Client::fill(Clock::time_point deadline) {
    for (;;) {
        const auto left = std::chrono::duration_cast<milliseconds>(deadline - Clock::now());
        if (left.count() <= 0) {
            return false;
        }
        pollfd p{fd_, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
        if (ready < 0 && errno == EINTR) {
            continue;
        }
        if (ready <= 0) {
            return false;
        }
        char buffer[4096];
        const ssize_t got = ::recv(fd_, buffer, sizeof buffer, 0);
        if (got <= 0) {
            return false;
        }
        pending_.append(buffer, static_cast<std::size_t>(got));
        return true;
    }
}

bool Client::send_raw(const std::string& bytes) {
    return fd_ >= 0 && ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
}

std::string Client::read_lines(int lines, milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    auto end_of = [this](int n) {
        std::size_t end = 0;
        for (int i = 0; i < n; ++i) {
            const auto nl = pending_.find('\n', end);
            if (nl == std::string::npos) {
                return std::string::npos;
            }
            end = nl + 1;
        }
        return end;
    };
    while (fd_ >= 0 && end_of(lines) == std::string::npos && fill(deadline)) {
    }
    std::size_t end = end_of(lines);
    if (end == std::string::npos) {
        end = pending_.size();
    }
    std::string out = pending_.substr(0, end);
    pending_.erase(0, end);
    return out;
}

Reply Client::lost() {
    // Cut off mid-reply: the stream is out of step and can only be reopened.
    disconnect();
    Reply r;
    r.code = code(Errc::io);
    return r;
}

Reply Client::exchange(const std::string& line, Protocol protocol, Shape shape) {
    if (!send_raw(line)) {
        return lost();
    }
    const auto deadline = Clock::now() + (probing_ ? options_.connect_timeout : options_.timeout);
    for (;;) {
        if (auto reply = take_reply(pending_, protocol, shape)) {
            return *reply;
        }
        if (!fill(deadline)) {
            return lost();
        }
    }
}

Reply Client::ask(const std::string& command, Shape shape) {
    return exchange(request(command, options_.protocol), options_.protocol, shape);
}

Reply Client::ask_plain(const std::string& command, Shape shape) {
    return exchange(request(command, Protocol::plain), Protocol::plain, shape);
}

int Client::get_position(double& az, double& el) {
    const Reply r = ask("p", Shape::values(2));
    if (!r.ok()) {
        return r.code;
    }
    const auto a = r.lines.size() == 2 ? parse_number(r.lines[0]) : std::nullopt;
    const auto e = r.lines.size() == 2 ? parse_number(r.lines[1]) : std::nullopt;
    if (!a || !e) {
        return code(Errc::proto);
    }
    az = *a;
    el = *e;
    return 0;
}

int Client::set_position(double az, double el) {
    char command[64];
    std::snprintf(command, sizeof command, "P %.2f %.2f", az, el);
    return ask(command).code;
}

int Client::stop() {
    return ask("S").code;
}
int Client::park() {
    return ask("K").code;
}
int Client::reset(int what) {
    return ask("R " + std::to_string(what)).code;
}

int Client::ask_text(const std::string& command, std::string& text) {
    const Reply r = ask(command, Shape::values(1));
    if (r.ok()) {
        const auto v = r.values();
        text = v.empty() ? std::string() : v.front();
    }
    return r.code;
}

int Client::get_status(std::string& flags) {
    return ask_text("s", flags);
}
int Client::get_info(std::string& info) {
    return ask_text("_", info);
}

int Client::get_limits(Limits& limits) {
    const Reply r = ask_plain("\\dump_state", Shape::until_done());
    if (!r.ok()) {
        return r.code;
    }
    const auto parsed = parse_dump_state(r.lines);
    if (!parsed) {
        return code(Errc::proto);
    }
    limits = *parsed;
    return 0;
}

int Client::get_caps(Caps& caps) {
    // Not `+\dump_caps`: Hamlib 4.5.4's rotctld reads the rest of such a line as one-letter
    // commands. The plain reply ends with its RPRT line too.
    const Reply r = ask_plain("\\dump_caps", Shape::until_rprt());
    if (r.ok()) {
        caps = parse_dump_caps(r.lines);
    }
    return r.code;
}

int Client::ext_levels(std::vector<std::string>& names) {
    const Reply r = ask("v ?", Shape::values(1));
    if (r.ok()) {
        names = words(r.lines);
    }
    return r.code;
}

int Client::get_level(const std::string& name, double& value) {
    const Reply r = ask("v " + name, Shape::values(1));
    if (!r.ok()) {
        return r.code;
    }
    const auto v = r.lines.empty() ? std::nullopt : parse_number(r.lines.back());
    if (!v) {
        return code(Errc::proto);
    }
    value = *v;
    return 0;
}

int Client::set_level(const std::string& name, double value) {
    char number[32];
    std::snprintf(number, sizeof number, "%g", value);
    return ask("V " + name + " " + number).code;
}

}  // namespace birdcage::rotctl
