// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A scripted stand-in for a dish console: records what the core writes and plays back replies.
// Time never passes inside it: a read with nothing queued returns Errc::timeout at once, which the
// Transport contract allows ("timeout at the deadline"), so tests are fast and deterministic.
#pragma once

#include <array>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "console/transport.hpp"

namespace birdcage::test {

class FakeTransport : public Transport {
public:
    // Called for every complete command line written (without its CR); returns the bytes the dish
    // sends back, as chunks (each chunk arrives as one read).
    using Responder = std::function<std::vector<std::string>(const std::string& command)>;

    explicit FakeTransport(Responder responder = {}) : responder_(std::move(responder)) {}

    Status write(std::string_view bytes, Deadline deadline) override;
    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override;
    void discard_input() override { input_.clear(); }

    void push_input(std::string chunk) { input_.push_back(std::move(chunk)); }
    // The chunk arrives after `empty_reads` more reads have found nothing queued (i.e. "later").
    void push_delayed(std::string chunk, int empty_reads) { delayed_.push_back({empty_reads, std::move(chunk)}); }
    void set_responder(Responder responder) { responder_ = std::move(responder); }
    void hang_up() { hung_up_ = true; }

    const std::vector<std::string>& commands() const { return commands_; }
    const std::string& written() const { return written_; }
    std::size_t reads_with_nothing_queued() const { return empty_reads_; }

private:
    Responder responder_;
    std::deque<std::string> input_;
    std::deque<std::pair<int, std::string>> delayed_;
    std::vector<std::string> commands_;
    std::string written_;
    std::string line_;
    bool hung_up_ = false;
    std::size_t empty_reads_ = 0;
};

// A Carryout G2 console: echo, CR LF line ends, `TRK>`/`MOT>` prompts, `a` queries, `a <id> <deg>`
// moves that advance `step_per_query` degrees toward the target on every later `a` query.
struct FakeG2 {
    std::string menu = "TRK";
    double az = 180.0, el = 45.0;
    double target_az = 180.0, target_el = 45.0;
    double step_per_query = 1000.0;  // default: a move is complete at the next query
    bool homed = true;
    bool shell_killed = false;
    std::vector<std::string> extra_lines_after_query;  // e.g. a stall line, played once
    // With a value: `dvb` enters DVB>, whose `dis` lists the channel parameters with this as the
    // LNB row's current value (the real console's `ODU:13V`); `lnbdc odu|stb` sets it.
    std::optional<std::string> lnb_polarity;

    std::vector<std::string> respond(const std::string& command);
};

// A Trav'ler HAL 2.05 console with no prompt: `AZ = .. EL = .. SK = ..` replies, moves as FakeG2;
// `?` lists commands (docs/firmware.md 2: every console lists its menu on `?`).
struct FakeTravler {
    double az = 90.0, el = 30.0;
    double target_az = 90.0, target_el = 30.0;
    double step_per_query = 1000.0;
    bool echo = true;
    // A motor that starts late: an axis at rest sent a move stays put for this many `a` queries.
    int startup_queries = 0;
    std::array<int, 2> queries_until_start{};
    std::vector<std::string> respond(const std::string& command);
};

}  // namespace birdcage::test
