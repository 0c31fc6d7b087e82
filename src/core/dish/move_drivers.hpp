// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The two move styles of the variant table (internal to the core; see move_driver.hpp).
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <string>
#include <utility>

#include "dish/move_driver.hpp"
#include "tracking/position_model.hpp"

namespace birdcage {

// Per-axis legs, `a <axis> <deg>` (Trav'lers, G2), one motor at a time, followed by polling the
// position; azimuth legs on the cable-wrap branch the wrap tracker chose, by waypoints.
class AxisLegDriver final : public MoveDriver {
public:
    explicit AxisLegDriver(const MoveContext& context) : c_(context) {}
    void plan(AzEl wanted, AzEl command, const std::optional<AzEl>& previous, double az_rate_dps,
              const std::optional<wrap::PassAhead>& ahead) override;
    Status service() override;
    void cancel() override { pending_.clear(); }
    void reset() override;
    bool idle() const override { return !in_flight_ && pending_.empty(); }
    bool leg_in_flight() const override { return in_flight_.has_value(); }
    MovingAxes moving_axes() const override;
    std::optional<double> azimuth_waypoint() const override;
    bool sync_lost() const override { return false; }
    std::optional<double> learnt_step_seconds(Axis axis) const override;
    MotorTiming learnt_motor() const override;
    void take_learning_from(const MoveDriver& before) override;
    void recovered() override { farther_axis_first_ = true; }
    std::chrono::milliseconds startup_allowance() const override;
    void watch_motion_of_its_own(bool watch) override { watch_motion_ = watch; }
    bool took_motion_of_its_own() override { return std::exchange(moved_on_its_own_, false); }

private:
    static constexpr int max_waypoint_legs = 4;  // bounds the waypoint legs per target (3 span any window)
    struct Leg {
        Axis axis = Axis::azimuth;
        AzEl target;  // the commanded value; only the axis' field counts
        // Azimuth legs: the mechanical azimuth this leg commands (target.az is its display form)
        // and the one the move ends at; they differ while waypoints lead there (wrap::next_waypoint).
        double mech_az = 0.0;
        double final_mech_az = 0.0;
        int waypoints_left = max_waypoint_legs;
        // Azimuth legs, for learning the mapping: where the axis started and the range its readings
        // swept; path_known while the readings came close enough together to follow it.
        double from_mech = 0.0, lowest = 0.0, highest = 0.0;
        bool path_known = false;
        std::optional<double> expected_end;  // where the learnt mapping now says it goes (if not mech_az)
        Clock::time_point sent_at{};
        std::chrono::milliseconds budget{0};
        std::optional<double> last_seen;  // the axis' position at the previous poll
        Clock::time_point last_change{};
        LegMotion motion;       // for the position model (send() starts it, polls add readings)
        bool from_rest = true;  // the axis was not still covering a previous leg when this one was sent
        // Where the axis counts as not yet under way towards this leg's end (mechanical azimuth or
        // elevation): where it stood, or the end of the previous leg it was still covering when
        // that lies on the way; under_way once a poll shows it past that.
        double unmoved_ref = 0.0, under_way_degrees = 0.0;
        bool under_way = false;
        // The other axis' position when this leg was sent, if no leg of the backend's moved it
        // then: the firmware runs one axis at a time, so its motion before this leg is under way is
        // not this leg's.
        std::optional<double> other_still;
        std::optional<double> nearest;  // the nearest the axis has come to this leg's end
        // How long the firmware was still expected to run an earlier leg when this one was sent,
        // and how long it may take at most: `a` queues a motor command behind the motor that is
        // moving (docs/firmware.md §2, §3.4), so this axis cannot start before that is over.
        std::chrono::milliseconds queued_behind{0}, queued_at_most{0};
        std::chrono::milliseconds estimate{0};  // the move's estimated time once the axis runs
    };

    Status send(Leg& leg);
    Status follow();
    bool moves_on_its_own(Leg& leg, AzEl position) const;
    Result<AzEl> poll();
    void plan_azimuth_leg(Leg& leg);
    void observe_azimuth_leg(Leg& leg, bool at_rest);
    void replan_after_surprise();
    double distance(const Leg& leg) const;
    void finish(std::string_view how);
    void record_reading(AzEl position);
    LegMotion motion_of(const Leg& leg) const;
    std::chrono::milliseconds start_allowance(const Leg& leg) const;
    void forget_commands();

    MoveContext c_;
    std::deque<Leg> pending_;
    std::optional<Leg> in_flight_;
    // Per axis, the leg that last arrived: within arrival_tolerance is not at rest, and the axis may
    // still be covering the rest while the other axis' leg runs. Kept until a reading shows it still.
    std::array<std::optional<Leg>, 2> settling_;
    std::optional<Leg>& settling(Axis axis) { return settling_[static_cast<std::size_t>(axis)]; }
    const std::optional<Leg>& settling(Axis axis) const { return settling_[static_cast<std::size_t>(axis)]; }
    // A leg that arrived before its axis was seen to move (the reading was already within the
    // arrival tolerance) is still run by the firmware: it waits out its start-up delay and covers
    // the rest, and the next leg queues behind it. Until when that is expected to last, and at most.
    struct FirmwareBusy {
        Clock::time_point expected{}, at_most{};
    } firmware_busy_;
    AxisPaces paces_;        // how fast the motors ran on earlier legs: a fact about the dish, kept
    StartupDelays startup_;  // how long each motor took to start on earlier legs: likewise
    // How long small legs took from the command to the reading that showed them there: what a
    // step costs on this dish, start-up, motion and polling together (an average over legs). Only
    // legs of a comparable size count: on an acceleration-limited motor the time grows with the
    // root of the distance, and the emulated Trav'ler's 0.1-0.3 deg aims (about 0.5 s) passed for
    // fast beside its 0.5-1 deg client steps (about 1 s), so the pointing mode chosen from them
    // flipped with every change of mode (docs/tracking.md §6).
    static constexpr double small_step_min_deg = 0.4, small_step_max_deg = 2.0;
    StartupDelays step_times_;
    std::optional<Axis> unstarted_stop_;                 // the axis whose last leg was declared stopped before it moved
    std::optional<double> commanded_az_, commanded_el_;  // values last sent (or in flight); az mechanical
    Clock::time_point last_poll_{};
    unsigned move_count_ = 0;
    bool farther_axis_first_ = false;  // set by recovered(), for the next plan only
    bool watch_motion_ = true;         // watch_motion_of_its_own()
    bool moved_on_its_own_ = false;    // took_motion_of_its_own()
};

// The 2003 Carryout's combined `g <az> <el>` in its `target` menu: no position query, only live
// position lines while the move runs (docs/firmware.md 8.3, 8.4), and input during the move may abort
// it (8.5), so the driver listens and never polls. The one place that quirk is handled.
class CombinedMoveDriver final : public MoveDriver {
public:
    explicit CombinedMoveDriver(const MoveContext& context) : c_(context) {}
    void plan(AzEl wanted, AzEl command, const std::optional<AzEl>& previous, double az_rate_dps,
              const std::optional<wrap::PassAhead>& ahead) override;
    Status service() override;
    void cancel() override;
    void reset() override;
    bool idle() const override { return !in_flight_ && !pending_; }
    bool leg_in_flight() const override { return in_flight_.has_value(); }
    MovingAxes moving_axes() const override { return {}; }
    bool sync_lost() const override { return sync_lost_; }

private:
    struct Move {
        AzEl target;
        Clock::time_point sent_at{};
        std::chrono::milliseconds budget{0};
        bool live_seen = false;     // a live position line was printed for this move
        bool needs_motion = false;  // the dish was not already at the target
    };

    Status send(Move move);
    Status follow();
    bool at_target(const AzEl& position) const;
    void end_without_readback(std::string_view how);
    void finish(std::string_view how);
    Status lose_sync(const std::string& why);

    MoveContext c_;
    std::optional<Move> pending_;
    std::optional<Move> in_flight_;
    Clock::time_point last_poll_{};
    // This console prints live positions while `g` runs (a fact about the firmware: kept across
    // re-initialisations); only then can their absence mean anything.
    bool live_output_proven_ = false;
    bool sync_lost_ = false;
};

}  // namespace birdcage
