// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Cable-wrap arithmetic (docs/tracking.md §2.3): which mechanical azimuth ("branch") a 0..360 target
// goes to, and how to steer a firmware that resolves 0..360 azimuths itself onto that branch.
// Pure: no I/O, no clock, no variant table.
//
// Terms. A *display* azimuth is in [0, 360) (what clients send and what `p` reports). A
// *mechanical* azimuth counts cable-wrap turns in the dish's own coordinates; the variant's
// travel (FirmwareProfile::az_min..az_max) is wider than 360 on the Trav'lers (0..455) and the
// G2 (-423.33..+23.33), so some display azimuths have two mechanical branches, 360 apart.
#pragma once

#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace birdcage::wrap {

struct Window {
    double min = 0.0;
    double max = 360.0;
    bool contains(double mechanical) const;  // inclusive, with a 1e-9 tolerance
    double span() const { return max - min; }
};

// Never command within this of a wrap limit (docs/tracking.md §2.3: [wrap_min + 2, wrap_max - 2]).
inline constexpr double limit_margin_deg = 2.0;
// A LEO pass covers at most this much azimuth (the branch chosen at a pass start wants this much
// room ahead of it).
inline constexpr double pass_span_deg = 180.0;
// The longest single azimuth leg: every leg then lands within 180 deg of where the dish is, so a
// firmware that maps a 0..360 command to the nearest branch (or turns the shortest way) ends on
// the intended branch (see next_waypoint()).
inline constexpr double max_leg_deg = 170.0;
// A target this close to el_min, moving, is the start of a pass.
inline constexpr double pass_start_band_deg = 10.0;

// The travel the backend commands within: the mechanical window less limit_margin_deg at each
// end where the window is wide enough to keep every display azimuth reachable (span >= 360 +
// 2 margins); otherwise the largest margin that does (none on a 0..360 window).
Window usable_window(Window mechanical, double margin = limit_margin_deg);

// The azimuth equal to `display` modulo 360 nearest to `reference` (no window). On an exact tie
// (180 deg either way) the clockwise one.
double nearest_branch(double display, double reference);

// Every azimuth equal to `display` modulo 360 inside `window`, ascending.
std::vector<double> branches(double display, Window window);

// A position reading, given as a display azimuth, unwrapped to the branch inside the mechanical
// window (with 1 deg of slack for overshoot) nearest to `reference` (the controller's estimate);
// the nearest branch overall if none is inside.
double unwrap_reading(double display, double reference, Window mechanical);

// The branch assumed for a reading when nothing else is known: the one nearest mechanical 0
// (clamped into the window). The G2 homes to AZ 0 (docs/firmware.md 6.2 item 11, 6.4), so the branch
// nearest 0 is where it is unless something turned it a whole wrap since; on windows that start
// at 0 (Trav'ler 0..455, Carryout 0..360) this is the reading itself.
double start_branch(double display, Window mechanical);

// Degrees of travel left from `mechanical` towards the limit in `direction` (+1 clockwise,
// -1 anticlockwise) inside `window`; 0 for direction 0.
double room_ahead(double mechanical, int direction, Window window);

enum class Reason {
    continuous,     // the branch nearest the previous target (no cable unwind)
    pass_start,     // a pass is starting and the continuous branch lacks room for it
    forced_unwind,  // the continuous branch is beyond the usable window
    no_branch,      // no branch inside the window at all: the nearest window edge
    culmination,    // past its culmination the pass needs more room than its branch has left
    orbit_pass,     // before the pass rises, its orbit shows it needs more room than this branch has
};
std::string_view reason_text(Reason reason);

struct Choice {
    double mechanical;  // the branch to command
    Reason reason;
    double continuous;  // the branch nearest the reference (what continuity alone would pick)
};

// The rest of the pass being followed, as a trusted orbit foresees it (TargetPredictor::pass_ahead()):
// the satellite is above the dish's elevation floor from display azimuth `from_az` on and turns
// `sweep_deg` more azimuth (signed, + clockwise) before it sets below it. `rises_in_s` > 0: it is
// still below the floor and rises there that much later; `culminates_in_s` <= 0: past its culmination.
struct PassAhead {
    double from_az = 0.0;
    double sweep_deg = 0.0;
    double rises_in_s = 0.0;
    double culminates_in_s = 0.0;
};

// The mechanical travel the rest of the pass `ahead` covers if the target `display` goes to branch
// `mechanical` (the target may lie ahead of the satellite by a client's lead, or at the rise
// azimuth before the pass): [lowest, highest].
std::pair<double, double> pass_travel(double display, double mechanical, const PassAhead& ahead);
// How far (degrees) that travel reaches beyond `usable` at either end; 0 when the branch holds it.
double pass_overflow(double display, double mechanical, const PassAhead& ahead, Window usable);
// Among the branches of `display` inside `usable`: the nearest to `reference` that holds the whole
// rest of the pass, else the one it overflows least; nullopt if no branch is inside.
std::optional<double> branch_for_pass(double display, double reference, const PassAhead& ahead, Window usable);

// The mechanical azimuth for `display`:
//  - normally the branch nearest `reference` (continuity) if it lies inside `usable`;
//  - if `pass_starting` and `direction` != 0: among the branches inside `usable`, the one nearest
//    `reference` that has at least pass_span_deg of room ahead in `direction`, else the one with
//    the most room ahead;
//  - if the continuous branch lies outside `usable` (an unwind cannot be avoided): the branch with
//    the most room ahead in `direction`, or the nearest to `reference` when direction is 0.
Choice choose_branch(double display, double reference, int direction, bool pass_starting, Window usable);

// An unwind no branch can spare a pass is cheapest near its culmination: an azimuth error of D
// there costs 2 asin(cos(el) sin(D/2)) on the sky, the least it will cost anywhere in the pass
// (docs/tracking.md §2.3). Just past the culmination, with `remaining_deg` of azimuth still to go
// in `direction`: the branch of `display` with room for all of it, if the `continuous` one lacks
// room by more than `slack_deg`; nullopt to stay (it fits, or no branch holds the rest either).
std::optional<double> culmination_branch(double display, double continuous, int direction, double remaining_deg,
                                         Window usable, double slack_deg);

// The next mechanical azimuth to command on the way from `from` to `to`: `to` itself if it is at
// most `max_leg` away, else the first of the fewest equal steps of at most `max_leg`.
//
// Why: the firmware is given display azimuths (0..360), as every upstream client sends, and maps
// them onto its wrap window itself. How is only partly known (docs/firmware.md §14 G2.4: "how a
// target like 180 is mapped into the window"; the notes describe it reversing at its limit and
// coming round the other side): whether it takes a literal out-of-0..360 value is unknown. The
// two plausible rules, "the branch nearest where the axis is" and "the shortest way round",
// agree whenever the intended branch is less than 180 deg from the axis, because every other
// branch is then more than 180 deg away. Legs of at most max_leg_deg (< 180, with slack for the
// arrival tolerance and leapfrog) therefore land on the intended branch under either rule, and
// a long slew that the firmware would otherwise resolve onto the other branch (the pass-start
// branch choice, an unwind) becomes a few such legs in the intended direction.
double next_waypoint(double from, double to, double max_leg = max_leg_deg);

// The whole sequence of next_waypoint() steps from `from`, ending with `to`.
std::vector<double> waypoints(double from, double to, double max_leg = max_leg_deg);

}  // namespace birdcage::wrap
