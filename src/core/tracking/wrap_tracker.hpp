// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The wrap tracker: where the azimuth axis is on its travel (mechanical degrees, cable-wrap turns
// included) while clients and most firmware speak display degrees (0..360), and which mechanical
// branch a display target goes to. Built on the pure arithmetic of wrap.hpp and on what the
// azimuth-mapping learner (az_mapping.hpp) knows of the firmware. Pure: no I/O, times are passed in.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "base/azel.hpp"
#include "base/clock.hpp"
#include "base/log.hpp"
#include "tracking/az_mapping.hpp"
#include "tracking/wrap.hpp"

namespace birdcage {

class WrapTracker {
public:
    // `travel`: the variant's mechanical travel and how numbers are sent for it; `stated`: the
    // user's azimuth mapping (nullopt: learnt).
    WrapTracker(azmap::Travel travel, std::optional<azmap::Mapping> stated, LogSink log);

    // A position reading's azimuth, as the dish reported it (display or mechanical), at `at`.
    // The reply may carry the displayed 0..360 azimuth or the mechanical one (docs/firmware.md §14
    // G2.4): a reading outside 0..360 (twice in a row, inside the travel) proves the latter, and
    // readings are then taken literally; otherwise each is unwrapped to the branch nearest the
    // estimate, which follows the dish as long as it turns less than 180 deg between readings.
    // The first reading's branch is the start assumption (wrap::start_branch()).
    void note_reading(double reported, Clock::time_point at);
    // The mechanical azimuth estimate; nullopt before the first reading.
    std::optional<double> mechanical() const { return mechanical_; }
    std::optional<Clock::time_point> reading_at() const { return reading_at_; }
    unsigned readings() const { return readings_; }  // how many note_reading() calls so far
    // Readings beyond 0..360 proved the dish reports mechanical angles (they name the branch).
    bool reports_mechanical() const { return reports_mechanical_; }
    // A reading that turned out to be line noise is taken back.
    void restore_mechanical(std::optional<double> mechanical) { mechanical_ = mechanical; }
    // After a (re)initialisation: the estimate survives a hang-up or lost sync, not a reboot
    // (which recalibrates and moves the dish); the next reading decides.
    void recheck_branch() { recheck_branch_ = true; }
    // Homing recalibrates the axis: the branch is the start assumption again (G2: AZ 0, 6.4).
    void forget_position() { mechanical_.reset(); }
    // The dish, moving when first read, has come to rest: a branch still only assumed (no reading
    // since named one) is assumed again where it rests, as for a dish read at rest first.
    void judge_branch_at_rest();
    // The branch is the start assumption, not yet confirmed by a reading that has only one branch.
    bool branch_assumed() const { return branch_assumed_; }

    // The mechanical azimuth for `wanted` (see wrap_tracker.cpp for the rule); remembered as
    // target_mechanical(). `leg_end`: where an azimuth leg in flight ends; `commanded`: the
    // mechanical azimuth last commanded.
    // `ahead`: the rest of the pass as a trusted orbit foresees it, if one does.
    double choose_branch(AzEl wanted, const std::optional<AzEl>& previous, double az_rate_dps, double el_min,
                         std::optional<double> leg_end, std::optional<double> commanded,
                         const std::optional<wrap::PassAhead>& ahead = std::nullopt);
    std::optional<double> target_mechanical() const { return target_mechanical_; }
    void set_target_mechanical(std::optional<double> mechanical) { target_mechanical_ = mechanical; }
    void forget_target();

    // The window the firmware's mapping (as far as it is known) lets absolute commands reach.
    wrap::Window plan_window() const { return learner_.plan_window(usable_); }
    double command_value(double mechanical) const { return azmap::command_value(mechanical, travel_); }
    const wrap::Window& window() const { return travel_.window; }
    const azmap::Travel& travel() const { return travel_; }
    azmap::Learner& learner() { return learner_; }
    const azmap::Learner& learner() const { return learner_; }
    // The cable-wrap state in words (see Controller::describe_wrap()).
    std::string describe() const;

private:
    std::optional<double> pass_branch_from_orbit(AzEl wanted, double continuous, const wrap::PassAhead& ahead,
                                                 const wrap::Window& plan);

    azmap::Travel travel_;
    wrap::Window usable_;  // the travel less the limit margins: never commanded outside
    azmap::Learner learner_;
    LogSink log_;
    std::optional<double> mechanical_;
    std::optional<Clock::time_point> reading_at_;
    unsigned readings_ = 0;
    bool reports_mechanical_ = false;
    int beyond_display_readings_ = 0;  // consecutive readings outside 0..360 (2 prove it)
    bool recheck_branch_ = false;
    bool branch_assumed_ = false;
    std::optional<double> target_mechanical_;
    std::optional<int> pass_direction_;  // azimuth direction of the pass being followed (+1/-1)
    double pass_furthest_az_ = 0.0;      // display azimuth of the furthest target along it so far
    // The pass being followed as its targets show it, for the unwind at its culmination.
    struct PassProgress {
        bool seen_from_start = false;  // its first target was near el_min, rising
        double travelled_deg = 0.0;    // azimuth covered so far, in its direction
        double top_el = -90.0;         // the highest target elevation so far
        double travelled_at_top_deg = 0.0;
        // (azimuth travelled, elevation) of the targets within a few degrees of the top: where
        // the culmination lies between sparse targets.
        std::vector<std::pair<double, double>> near_top;
        bool culmination_checked = false;
    };
    PassProgress pass_;
};

}  // namespace birdcage
