// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The rotator as the screen sees it: a worker thread owns the rotctld client (src/client/), polls position and
// status, runs the user's commands one at a time, and reconnects with backoff when rotctld goes
// away. The screen only reads snapshots and queues commands, so a slow reply never freezes it.
#pragma once

#include "rotctl_client.hpp"

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace birdcage::tui {

using Limits = rotctl::Limits;
using RotatorCaps = rotctl::Caps;

enum class LinkState { connecting, connected, reconnecting };

struct Snapshot {
    LinkState link = LinkState::connecting;
    std::string link_detail;  // why the link is down, when the next attempt is
    int connects = 0;         // successful connects so far (more than one: reconnected)

    std::optional<std::pair<double, double>> position;  // az, el
    std::string position_error;                         // rotctld's error for `p`, when it gave one
    std::optional<std::pair<double, double>> target;    // the last position this client sent
    std::optional<std::string> status;                  // `s` flags, when the rotator reports them
    std::string info;                                   // `_`
    Limits limits;
    RotatorCaps caps;
    std::vector<std::string> levels;  // `v ?`; empty: the rotator has no extension levels

    std::optional<double> rssi;
    std::deque<double> rssi_trend;  // oldest first, at most kTrendLength
    std::optional<double> lnb;
    std::string signal_error;  // what `v RSSI` answered instead of a value

    std::string busy;            // the command in flight
    std::string last_result;     // "P 200.00 35.00: ok"; cleared when the link drops
    std::uint64_t revision = 0;  // grows with every change
};

struct Command {
    // move: to (a, b); jog: by (a, b) from where the dish reports it is when the jog runs.
    enum class Kind { move, jog, stop, park, home, set_level } kind;
    double a = 0, b = 0;
    std::string name;
};

// Why (az, el) is not sent to a rotator with these limits ("az 999.00 is outside -180.00..540.00");
// empty when it is within them. The front end refuses such a target, it never clamps it.
std::string out_of_range(const Limits& limits, double az, double el);

class Station {
public:
    static constexpr std::size_t kTrendLength = 240;

    Station(std::string host, int port);
    ~Station();
    Station(const Station&) = delete;
    Station& operator=(const Station&) = delete;

    Snapshot snapshot() const;
    void submit(Command command);
    // The signal screen is showing: read RSSI/LNB about once a second (each reading keeps rotctld
    // busy for a moment, so only while someone looks).
    void watch_signal(bool on);
    const std::string& address() const { return address_; }

private:
    void run();
    void connect_once();
    void poll();
    void execute(const Command& command);
    // The jog's target from a fresh `p`; false (last_result says why) when there is none.
    bool jog_target(const Command& jog, double& az, double& el);
    bool link_lost(int code);
    void wait_for(std::chrono::milliseconds period);
    template <class F>
    void update(F&& change);

    rotctl::Client client_;
    std::string address_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Snapshot snapshot_;
    std::deque<Command> queue_;
    Limits base_limits_;  // the caps' range, before `_` narrows it
    bool signal_wanted_ = false;
    bool stopping_ = false;
    // A restarted rotctld is back within seconds; a longer wait would only delay noticing it.
    rotctl::Backoff backoff_{std::chrono::milliseconds(250), std::chrono::seconds(2)};
    std::chrono::steady_clock::time_point last_signal_read_{};
    std::chrono::steady_clock::time_point last_info_read_{};
    std::thread worker_;
};

std::string describe(const Command& command);

// The status flags as shown: repeated names once, "idle" for none.
std::string squeeze_flags(const std::string& flags);

}  // namespace birdcage::tui
