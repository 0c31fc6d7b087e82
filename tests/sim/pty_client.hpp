// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A tiny client for the emulator's pty, as the backend would open it: raw mode, non-blocking,
// reads bounded by poll deadlines. Test-local (no backend code).
#pragma once

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <utility>

namespace birdcage::sim::testing {

using namespace std::chrono_literals;

class PtyClient {
public:
    explicit PtyClient(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK)) {
        if (fd_ < 0)
            throw std::runtime_error("cannot open " + path);
        termios attributes{};
        ::tcgetattr(fd_, &attributes);
        ::cfmakeraw(&attributes);
        ::tcsetattr(fd_, TCSANOW, &attributes);
    }
    ~PtyClient() { ::close(fd_); }
    PtyClient(const PtyClient&) = delete;
    PtyClient& operator=(const PtyClient&) = delete;

    int fd() const { return fd_; }

    void send(std::string_view bytes) {
        REQUIRE(::write(fd_, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
    }

    // Everything up to and including `needle`; what follows stays buffered. Empty on timeout.
    std::string read_until(std::string_view needle, std::chrono::milliseconds timeout = 5s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        for (;;) {
            const std::size_t found = buffer_.find(needle);
            if (found != std::string::npos) {
                std::string head = buffer_.substr(0, found + needle.size());
                buffer_.erase(0, found + needle.size());
                return head;
            }
            if (!fill_until(deadline))
                return {};
        }
    }

    // Exactly `count` bytes, or fewer if the deadline passes first.
    std::string read_count(std::size_t count, std::chrono::milliseconds timeout = 5s) {
        const auto deadline = std::chrono::steady_clock::now() + timeout;
        while (buffer_.size() < count && fill_until(deadline)) {
        }
        std::string head = buffer_.substr(0, std::min(count, buffer_.size()));
        buffer_.erase(0, head.size());
        return head;
    }

    // Everything that arrives within `duration`.
    std::string read_for(std::chrono::milliseconds duration) {
        const auto deadline = std::chrono::steady_clock::now() + duration;
        while (fill_until(deadline)) {
        }
        return std::exchange(buffer_, {});
    }

    // Everything until the line has been quiet for `quiet` (or `limit` has passed).
    std::string read_until_quiet(std::chrono::milliseconds quiet, std::chrono::milliseconds limit = 10s) {
        const auto end = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < end) {
            const std::size_t before = buffer_.size();
            fill_until(std::chrono::steady_clock::now() + quiet);
            if (buffer_.size() == before)
                break;
        }
        return std::exchange(buffer_, {});
    }

    std::string command(std::string_view line, std::string_view prompt, std::chrono::milliseconds timeout = 5s) {
        send(std::string(line) + "\r");
        return read_until(prompt, timeout);
    }

    // The last poll revents and read result seen by fill_until (for hang-up tests).
    short last_revents = 0;
    ssize_t last_read = 0;
    int last_errno = 0;

private:
    // One poll + read; false when the deadline has passed or the line is hung up.
    bool fill_until(std::chrono::steady_clock::time_point deadline) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        if (left.count() <= 0)
            return false;
        pollfd descriptor{fd_, POLLIN, 0};
        if (::poll(&descriptor, 1, static_cast<int>(left.count())) <= 0)
            return false;
        last_revents = descriptor.revents;
        char chunk[4096];
        last_read = ::read(fd_, chunk, sizeof chunk);
        last_errno = last_read < 0 ? errno : 0;
        if (last_read > 0)
            buffer_.append(chunk, static_cast<std::size_t>(last_read));
        if (last_read == 0 || (last_read < 0 && errno != EAGAIN))
            return false;  // hung up
        return true;
    }

    int fd_;
    std::string buffer_;
};

template <typename Predicate>
bool wait_for(Predicate done, std::chrono::milliseconds timeout = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(1ms);
    }
    return true;
}

}  // namespace birdcage::sim::testing
