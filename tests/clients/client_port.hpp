// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The serial side of the upstream clients of docs/firmware.md Appendix C, as pyserial gives it to
// them: read(n) returns at n bytes or when its timeout expires, readline() at LF or on timeout,
// reset_input_buffer() discards what is waiting. Client timeouts are real seconds, as in the
// clients; client pauses (which wait for the dish) are divided by the emulator's time scale.
#pragma once

#include <catch2/catch.hpp>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

namespace birdcage::clients {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

class ClientPort {
public:
    ClientPort(const std::string& path, double time_scale)
        : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK)), time_scale_(time_scale) {
        if (fd_ < 0)
            throw std::runtime_error("cannot open " + path);
        termios attributes{};
        ::tcgetattr(fd_, &attributes);
        ::cfmakeraw(&attributes);
        ::tcsetattr(fd_, TCSANOW, &attributes);
    }
    ~ClientPort() { ::close(fd_); }
    ClientPort(const ClientPort&) = delete;
    ClientPort& operator=(const ClientPort&) = delete;

    // serial.write(): one call, all bytes.
    void write(std::string_view bytes) {
        REQUIRE(::write(fd_, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
        written_ += bytes;
    }

    // serial.read(n) with the port's timeout.
    std::string read(std::size_t count, double timeout_seconds) {
        const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(Seconds(timeout_seconds));
        while (buffer_.size() < count && fill(deadline)) {
        }
        return take(std::min(count, buffer_.size()));
    }

    // serial.readline(): up to and including LF, or what arrived before the timeout.
    std::string readline(double timeout_seconds) {
        const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(Seconds(timeout_seconds));
        for (;;) {
            const std::size_t lf = buffer_.find('\n');
            if (lf != std::string::npos)
                return take(lf + 1);
            if (!fill(deadline))
                return take(buffer_.size());
        }
    }

    // serial.read(1) in a loop until `stop` arrives, each byte with its own timeout (Davidson's
    // transport, §6.6). nullopt if a byte did not come in time.
    std::optional<std::string> read_through(char stop, double per_byte_timeout) {
        std::string reply;
        for (;;) {
            const std::string byte = read(1, per_byte_timeout);
            if (byte.empty())
                return std::nullopt;
            reply += byte;
            if (byte[0] == stop)
                return reply;
        }
    }

    // serial.reset_input_buffer(): what has arrived is discarded.
    void reset_input_buffer() {
        fill(Clock::now());
        buffer_.clear();
    }

    // time.sleep() of the client: it waits for the dish, so it runs at the dish's time scale.
    void client_sleep(double seconds) const { std::this_thread::sleep_for(Seconds(seconds / time_scale_)); }

    const std::string& written() const { return written_; }

private:
    std::string take(std::size_t count) {
        std::string head = buffer_.substr(0, count);
        buffer_.erase(0, count);
        return head;
    }

    // Waits for bytes until `deadline`; reads whatever is there. False when nothing came.
    bool fill(Clock::time_point deadline) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
        pollfd descriptor{fd_, POLLIN, 0};
        if (::poll(&descriptor, 1, static_cast<int>(std::max<long>(0, left.count()))) <= 0)
            return false;
        char chunk[4096];
        const ssize_t count = ::read(fd_, chunk, sizeof chunk);
        if (count <= 0)
            return false;
        buffer_.append(chunk, static_cast<std::size_t>(count));
        return true;
    }

    int fd_;
    double time_scale_;
    std::string buffer_;
    std::string written_;
};

// Python's str(float): shortest round trip, `.0` on whole numbers, `1e-05` style exponents.
inline std::string py_float(double value) {
    char text[64];
    const auto result = std::to_chars(text, text + sizeof text, value);
    std::string out(text, result.ptr);
    if (out.find_first_of(".einf") == std::string::npos)
        out += ".0";
    return out;
}

// Python's int(str): surrounding whitespace allowed, an optional sign, digits only. The clients
// crash on anything else, which the tests report as a failure.
inline std::optional<long> py_int(std::string_view text) {
    const auto first = text.find_first_not_of(" \t\r\n\f\v");
    if (first == std::string_view::npos)
        return std::nullopt;
    text = text.substr(first, text.find_last_not_of(" \t\r\n\f\v") - first + 1);
    const bool negative = text.front() == '-';
    if (text.front() == '+' || text.front() == '-')
        text.remove_prefix(1);
    if (text.empty() || text.find_first_not_of("0123456789") != std::string_view::npos)
        return std::nullopt;
    long value = 0;
    std::from_chars(text.data(), text.data() + text.size(), value);
    return negative ? -value : value;
}

// bytes.decode() with errors='strict' succeeds: here, 7-bit text (the emulator prints ASCII; a
// non-ASCII byte would at best be half of a UTF-8 sequence the clients choke on).
inline bool strict_ascii(std::string_view bytes) {
    for (const char byte : bytes)
        if (static_cast<unsigned char>(byte) >= 0x80)
            return false;
    return true;
}

// str.strip()
inline std::string py_strip(std::string_view text) {
    const auto first = text.find_first_not_of(" \t\r\n\f\v");
    if (first == std::string_view::npos)
        return {};
    return std::string(text.substr(first, text.find_last_not_of(" \t\r\n\f\v") - first + 1));
}

// str.split(' '): single spaces, empty tokens kept.
inline std::vector<std::string> py_split_space(const std::string& text) {
    std::vector<std::string> tokens;
    std::size_t start = 0;
    for (;;) {
        const std::size_t space = text.find(' ', start);
        tokens.push_back(text.substr(start, space == std::string::npos ? std::string::npos : space - start));
        if (space == std::string::npos)
            return tokens;
        start = space + 1;
    }
}

inline std::vector<std::string> regex_all(const std::string& text, const std::regex& pattern) {
    std::vector<std::string> found;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern); it != std::sregex_iterator(); ++it)
        found.push_back(it->str());
    return found;
}

}  // namespace birdcage::clients
