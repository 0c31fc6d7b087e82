// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A client that drives rotctld the way Gpredict 2.3–2.6 does (docs/tracking.md §5,
// docs/tracking.md §1.3 and §3.2), written from that description, on a scaled clock:
//   * a "GUI" timer every `cycle` computes the target: the satellite's position clamped to the
//     configured limits (before AOS: the AOS azimuth at the lowest elevation); only when the
//     read-back position is more than `threshold` away on either axis (plain differences, no
//     wrap) does it post a new target, and then it leads the satellite: a bisection finds the
//     furthest future time at which the satellite is still within `threshold` of where it is now;
//   * an I/O thread loops: `P az el` (%.2f) if a target is pending, sleep 100 ms, `p`, then sleep
//     max(elapsed, 0.7 s). A loop in which `P` or `p` answered an error (or nothing) is an I/O error;
//   * the timer counts its ticks that find the last loop in error, and resets the count on one that
//     does not. A tick that finds an error with the count already at MAX_ERROR_COUNT (5) disengages
//     the rotator: Gpredict sends `S`, stops its I/O thread and never engages again by itself (the
//     user must press Engage), so the rest of the pass is lost (gtk-rot-ctrl.c, docs/gpredict.md).
//   * as Gpredict 2.3's rotator controller (gtk-rot-ctrl.c) does, the timer sees the satellite and
//     the time as the module last computed them (a 300 ms refresh of its own), and the I/O thread
//     hands the "new target" flag back at the end of its loop: a target the timer posts while the
//     thread is between taking the flag and handing it back (its P, 100 ms, its p) is dropped.
//     With a 1 s timer against a ~0.8 s loop, one tick in four can land there: bursts of three
//     targets 0.8 s apart, then 2.4 s of nothing (docs/tracking.md §5). Only the Gpredict client
//     (look_ahead) does this; the simpler client and the oracle keep the plain hand-over.
// Simulated time is the emulator's clock; every client sleep is divided by the emulator's time
// scale, so the client keeps Gpredict's rhythm in simulated seconds.
#pragma once

#include "pass.hpp"

#include <birdcage_sim/emulator.hpp>

#include <atomic>
#include <mutex>
#include <optional>
#include <vector>

namespace bench {

struct ClientSettings {
    double threshold_deg = 5.0;  // Gpredict default
    // The benchmark's oracle: every cycle posts where the satellite is (no threshold, no lead), so
    // the backend's scheduler works from the true trajectory: the floor of what it can do.
    bool true_position_every_cycle = false;
    // false: a simpler client than Gpredict, as a new user may meet one: it sends the satellite's
    // direction as it is now (clamped to its limits) whenever that is more than the threshold from
    // the last target it sent, on either axis, and never reads the dish back for it (no look-ahead,
    // no lead). The backend must learn a lead of 0 from it (docs/tracking.md §6).
    bool look_ahead = true;
    double cycle_s = 1.0;     // Gpredict default "Cycle" 1000 ms
    double io_sleep_s = 0.1;  // between P and p
    double io_min_period_s = 0.7;
    // Gpredict's module refresh (its default, 300 ms): the timer uses the satellite as of the
    // module's last refresh. 0: the satellite at the tick itself.
    double module_refresh_s = 0.3;
    // When the first timer tick comes after the I/O thread starts (GLib's timer and the thread
    // start at unrelated moments; which ticks fall into the thread's hand-over depends on it).
    double timer_offset_s = 0.5;
    // Gpredict's rotator limits (README now advises 0-90 for elevation; the dish's range was the advice before).
    double min_az = 0.0, max_az = 360.0, min_el = 0.0, max_el = 90.0;
    // Gpredict's MAX_ERROR_COUNT: erroring timer ticks tolerated in a row; 0 = never disengage.
    int max_error_count = 5;
};

struct TimedDirection {
    double t;  // pass clock, seconds
    Direction dir;
};

struct ClientRecord {
    std::vector<TimedDirection> sent_targets;  // every P
    std::vector<double> p_round_trip_ms;       // real time
    std::vector<double> set_round_trip_ms;     // real time
    std::vector<double> p_error_deg;           // reported position against the dish's true path
                                               // during the round trip (see distance_to_path)
    struct ReadBack {
        double t;  // pass clock when asked
        Direction reported, true_before, true_after;
    };
    std::vector<ReadBack> read_backs;  // every parsed `p`, for the run's read-back trace
    unsigned failed_replies = 0;
    // Gpredict's view of the errors: timer ticks (cycles) that found the I/O thread in error.
    unsigned erroring_cycles = 0;
    int longest_error_streak = 0;  // most erroring cycles in a row
    bool disengaged = false;       // MAX_ERROR_COUNT was exceeded: tracking stopped
    double disengaged_at = 0.0;    // pass clock
};

class GpredictClient {
public:
    // pass_clock_start: the pass time that the emulator's current sim_time() corresponds to.
    GpredictClient(const Pass& pass, ClientSettings settings, const birdcage::sim::Emulator& dish, double time_scale,
                   int rotctld_port, double pass_clock_start);

    // Runs the timer and I/O threads until the pass clock reaches `end`.
    ClientRecord run_until(double end);

    // Pass clock time that corresponds to an emulator sim time.
    double pass_time_of(double sim_time) const { return sim_time - sim_origin_ + pass_origin_; }

private:
    double pass_now() const;
    void sleep_sim(double seconds) const;
    bool gpredict_timing() const { return settings_.look_ahead && !settings_.true_position_every_cycle; }
    void timer_tick();
    Direction lead_target(double now, Direction current) const;
    void io_loop(double end);

    const Pass& pass_;
    ClientSettings settings_;
    const birdcage::sim::Emulator& dish_;
    double time_scale_;
    int port_;
    double sim_origin_ = 0.0;
    double pass_origin_ = 0.0;
    double engaged_at_ = 0.0;  // pass clock when run_until started: the module refresh's grid

    std::mutex mutex_;  // between the timer and the I/O thread, like Gpredict's client mutex
    Direction read_back_{};
    Direction pending_{};
    std::optional<Direction> last_sent_;  // the no-look-ahead client's last target
    bool new_target_ = false;
    bool io_error_ = false;  // the I/O thread's last loop failed (set by it, read by the timer)
    int error_count_ = 0;    // Gpredict's errcnt
    int error_streak_ = 0;
    bool engaged_ = true;
    std::atomic<bool> stop_{false};
    ClientRecord record_;
};

}  // namespace bench
