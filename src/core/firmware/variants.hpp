// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// One table row per firmware variant (src/core/firmware/variants.cpp). Variants differ only as data and
// named quirks; nothing outside variants.cpp may branch on VariantId.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

#include "base/azel.hpp"
#include "base/span.hpp"

namespace birdcage {

enum class VariantId { travler_hal000, travler_hal205, travler_pro, carryout2003, carryout_g2 };

// Each quirk is a fact about the firmware that changes what the core does, and each is read in
// exactly one function (named next to it).
enum Quirk : std::uint32_t {
    quirk_none = 0,
    // `q` at the root prompt terminates the shell until a power cycle (G2 02.02.48, docs/firmware.md 6.5).
    // Read by: hazard_check(); detection treats this firmware's clues as a warning against `q`.
    quirk_q_at_root_kills_shell = 1u << 0,
    // Motor/NVS/OS commands live on the ODU console behind the IDU's `odu` tunnel, and where `q`
    // at the ODU root leads is unknown (Trav'ler Pro, 5.1). Read by: ConsoleSession::note_menu_after().
    quirk_odu_tunnel = 1u << 3,
    // Axes are uncalibrated after power-up until `h <id>` (G2 with NVS 20 TRUE, 6.4).
    // Read by: Controller::warn_if_unhomed().
    quirk_requires_homing = 1u << 4,
};

enum class PositionFormat {
    travler_az_el_sk,  // `AZ = <f> EL = <f> SK = <f>` (any whitespace / line layout, optional sign)
    g2_angle_index,    // `Angle[0] = <f>` / `Angle[1] = <f>`
    carryout_live,     // none at rest; `... <azcdeg>   el = <elcdeg>` while `g` runs
};

enum class MoveAckFormat {
    none,      // nothing documented; replies are not read
    g2_angle,  // `Angle = <f>`
};

enum class MoveStyle {
    per_axis_a,  // `a <id> <deg>`, one motor at a time
    combined_g,  // `g <az> <el>` in a menu of its own; live output while it runs (CombinedMoveDriver)
};

enum class MotionModel {
    trapezoid,         // speed + acceleration per axis
    travler_time_fit,  // Gabe's empirical fit, docs/firmware.md 3.4
};

// A console command plus how long to keep listening before the next one (pacing some firmware needs).
struct ConsoleStep {
    std::string_view command;
    std::chrono::milliseconds settle{0};
};

struct FirmwareProfile {
    VariantId id;
    std::string_view short_name;  // "hal000", "hal205", "pro", "carryout2003", "g2"
    std::string_view display_name;
    int baud;
    std::string_view line_ending;

    // Prompts. Empty means "not documented": the session then ends a transaction on the expected
    // reply plus a quiet gap instead of on the prompt.
    std::string_view root_prompt;
    std::string_view motor_prompt;
    std::chrono::milliseconds quiet_gap;

    Span<const ConsoleStep> motor_menu_entry;            // from the root menu into the motor menu
    Span<const ConsoleStep> search_kill;                 // stops the TV search; starts and ends at root
    Span<const std::string_view> boot_complete_markers;  // substrings: boot has finished
    Span<const std::string_view> reboot_markers;         // substrings: the dish is (re)booting

    std::string_view position_query;  // empty when the variant has none (only live output while `g` runs)
    PositionFormat position_format;
    MoveAckFormat move_ack;
    MoveStyle move_style;

    double el_min, el_max;     // firmware/mechanical limits, degrees
    double az_min, az_max;     // travel including cable wrap, in the dish's own coordinates
    double arrival_tolerance;  // |target - position| that counts as arrived, degrees

    MotionModel motion_model;
    double az_speed_dps, el_speed_dps, accel_dps2;  // trapezoid parameters

    std::uint32_t quirks;

    // Park: a safe resting pointing reached with ordinary moves (never the firmware's `stow`,
    // which folds the dish flat and can destroy a modified feed, docs/firmware.md 3.5).
    double park_az, park_el;
    // Homing (Hamlib reset): the commands, in order; empty = the firmware has none (power-on only).
    Span<const std::string_view> home_commands;
    // NVS index of "Disable Tracker Proc?" (read-only check at init); -1 = none.
    int tracker_disable_nvs_index;

    // First guess of the pointing mode, until the dish's own small steps are timed (ServiceWorker::
    // choose_mode_from_dish): predictive where the motors usually step fast enough to follow an aim
    // a deadband ahead (G2); elsewhere each target as sent, because a dish that needs ~1 s per small
    // move (the documented Trav'ler timings, docs/firmware.md 3.4) only trails an extrapolated aim.
    bool predictive_by_default;

    // The submenu holding the satellite tuner (G2 `dvb`, docs/firmware.md 6.3), entered from the root
    // menu; empty = the variant has no tuner we can read. Read by: Controller::in_submenu() callers
    // (receiver.cpp).
    std::string_view receiver_menu = {};

    // The variant whose inner console (behind a tunnel) looks exactly like this variant's root:
    // HAL 0.0.00's root is what a Trav'ler Pro shows inside its ODU console (docs/firmware.md 5.1).
    // Auto-detection that finds this variant sends the one `q` that tells the two apart.
    std::optional<VariantId> also_shown_inside = std::nullopt;

    // Substrings of the documented last boot line, after which the console takes input at once and
    // the TV search is about to start (Trav'ler `NoGPS`, HAL 2.05 `No LNB Voltage`: docs/firmware.md
    // 3.2, 3.6, 4.2). Heard as the latest output, it ends the wait for the boot without a poke, so
    // the search is stopped before it swings the dish. Empty: two answered pokes confirm every boot
    // (the G2 prints status lines for ~10 s after its `Boot Complete`, 6.2).
    Span<const std::string_view> ready_markers = {};

    bool has(Quirk quirk) const { return (quirks & quirk) != 0; }
    bool prompt_known() const { return !motor_prompt.empty(); }
};

const FirmwareProfile& profile(VariantId id);

// The console profile used while the variant is still unknown: no known prompts, quiet-gap
// framing, every variant's boot markers, and the strictest hazard rules (a `q` is refused unless
// the console is known to be inside a submenu, because `q` at the G2 root kills its shell).
const FirmwareProfile& probe_profile();

std::optional<VariantId> variant_from_name(std::string_view short_name);

Span<const FirmwareProfile> all_profiles();

// Seconds an axis at rest takes over `distance` degrees, accelerating at `accel` up to `speed` and
// braking at `accel` (a triangle when the move is too short to reach `speed`).
double trapezoid_move_seconds(double distance, double speed, double accel);
// Estimated duration of a single-axis move of `degrees` from the variant's motion model.
std::chrono::milliseconds estimated_move_time(const FirmwareProfile& profile, Axis axis, double degrees);
// Degrees covered `seconds` after such a move started from rest, by the same model (0..|degrees|):
// the shape of a move between two position readings.
double travelled_after(const FirmwareProfile& profile, Axis axis, double degrees, double seconds);

}  // namespace birdcage
