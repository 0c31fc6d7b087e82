// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// How the firmware maps an absolute azimuth command onto its mechanical travel — an open question
// (docs/firmware.md §14 G2.4; §2, §3.4, §3.5) that the backend does not bet on: it plans with the most
// permissive reading the evidence still allows and learns from where the dish goes. Pure: no I/O,
// no clock, no variant table.
//
// The readings (the emulator's Options::az_mapping offers the same three, written independently):
//  nearest       a 0..360 number goes to the branch nearest the axis; an in-travel number beyond
//                0..360 is taken as the mechanical angle;
//  literal       the number is the mechanical angle; on a console where '-' makes a relative move
//                (G2, §6.3) and the travel is mostly negative, a number outside the travel names
//                the angle 360 below it;
//  wrap_manager  the axis never passes a wrap point: a number is taken modulo 360 into the
//                360-degree sector between two mechanical angles equal to the wrap point (the one
//                overlapping the travel most), the long way round if need be.
#pragma once

#include <array>
#include <bitset>
#include <optional>
#include <string>
#include <string_view>

#include "tracking/wrap.hpp"

namespace birdcage::azmap {

enum class Mapping { nearest, literal, wrap_manager };
inline constexpr std::array<Mapping, 3> all_mappings{Mapping::nearest, Mapping::literal, Mapping::wrap_manager};
std::string_view mapping_name(Mapping mapping);
std::optional<Mapping> mapping_from_name(std::string_view name);

struct Travel {
    wrap::Window window;                // the mechanical travel
    bool negative_is_relative = false;  // absolute numbers are >= 0: a leading '-' is a relative move
};

// The number sent for mechanical azimuth `mechanical` (two decimals, as the command prints it):
// the angle itself where the console has a number for every angle of the travel (0..455), so that
// a console taking it literally lands on that branch and one that picks the nearest branch does
// too; folded into 0..360 where negative numbers do not exist (never 360.00 then).
double command_value(double mechanical, const Travel& travel);

// The 360-degree sector a wrap manager with its wrap point at display azimuth `wrap_point` keeps
// the axis in (it may reach beyond the travel).
wrap::Window wrap_sector(double wrap_point, const Travel& travel);

// Where an absolute `value` sent with the axis at rest at `from` takes it (clamped into the travel).
double predict(Mapping mapping, double value, double from, const Travel& travel, double wrap_point = 0.0);

// The mechanical azimuths absolute commands can reach under `mapping`.
wrap::Window reachable(Mapping mapping, const Travel& travel, double wrap_point = 0.0);

// One azimuth move as the controller saw it: the number sent, the mechanical azimuth at the start,
// the range the axis swept (readings close enough in time to follow it) and, once it stopped,
// where it stopped.
struct Observation {
    double value = 0.0;
    double from = 0.0;
    double lowest = 0.0, highest = 0.0;
    std::optional<double> end;
};

class Learner {
public:
    // A stated mapping (the user's -C az_mapping) is kept whatever the dish does; contradictions are
    // reported. Without one every reading starts possible.
    explicit Learner(Travel travel, std::optional<Mapping> stated = std::nullopt);

    // Updates the beliefs; returns what changed, in words (for the log), or nullopt.
    std::optional<std::string> observe(const Observation& seen);

    bool possible(Mapping mapping) const;
    std::optional<Mapping> stated() const { return stated_; }
    // The one reading left (or stated); nullopt while several remain.
    std::optional<Mapping> known() const;
    // The reading moves are planned with: the stated one, else the most permissive still possible
    // (nearest, then literal, then wrap_manager): the dish only shows a reading by contradicting it.
    Mapping planning() const;
    // The wrap manager's wrap point when the evidence pins it within 90 degrees (the middle of the
    // candidates), else nullopt.
    std::optional<double> wrap_point() const;
    // `usable` narrowed to what the planning reading can reach. A wrap manager whose point is not
    // pinned yet is assumed at north (§3.5) if that is still possible.
    wrap::Window plan_window(wrap::Window usable) const;
    std::string describe() const;

private:
    bool consistent(Mapping mapping, const Observation& seen, double wrap_point) const;
    // The candidates' circular span: the smallest arc holding them all, as [first, first + span].
    std::optional<std::pair<int, int>> candidate_arc() const;

    Travel travel_;
    std::optional<Mapping> stated_;
    std::array<bool, 3> possible_{true, true, true};
    std::bitset<360> wrap_candidates_;  // whole-degree wrap points (display) still possible
    int contradictions_ = 0;            // observations a stated reading did not explain
};

}  // namespace birdcage::azmap
