// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The one C++ client of rotctld (as gpsd's clients share libgps): the TUI, the sky scan, the
// benchmark's Gpredict-like client and the end-to-end tests speak rotctld through it.
//
// One TCP connection, blocking calls with a deadline, one thread at a time (interrupt() may come
// from another). Errors are Hamlib's codes (0 or -RIG_E*, see rotctl_protocol.hpp); a lost or
// out-of-step link reads -RIG_EIO and closes the connection, and connect() or reconnect() opens
// it again.
//
// No `\get_conf`: Hamlib 4.5.4's rotctld does not have it, and it reads an unknown long command as
// a string of one-letter commands (`\get_conf nope` answers with the position, from its `p`).
#pragma once

#include "rotctl_protocol.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace birdcage::rotctl {

// The Winegard backend's extension levels (docs/receiver.md).
namespace level {
inline constexpr const char* rssi = "RSSI";
inline constexpr const char* rssi_samples = "RSSI_SAMPLES";
inline constexpr const char* lnb = "LNB";
}  // namespace level

struct Options {
    Protocol protocol = Protocol::extended;
    // A reply can take long (a homing `R`, another client's long RSSI reading).
    std::chrono::milliseconds timeout = std::chrono::seconds(30);
    // Connecting, and the first question on a new connection: something else listening there (or
    // a host that is down) must not hold the caller for the kernel's minutes of SYN retries.
    std::chrono::milliseconds connect_timeout = std::chrono::seconds(3);
    // Ask `p` right after connecting, to tell a rotctld from something else listening there.
    bool probe = true;
};

// Delays between reconnection attempts: doubling from `first` up to `most`.
class Backoff {
public:
    explicit Backoff(std::chrono::milliseconds first = std::chrono::milliseconds(250),
                     std::chrono::milliseconds most = std::chrono::seconds(5))
        : first_(first), most_(most), next_(first) {}
    std::chrono::milliseconds next();
    void reset() { next_ = first_; }

private:
    std::chrono::milliseconds first_, most_, next_;
};

class Client {
public:
    Client(std::string host, int port, Options options = {});
    ~Client();
    Client(const Client&) = delete;
    Client& operator=(const Client&) = delete;

    // Opens the connection; on failure says why and leaves nothing open.
    bool connect(std::string* why = nullptr);
    // connect() until it succeeds, waiting backoff's delays between attempts through `wait`, which
    // returns false to give up (the caller is quitting).
    bool reconnect(Backoff& backoff, const std::function<bool(std::chrono::milliseconds)>& wait,
                   std::string* why = nullptr);
    void disconnect();
    bool connected() const { return fd_ >= 0; }
    // From another thread: makes a blocked call return at once (the connection is then lost).
    void interrupt();
    // rotctld closed the connection (it exited or restarted): it must be opened again.
    bool peer_closed() const;
    const std::string& address() const { return address_; }
    const Options& options() const { return options_; }
    void set_timeout(std::chrono::milliseconds timeout) { options_.timeout = timeout; }

    // One command in the configured protocol; `shape` tells where a plain reply ends.
    Reply ask(const std::string& command, Shape shape = Shape::values(0));
    // One command in the plain protocol, whatever the configured one (the long commands, which
    // Hamlib 4.5.4's rotctld does not take after `+`).
    Reply ask_plain(const std::string& command, Shape shape);
    // Bytes as they are, and raw lines back: for tests of rotctld's own framing.
    bool send_raw(const std::string& bytes);
    // Up to `lines` whole lines (fewer at the deadline or when the peer closes), each with its '\n'.
    std::string read_lines(int lines, std::chrono::milliseconds timeout);

    // The commands, each returning 0 or -RIG_E*.
    int get_position(double& az, double& el);               // p
    int set_position(double az, double el);                 // P (%.2f, as Gpredict sends)
    int stop();                                             // S
    int park();                                             // K
    int reset(int what = 1);                                // R (1: all axes)
    int get_status(std::string& flags);                     // s: the flags' names, empty when idle
    int get_info(std::string& info);                        // _
    int get_limits(Limits& limits);                         // \dump_state
    int get_caps(Caps& caps);                               // \dump_caps
    int ext_levels(std::vector<std::string>& names);        // v ?
    int get_level(const std::string& name, double& value);  // v NAME
    int set_level(const std::string& name, double value);   // V NAME value

private:
    bool open_socket(std::string* why);
    bool fill(std::chrono::steady_clock::time_point deadline);
    Reply exchange(const std::string& line, Protocol protocol, Shape shape);
    Reply lost();
    int ask_text(const std::string& command, std::string& text);  // one line's value

    std::string host_;
    int port_;
    std::string address_;
    Options options_;
    int fd_ = -1;
    std::atomic<int> open_fd_{-1};  // for interrupt()
    std::string pending_;
    bool probing_ = false;
};

}  // namespace birdcage::rotctl
