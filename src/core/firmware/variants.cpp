// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The variant table. Each fact cites a section (n.n) of the compiled docs/firmware.md; what each row
// means for a user is in docs/variants.md, the emulator's independent reading in sim/README.md.
#include "firmware/variants.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace birdcage {
namespace {

using namespace std::chrono_literals;

// ---- Trav'ler HAL 0.0.00 (docs/firmware.md 3) ----
constexpr std::array<ConsoleStep, 1> hal000_motor_entry{{{"mot", 0ms}}};
// travler_init.py: q, CR, os, kill Search, q, CR.
constexpr std::array<ConsoleStep, 6> hal000_search_kill{
    {{"q", 0ms}, {"", 0ms}, {"os", 0ms}, {"kill Search", 0ms}, {"q", 0ms}, {"", 0ms}}};
constexpr std::array<std::string_view, 1> hal000_boot_complete{"NoGPS"};

// ---- Trav'ler HAL 2.05.003 (docs/firmware.md 4) ----
constexpr std::array<ConsoleStep, 1> hal205_motor_entry{{{"motor", 0ms}}};
// birdcage's HAL205 sequence (4.3), with its 0.2 s pauses after `ngsearch` and `s`.
constexpr std::array<ConsoleStep, 6> hal205_search_kill{
    {{"q", 0ms}, {"", 0ms}, {"ngsearch", 200ms}, {"s", 200ms}, {"q", 0ms}, {"", 0ms}}};
constexpr std::array<std::string_view, 2> hal205_boot_complete{"NoGPS", "No LNB Voltage"};

// ---- Trav'ler Pro (docs/firmware.md 5) ----
// Client v2.0 start-up paces `odu` with 1 s pauses (5.6), then (README) os / kill Search / q.
// Whether `q` at the ODU root returns to the IDU is unknown (14 Pro.2), so the sequence works
// either way: two `q` reach the ODU root or the IDU; `odu` then enters the ODU from the IDU and
// is an unknown (harmless) command at the ODU root. No `q` follows `odu` (the upstream client's
// `odu`, `q`, `mot` only works if `q` stays on the ODU).
constexpr std::array<ConsoleStep, 9> pro_search_kill{{{"q", 0ms},
                                                      {"q", 0ms},
                                                      {"", 1000ms},
                                                      {"odu", 1000ms},
                                                      {"", 0ms},
                                                      {"os", 0ms},
                                                      {"kill Search", 0ms},
                                                      {"q", 0ms},
                                                      {"", 0ms}}};
constexpr std::array<ConsoleStep, 1> pro_motor_entry{{{"mot", 0ms}}};

// ---- Carryout 2003, HAL 1.00.065 (docs/firmware.md 8) ----
constexpr std::array<ConsoleStep, 1> carryout_motor_entry{{{"target", 0ms}}};

// ---- Carryout G2 02.02.48 (docs/firmware.md 6) ----
constexpr std::array<ConsoleStep, 1> g2_motor_entry{{{"mot", 0ms}}};
// `Boot Complete` then `Loc Startup: IDU NOT Present`: the boot-complete pair (6.2 item 3-4); the
// second may arrive after the first has been answered, so either ends the boot.
constexpr std::array<std::string_view, 2> g2_boot_complete{"Boot Complete", "Loc Startup:"};
constexpr std::array<std::string_view, 5> g2_reboot{"Bootloader v", "Motor init:", "Ant ID -", "Boot Complete",
                                                    "Loc Startup:"};

// G2 homing, elevation first as `h *` does (6.3): the dish rises before it turns.
constexpr std::array<std::string_view, 2> g2_home{"h 1", "h 0"};

constexpr std::array<std::string_view, 4> any_boot_complete{"NoGPS", "No LNB Voltage", "Boot Complete", "Loc Startup:"};
constexpr std::array<std::string_view, 8> any_boot_marker{"NoGPS",        "No LNB Voltage", "Boot Complete",
                                                          "Bootloader v", "Motor init:",    "Ant ID -",
                                                          "Loc Startup:", "Antenna Facing"};

constexpr FirmwareProfile travler_hal000_profile() {
    FirmwareProfile p{};
    p.id = VariantId::travler_hal000;
    p.short_name = "hal000";
    p.display_name = "Trav'ler HAL 0.0.00";
    p.baud = 57600;
    p.line_ending = "\r";
    p.root_prompt = "";
    p.motor_prompt = "";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = hal000_motor_entry;
    p.search_kill = hal000_search_kill;
    p.boot_complete_markers = hal000_boot_complete;
    p.reboot_markers = hal000_boot_complete;
    p.position_query = "a";
    p.position_format = PositionFormat::travler_az_el_sk;
    p.move_ack = MoveAckFormat::none;
    p.move_style = MoveStyle::per_axis_a;
    p.el_min = 15.0;
    p.el_max = 90.0;
    p.az_min = 0.0;
    p.az_max = 455.0;
    p.arrival_tolerance = 0.2;
    p.motion_model = MotionModel::travler_time_fit;
    p.az_speed_dps = 0;
    p.el_speed_dps = 0;
    p.accel_dps2 = 0;
    p.quirks = quirk_none;
    p.park_az = 0.0;
    p.park_el = 45.0;
    p.home_commands = {};
    p.tracker_disable_nvs_index = -1;
    p.predictive_by_default = false;
    p.also_shown_inside = VariantId::travler_pro;
    p.ready_markers = hal000_boot_complete;
    return p;
}

constexpr FirmwareProfile travler_hal205_profile() {
    FirmwareProfile p{};
    p.id = VariantId::travler_hal205;
    p.short_name = "hal205";
    p.display_name = "Trav'ler HAL 2.05";
    p.baud = 57600;
    p.line_ending = "\r";
    p.root_prompt = "";
    p.motor_prompt = "";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = hal205_motor_entry;
    p.search_kill = hal205_search_kill;
    p.boot_complete_markers = hal205_boot_complete;
    p.reboot_markers = hal205_boot_complete;
    p.position_query = "a";
    p.position_format = PositionFormat::travler_az_el_sk;
    p.move_ack = MoveAckFormat::none;
    p.move_style = MoveStyle::per_axis_a;
    p.el_min = 15.0;
    p.el_max = 90.0;
    p.az_min = 0.0;
    p.az_max = 455.0;
    p.arrival_tolerance = 0.2;
    p.motion_model = MotionModel::travler_time_fit;
    p.az_speed_dps = 0;
    p.el_speed_dps = 0;
    p.accel_dps2 = 0;
    p.quirks = quirk_none;
    p.park_az = 0.0;
    p.park_el = 45.0;
    p.home_commands = {};
    p.tracker_disable_nvs_index = -1;
    p.predictive_by_default = false;
    p.ready_markers = hal205_boot_complete;
    return p;
}

constexpr FirmwareProfile travler_pro_profile() {
    FirmwareProfile p{};
    p.id = VariantId::travler_pro;
    p.short_name = "pro";
    p.display_name = "Trav'ler Pro";
    p.baud = 57600;  // unconfirmed; irrelevant on the USB CDC-ACM link (5.1)
    p.line_ending = "\r";
    p.root_prompt = "";
    p.motor_prompt = "";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = pro_motor_entry;
    p.search_kill = pro_search_kill;
    p.boot_complete_markers = {};
    p.reboot_markers = {};
    p.position_query = "a";
    p.position_format = PositionFormat::travler_az_el_sk;
    p.move_ack = MoveAckFormat::none;
    p.move_style = MoveStyle::per_axis_a;
    p.el_min = 12.0;
    p.el_max = 75.0;  // motors stall above ~75 and may lock up (5.4)
    p.az_min = 0.0;
    p.az_max = 455.0;
    p.arrival_tolerance = 0.2;
    p.motion_model = MotionModel::travler_time_fit;
    p.az_speed_dps = 0;
    p.el_speed_dps = 0;
    p.accel_dps2 = 0;
    p.quirks = quirk_odu_tunnel;
    p.park_az = 0.0;
    p.park_el = 45.0;
    p.home_commands = {};
    p.tracker_disable_nvs_index = -1;
    p.predictive_by_default = false;
    return p;
}

constexpr FirmwareProfile carryout2003_profile() {
    FirmwareProfile p{};
    p.id = VariantId::carryout2003;
    p.short_name = "carryout2003";
    p.display_name = "Carryout HAL 1.00.065";
    p.baud = 57600;
    p.line_ending = "\r";
    p.root_prompt = "";
    p.motor_prompt = "";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = carryout_motor_entry;
    p.search_kill = {};  // cannot be stopped without losing calibration (8.2)
    p.boot_complete_markers = {};
    p.reboot_markers = {};
    p.position_query = "";
    p.position_format = PositionFormat::carryout_live;
    p.move_ack = MoveAckFormat::none;
    p.move_style = MoveStyle::combined_g;
    p.el_min = 22.0;
    p.el_max = 73.0;  // NVS 102 default (8.5)
    p.az_min = 0.0;
    p.az_max = 360.0;
    p.arrival_tolerance = 0.5;
    // No speed is documented; scans manage ~3 one-degree moves per second (8.5). Conservative guess.
    p.motion_model = MotionModel::trapezoid;
    p.az_speed_dps = 10.0;
    p.el_speed_dps = 10.0;
    p.accel_dps2 = 20.0;
    p.quirks = quirk_none;
    p.park_az = 0.0;
    p.park_el = 45.0;
    p.home_commands = {};
    p.tracker_disable_nvs_index = -1;
    p.predictive_by_default = false;
    return p;
}

constexpr FirmwareProfile carryout_g2_profile() {
    FirmwareProfile p{};
    p.id = VariantId::carryout_g2;
    p.short_name = "g2";
    p.display_name = "Carryout G2";
    p.baud = 115200;
    p.line_ending = "\r";
    p.root_prompt = "TRK>";
    p.motor_prompt = "MOT>";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = g2_motor_entry;
    p.search_kill = {};  // NVS 20 "Disable Tracker Proc?" TRUE keeps the search off (6.2)
    p.boot_complete_markers = g2_boot_complete;
    p.reboot_markers = g2_reboot;
    p.position_query = "a";
    p.position_format = PositionFormat::g2_angle_index;
    p.move_ack = MoveAckFormat::g2_angle;
    p.move_style = MoveStyle::per_axis_a;
    p.el_min = 18.0;
    p.el_max = 65.0;  // NVS 101/102
    p.az_min = -423.33;
    p.az_max = 23.33;  // cable wrap after homing (6.4)
    p.arrival_tolerance = 0.1;
    p.motion_model = MotionModel::trapezoid;
    p.az_speed_dps = 65.0;
    p.el_speed_dps = 45.0;
    p.accel_dps2 = 400.0;  // NVS 80/85/81/86
    p.quirks = quirk_q_at_root_kills_shell | quirk_requires_homing;
    p.park_az = 0.0;
    p.park_el = 65.0;
    p.home_commands = g2_home;
    p.tracker_disable_nvs_index = 20;
    p.predictive_by_default = true;
    p.receiver_menu = "dvb";
    return p;
}

constexpr std::array<FirmwareProfile, 5> profiles{{travler_hal000_profile(), travler_hal205_profile(),
                                                   travler_pro_profile(), carryout2003_profile(),
                                                   carryout_g2_profile()}};

// docs/firmware.md 3.4: time ~ |3.23 ln(0.84 d) - 0.48| s. The fit dips to ~0.3 s around 1.2-1.5 deg,
// an artefact, so it is floored at 1 s from 1 deg up.
double seconds_travler_fit(double distance) {
    if (distance < 0.5) {
        return 0.3;
    }
    if (distance < 1.0) {
        return 0.5;
    }
    return std::max(1.0, std::fabs(3.23 * std::log(0.84 * distance) - 0.48));
}

double move_seconds(const FirmwareProfile& profile, Axis axis, double distance) {
    switch (profile.motion_model) {
        case MotionModel::trapezoid:
            return trapezoid_move_seconds(distance, axis == Axis::azimuth ? profile.az_speed_dps : profile.el_speed_dps,
                                          profile.accel_dps2);
        case MotionModel::travler_time_fit:
            return seconds_travler_fit(distance);
    }
    return 0.0;
}

constexpr FirmwareProfile auto_detect_profile() {
    FirmwareProfile p{};
    p.id = VariantId::carryout_g2;  // not used for decisions; the quirks below are the G2's worst case
    p.short_name = "auto";
    p.display_name = "Auto-detect";
    p.baud = 57600;
    p.line_ending = "\r";
    p.root_prompt = "TRK>";  // the G2's: the guard refuses `q` there while the variant is unknown
    p.motor_prompt = "";
    p.quiet_gap = 150ms;
    p.motor_menu_entry = {};
    p.search_kill = {};
    p.boot_complete_markers = any_boot_complete;
    p.reboot_markers = any_boot_marker;
    p.position_query = "";
    p.position_format = PositionFormat::travler_az_el_sk;
    p.move_ack = MoveAckFormat::none;
    p.move_style = MoveStyle::per_axis_a;
    p.el_min = 0;
    p.el_max = 0;
    p.az_min = 0;
    p.az_max = 0;
    p.arrival_tolerance = 0;
    p.motion_model = MotionModel::trapezoid;
    p.az_speed_dps = 0;
    p.el_speed_dps = 0;
    p.accel_dps2 = 0;
    p.quirks = quirk_q_at_root_kills_shell;
    p.park_az = 0;
    p.park_el = 0;
    p.home_commands = {};
    p.tracker_disable_nvs_index = -1;
    p.predictive_by_default = false;
    return p;
}

constexpr FirmwareProfile probe = auto_detect_profile();

}  // namespace

const FirmwareProfile& probe_profile() {
    return probe;
}

const FirmwareProfile& profile(VariantId id) {
    for (const auto& row : profiles) {
        if (row.id == id) {
            return row;
        }
    }
    return profiles.front();  // unreachable: every enumerator has a row (checked by a test)
}

std::optional<VariantId> variant_from_name(std::string_view short_name) {
    for (const auto& row : profiles) {
        if (row.short_name == short_name) {
            return row.id;
        }
    }
    return std::nullopt;
}

Span<const FirmwareProfile> all_profiles() {
    return profiles;
}

double trapezoid_move_seconds(double distance, double speed, double accel) {
    if (distance < speed * speed / accel) {
        return 2.0 * std::sqrt(distance / accel);
    }
    return distance / speed + speed / accel;
}

std::chrono::milliseconds estimated_move_time(const FirmwareProfile& profile, Axis axis, double degrees) {
    const double seconds = move_seconds(profile, axis, std::fabs(degrees));
    return std::chrono::milliseconds(static_cast<long long>(std::ceil(seconds * 1000.0)));
}

double travelled_after(const FirmwareProfile& profile, Axis axis, double degrees, double seconds) {
    const double distance = std::fabs(degrees);
    const double total = move_seconds(profile, axis, distance);
    if (seconds <= 0.0 || distance <= 0.0) {
        return 0.0;
    }
    if (seconds >= total || total <= 0.0) {
        return distance;
    }
    if (profile.motion_model == MotionModel::trapezoid) {
        // Accelerate at a, cruise at v if the move is long enough to reach it, brake at a.
        const double v = axis == Axis::azimuth ? profile.az_speed_dps : profile.el_speed_dps;
        const double a = profile.accel_dps2;
        const double ramp = std::min(v / a, total / 2.0);
        if (seconds <= ramp) {
            return 0.5 * a * seconds * seconds;
        }
        const double braking = total - seconds;
        if (braking <= ramp) {
            return distance - 0.5 * a * braking * braking;
        }
        return 0.5 * a * ramp * ramp + v * (seconds - ramp);
    }
    // No published acceleration (docs/firmware.md 3.4): a symmetric smooth start and stop over the
    // fitted duration.
    const double u = seconds / total;
    return distance * u * u * (3.0 - 2.0 * u);
}

}  // namespace birdcage
