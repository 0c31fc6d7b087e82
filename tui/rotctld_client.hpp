// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A client of one rotctld, for any Hamlib rotator: Hamlib's own NET rotator (model 2) for what it
// can ask, rotctld's text protocol on a second TCP connection for what it cannot (a backend's
// extension levels, which the NET client looks up in its own caps and refuses; the status and
// the caps, which Hamlib 4.5's NET client does not ask for; `_`, which it cuts at 64 bytes).
//
// No `\get_conf`: Hamlib 4.5.4's rotctld does not have it, and it reads an unknown long command
// as a string of one-letter commands (`\get_conf nope` answers with the position, from its `p`).
// The Winegard backend's `_` states the conf values in force instead.
// Blocking calls, one thread; Station (station.hpp) runs it beside the screen.
#pragma once

#include <atomic>
#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

struct s_rot;

namespace birdcage::tui {

struct Limits {
    double min_az = 0, max_az = 360, min_el = 0, max_el = 90;
};

// What `\dump_caps` says about the rotator behind rotctld.
struct RotatorCaps {
    std::string model;          // "Winegard Carryout G2"
    std::string backend;        // "Winegard birdcage 0.1.0"
    bool can_park = false;
    bool can_reset = false;     // `R`: the Winegard backend homes the axes
    bool can_status = false;
    struct Level {
        std::string name, label, range;   // "LNB", "LNB supply (V)", "13..18/5"
    };
    std::vector<Level> levels;            // the backend's extension levels
};

// One reply of rotctld's extended protocol (`+cmd`): the value lines and the RPRT code.
struct Reply {
    int code = 0;                       // 0 or -RIG_E*
    std::vector<std::string> values;    // "Key: value" lines with the key removed
};

class RotctldClient {
public:
    RotctldClient(std::string host, int port, std::chrono::milliseconds timeout = std::chrono::seconds(30));
    ~RotctldClient();
    RotctldClient(const RotctldClient&) = delete;
    RotctldClient& operator=(const RotctldClient&) = delete;

    // Opens both connections; on failure says why and leaves nothing open.
    bool connect(std::string* why);
    void disconnect();
    bool connected() const { return rot_ != nullptr && text_fd_ >= 0; }
    // From another thread: makes a call blocked on rotctld return at once (the link is then lost).
    void interrupt();
    // rotctld closed either connection (it exited or restarted): the link must be opened again.
    bool peer_closed() const;
    const std::string& address() const { return address_; }

    // Through Hamlib's NET rotator; each returns RIG_OK or -RIG_E*.
    int get_position(double& az, double& el);
    int set_position(double az, double el);
    int stop();
    int park();
    int reset();
    Limits limits() const;   // what rotctld's \dump_state announced at connect

    // Through the text protocol.
    int get_status(std::string& flags);                 // `s`: the flags' names, empty when idle
    std::string get_info(int& code);                    // `_`
    RotatorCaps caps();                                 // `\dump_caps`
    std::optional<std::vector<std::string>> ext_levels();   // `v ?`: nullopt when none
    int get_level(const std::string& name, double& value);
    int set_level(const std::string& name, double value);
    // Sends `+command` and reads its extended reply up to the RPRT line.
    Reply ask(const std::string& command);
    // The same, the value lines as they came ("Key: value").
    Reply ask_lines(const std::string& command);

private:
    bool text_connect(std::string* why);
    bool read_line(std::string& line);

    std::string host_;
    int port_;
    std::string address_;
    std::chrono::milliseconds timeout_;
    s_rot* rot_ = nullptr;
    int text_fd_ = -1;
    std::string pending_;
    bool probing_ = false;   // the first question of a connection: a short deadline
    std::atomic<int> open_fds_[2] = {-1, -1};   // for interrupt(): the Hamlib and text sockets
};

// Hamlib's one-line text for -RIG_E* `code`.
std::string error_text(int code);

// The status flags as shown: repeated names once, "idle" for none.
std::string squeeze_flags(const std::string& flags);

} // namespace birdcage::tui
