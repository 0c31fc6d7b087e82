// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "station.hpp"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace birdcage::tui {

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr auto kPollPeriod = 200ms;
constexpr auto kSignalPeriod = 1s;
constexpr auto kInfoPeriod = 3s;
constexpr int RIG_OK = 0;
const int kLinkLost = rotctl::code(rotctl::Errc::io);
using rotctl::error_text;

std::string seconds_text(std::chrono::milliseconds ms) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f s", static_cast<double>(ms.count()) / 1000.0);
    return text;
}

}  // namespace

std::string describe(const Command& command) {
    char text[96];
    switch (command.kind) {
        case Command::Kind::move:
            std::snprintf(text, sizeof text, "P %.2f %.2f", command.a, command.b);
            return text;
        case Command::Kind::jog:
            std::snprintf(text, sizeof text, "jog %+.2f %+.2f", command.a, command.b);
            return text;
        case Command::Kind::stop:
            return "S (stop)";
        case Command::Kind::park:
            return "K (park)";
        case Command::Kind::home:
            return "R (home)";
        case Command::Kind::set_level:
            std::snprintf(text, sizeof text, "V %s %g", command.name.c_str(), command.a);
            return text;
    }
    return "?";
}

std::string out_of_range(const Limits& limits, double az, double el) {
    char text[128];
    if (!(az >= limits.min_az && az <= limits.max_az)) {
        std::snprintf(text, sizeof text, "az %.2f is outside %.2f..%.2f", az, limits.min_az, limits.max_az);
        return text;
    }
    if (!(el >= limits.min_el && el <= limits.max_el)) {
        std::snprintf(text, sizeof text, "el %.2f is outside %.2f..%.2f", el, limits.min_el, limits.max_el);
        return text;
    }
    return {};
}

Station::Station(std::string host, int port) : client_(std::move(host), port), address_(client_.address()) {
    snapshot_.link_detail = "connecting to rotctld at " + address_;
    worker_ = std::thread([this] { run(); });
}

Station::~Station() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    client_.interrupt();  // quitting must not wait for a rotctld that does not answer
    worker_.join();
}

Snapshot Station::snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return snapshot_;
}

void Station::submit(Command command) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        // A stop goes before anything still waiting: it is what the user wants now.
        if (command.kind == Command::Kind::stop) {
            queue_.clear();
        }
        queue_.push_back(std::move(command));
    }
    wake_.notify_all();
}

void Station::watch_signal(bool on) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        signal_wanted_ = on;
    }
    wake_.notify_all();
}

template <class F>
void Station::update(F&& change) {
    std::lock_guard<std::mutex> lock(mutex_);
    change(snapshot_);
    ++snapshot_.revision;
}

void Station::wait_for(std::chrono::milliseconds period) {
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait_for(lock, period, [this] { return stopping_ || !queue_.empty(); });
}

void Station::run() {
    for (;;) {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (stopping_) {
                return;
            }
        }
        if (!client_.connected()) {
            connect_once();
            continue;
        }
        std::optional<Command> next;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (!queue_.empty()) {
                next = std::move(queue_.front());
                queue_.pop_front();
            }
        }
        if (next) {
            execute(*next);
        } else {
            poll();
            wait_for(kPollPeriod);
        }
    }
}

void Station::connect_once() {
    std::string why;
    if (!client_.connect(&why)) {
        const auto delay = backoff_.next();
        update([&](Snapshot& s) {
            s.link = s.connects == 0 ? LinkState::connecting : LinkState::reconnecting;
            s.link_detail = why + "; retrying in " + seconds_text(delay);
        });
        std::unique_lock<std::mutex> lock(mutex_);
        // Commands typed meanwhile cannot reach the rotator: they are dropped, not replayed later.
        if (!queue_.empty()) {
            const std::string dropped = describe(queue_.back());
            queue_.clear();
            snapshot_.last_result = dropped + ": not sent, rotctld is not connected";
            ++snapshot_.revision;
        }
        wake_.wait_for(lock, delay, [this] { return stopping_; });
        return;
    }
    backoff_.reset();
    last_info_read_ = Clock::now();
    // What does not change while the link stays up: read once per connection.
    std::string info;
    if (client_.get_info(info) != RIG_OK) {
        info.clear();
    }
    RotatorCaps caps;
    (void)client_.get_caps(caps);
    // The range: the caps' (as `\dump_state` announces them where the caps name none), narrowed
    // to the dish's own elevation range where the backend's `_` names it (the MCP server's rule).
    Limits limits;
    if (caps.limits) {
        limits = *caps.limits;
    } else {
        (void)client_.get_limits(limits);
    }
    base_limits_ = limits;
    limits = rotctl::narrowed_by_info(limits, info);
    std::vector<std::string> levels;
    (void)client_.ext_levels(levels);
    if (client_.peer_closed()) {
        client_.disconnect();
        return;
    }
    update([&](Snapshot& s) {
        s.link = LinkState::connected;
        s.link_detail.clear();
        ++s.connects;
        s.info = info;
        s.caps = caps;
        s.limits = limits;
        s.levels = levels;
        s.rssi.reset();
        s.lnb.reset();
        s.signal_error.clear();
    });
}

bool Station::link_lost(int code) {
    if (code == RIG_OK || !client_.peer_closed()) {
        return false;
    }
    client_.disconnect();
    update([&](Snapshot& s) {
        s.link = LinkState::reconnecting;
        s.link_detail = "rotctld closed the connection; reconnecting";
        s.busy.clear();
        // Nothing of the old link is current any more: a restarted rotctld has no target either.
        s.position.reset();
        s.status.reset();
        s.target.reset();
        s.info.clear();
        // Nor is any reading or answer: the signal screen and the message line start empty.
        s.position_error.clear();
        s.rssi.reset();
        s.rssi_trend.clear();
        s.lnb.reset();
        s.signal_error.clear();
        s.last_result.clear();
    });
    return true;
}

void Station::poll() {
    // rotctld gone between two polls: say so now rather than after a call that runs into it.
    if (client_.peer_closed()) {
        link_lost(kLinkLost);
        return;
    }
    // The flags before the position: a leg may end between the two readings, and a position read
    // before flags that say "not moving" could be short of where the dish rests (the MCP server
    // reads in this order for the same reason).
    std::optional<std::string> status;
    if (snapshot().caps.can_status) {
        std::string flags;
        const int status_code = client_.get_status(flags);
        if (link_lost(status_code)) {
            return;
        }
        if (status_code == RIG_OK) {
            status = squeeze_flags(flags);
        }
    }
    double az = 0, el = 0;
    const int code = client_.get_position(az, el);
    if (link_lost(code)) {
        return;
    }
    // `_` describes the state (the Winegard backend's says where the dish is and what it plans):
    // read again every few seconds rather than once.
    std::optional<std::string> info;
    if (Clock::now() - last_info_read_ >= kInfoPeriod) {
        last_info_read_ = Clock::now();
        std::string text;
        const int info_code = client_.get_info(text);
        if (link_lost(info_code)) {
            return;
        }
        if (info_code == RIG_OK) {
            info = text;
        }
    }
    bool read_signal = false;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        const bool has_rssi =
            std::find(snapshot_.levels.begin(), snapshot_.levels.end(), "RSSI") != snapshot_.levels.end();
        read_signal = signal_wanted_ && has_rssi && Clock::now() - last_signal_read_ >= kSignalPeriod;
    }
    std::optional<double> rssi, lnb;
    std::optional<std::string> signal_error;
    if (read_signal) {
        last_signal_read_ = Clock::now();
        double value = 0;
        const int rssi_code = client_.get_level(rotctl::level::rssi, value);
        if (link_lost(rssi_code)) {
            return;
        }
        // A level can be listed and still not answer: the Trav'lers list the G2's levels and
        // have no tuner (-RIG_ENAVAIL).
        signal_error = rssi_code == RIG_OK ? std::string() : error_text(rssi_code);
        if (rssi_code == RIG_OK) {
            rssi = value;
        }
        if (client_.get_level(rotctl::level::lnb, value) == RIG_OK) {
            lnb = value;
        }
    }
    update([&](Snapshot& s) {
        if (code == RIG_OK) {
            s.position = std::make_pair(az, el);
            s.position_error.clear();
        } else {
            s.position_error = error_text(code);
        }
        s.status = status;
        if (info) {
            s.info = *info;
            s.limits = rotctl::narrowed_by_info(base_limits_, *info);
        }
        if (rssi) {
            s.rssi = rssi;
            s.rssi_trend.push_back(*rssi);
            while (s.rssi_trend.size() > kTrendLength) {
                s.rssi_trend.pop_front();
            }
        }
        if (lnb) {
            s.lnb = lnb;
        }
        if (signal_error) {
            s.signal_error = *signal_error;
        }
    });
}

void Station::execute(const Command& command) {
    const std::string what = describe(command);
    if (client_.peer_closed()) {
        link_lost(kLinkLost);
        update([&](Snapshot& s) { s.last_result = what + ": not sent, rotctld closed the connection"; });
        return;
    }
    update([&](Snapshot& s) { s.busy = what; });
    Command sent = command;
    if (command.kind == Command::Kind::jog) {
        sent.kind = Command::Kind::move;
        if (!jog_target(command, sent.a, sent.b)) {
            return;
        }
    }
    if (sent.kind == Command::Kind::move) {
        if (const std::string why = out_of_range(snapshot().limits, sent.a, sent.b); !why.empty()) {
            update([&](Snapshot& s) {
                s.busy.clear();
                s.last_result = describe(sent) + ": refused, " + why;
            });
            return;
        }
    }
    int code = RIG_OK;
    switch (sent.kind) {
        case Command::Kind::jog:
            break;  // made a move above
        case Command::Kind::move:
            code = client_.set_position(sent.a, sent.b);
            break;
        case Command::Kind::stop:
            code = client_.stop();
            break;
        case Command::Kind::park:
            code = client_.park();
            break;
        case Command::Kind::home:
            code = client_.reset();
            break;
        case Command::Kind::set_level:
            code = client_.set_level(command.name, command.a);
            break;
    }
    if (link_lost(code)) {
        update([&](Snapshot& s) { s.last_result = what + ": the link dropped before rotctld answered"; });
        return;
    }
    // `_` says what the rotator makes of the command: read it at the next poll, not seconds later.
    last_info_read_ = {};
    update([&](Snapshot& s) {
        s.busy.clear();
        s.last_result = describe(sent) + ": " + (code == RIG_OK ? std::string("ok") : error_text(code));
        if (sent.kind == Command::Kind::move && code == RIG_OK) {
            s.target = std::make_pair(sent.a, sent.b);
        }
        if ((command.kind == Command::Kind::stop || command.kind == Command::Kind::park ||
             command.kind == Command::Kind::home) &&
            code == RIG_OK) {
            s.target.reset();  // the rotator no longer heads for what this client last sent
        }
        if (command.kind == Command::Kind::set_level && command.name == "LNB" && code == RIG_OK) {
            s.lnb = command.a;
        }
    });
}

bool Station::jog_target(const Command& jog, double& az, double& el) {
    // From where the dish is now, never from a target this client sent earlier: another client
    // (Gpredict, the MCP server) may have moved it since.
    double now_az = 0, now_el = 0;
    const int code = client_.get_position(now_az, now_el);
    if (code != RIG_OK) {
        if (!link_lost(code)) {
            update([&](Snapshot& s) {
                s.busy.clear();
                s.last_result = describe(jog) + ": not sent, p answered " + error_text(code);
            });
        }
        return false;
    }
    az = now_az + jog.a;
    el = now_el + jog.b;
    return true;
}

std::string squeeze_flags(const std::string& flags) {
    // Hamlib 4.5.4 names several flags alike (MOVING_AZ and MOVING_EL are both "MOVING", so a
    // G2 homing reads "BUSY MOVING BUSY MOVING"): each name once.
    std::istringstream words(flags);
    std::vector<std::string> seen;
    std::string text;
    for (std::string w; words >> w;) {
        if (std::find(seen.begin(), seen.end(), w) != seen.end())
            continue;
        seen.push_back(w);
        text += (text.empty() ? "" : " ") + w;
    }
    return text.empty() ? "idle" : text;
}

}  // namespace birdcage::tui
