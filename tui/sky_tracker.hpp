// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The sky screen's side of birdcage-track (docs/sky.md, its machine interface): queries
// (--passes, --visible: one JSON object on stdout) and a track (--json TARGET: one JSON event a
// line) run as child processes, as the scan launcher runs birdcage-skyscan. The TUI computes no
// position itself: what it shows of the sky is what birdcage-track printed.
#pragma once

#include "json_reader.hpp"

#include <sys/types.h>
#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace birdcage::tui {

// What every birdcage-track child is given: the rotctld this TUI uses, the station, the TLEs and,
// for a rehearsal against the emulator, the clock.
struct SkyOptions {
    std::string program = "birdcage-track";
    std::string host = "localhost";
    int port = 4533;
    std::optional<double> lat, lon, alt;  // absent: the child reads BIRDCAGE_LAT/LON/ALT
    std::vector<std::string> tles;
    std::optional<double> at;          // rehearsal: the sky's clock starts here (Unix seconds)...
    std::optional<double> time_scale;  // ...and runs this many times faster
};

// Unix seconds of an ISO 8601 UTC time (YYYY-MM-DDTHH:MM:SS[.fff][Z]); nullopt when it is not one.
std::optional<double> parse_iso_time(const std::string& text);
std::string iso_time(double unix_seconds);

// The instant the sky is computed for: the real clock, or the rehearsal's (SkyOptions::at/time_scale)
// that started with this object.
class SkyClock {
public:
    explicit SkyClock(const SkyOptions& options);
    double now() const;
    // --at/--time-scale for a child, so that it starts where this clock is now.
    std::vector<std::string> args() const;

private:
    std::optional<double> at_, scale_;
    double wall_start_;
    std::chrono::steady_clock::time_point started_;
};

// The options every child gets before its own: --host, --port, the station, --tle, the clock.
std::vector<std::string> sky_common_args(const SkyOptions& options, const SkyClock& clock);

// One child with its stdout and stderr read without blocking.
class Child {
public:
    Child() = default;
    ~Child();
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;

    bool start(const std::string& program, const std::vector<std::string>& args, std::string* why);
    // Complete stdout lines since the last call; notices the exit (exit_status).
    std::vector<std::string> pump();
    void terminate();  // SIGTERM
    bool running() const { return pid_ > 0; }

    std::optional<int> exit_status;  // 128+N: signal N
    std::string last_error_line;     // the last line on stderr

private:
    void read_stderr();

    pid_t pid_ = -1;
    int out_ = -1, err_ = -1;
    std::string out_pending_, err_pending_;
};

// A query: `birdcage-track ARGS --json`, one JSON object on stdout at exit.
class SkyQuery {
public:
    bool start(const std::string& program, const std::vector<std::string>& args, std::string* why);
    // True once, when the child has ended (answer or error is then set).
    bool pump();
    bool running() const { return child_.running(); }
    void cancel() { child_.terminate(); }

    std::optional<Json> answer;
    std::string error;  // the program's own message, when it failed

private:
    Child child_;
    std::string text_;
};

struct VisibleTarget {
    std::string name, kind;
    double az = 0, el = 0;
    bool in_window = false;
};
struct PassTimes {
    std::string aos, tca, los;
    double max_el = 0, aos_az = 0, tca_az = 0, los_az = 0, duration_s = 0;
};
// The targets of a --visible answer, highest first; the passes of a --passes answer.
std::vector<VisibleTarget> visible_targets(const Json& answer);
std::vector<PassTimes> passes(const Json& answer);

// What a track's events said so far.
struct TrackState {
    std::string target;  // as asked; the plan's name once known
    std::string phase;   // starting, waiting, tracking; once ended: the end's outcome (los, interrupted, ...)
    std::optional<std::string> aos, los;
    std::optional<double> max_el;
    std::optional<double> seconds_to_aos, seconds_to_los;
    std::optional<std::pair<double, double>> aim, target_position, dish_position;
    std::optional<double> error_deg;
    std::string reason;  // the end's reason, or the program's message when it failed
    std::optional<double> rms_error_deg, max_error_deg;
    int samples = 0;
    bool parked = false;
    bool stopped = false;  // ended by cancel()
    std::optional<int> exit_status;
};

// A track: `birdcage-track ... --json TARGET`, followed event by event.
class Tracker : public TrackState {
public:
    bool start(const std::string& program, const std::vector<std::string>& args, const std::string& target,
               std::string* why);
    void pump();
    // SIGTERM: birdcage-track stops sending, sends `S`, prints its end event.
    void cancel();
    bool running() const { return child_.running(); }
    bool started() const { return !target.empty(); }
    // Applies one JSON line (plan, wait, progress, end); false when it is none of them.
    bool take(const std::string& line);

private:
    Child child_;
};

// Where the TUI finds a program of the tools: beside this program (an install or a build tree puts
// them in one directory), in the build tree's `build_dir` (relative to this program's), else on PATH.
std::string tool_program(const std::string& argv0, const std::string& name, const std::string& build_dir);

}  // namespace birdcage::tui
