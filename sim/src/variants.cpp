// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// One VariantProfile row and one set of menu tables per firmware variant (docs/firmware.md §1).
// Prompt names marked INVENTED are only used with PromptStyle::named; the G2's are known (§6.3).
#include <limits>

#include "engine.hpp"
#include "handlers.hpp"

namespace birdcage::sim {
namespace {

namespace h = handlers;

bool unlisted_on(const Options& options) { return options.unlisted_commands; }

// ---- Carryout G2, firmware 02.02.48 (§6) ---------------------------------------------------

constexpr Command g2_mot_commands[] = {
    {"a", h::angle, nullptr, "Angle: show, or move motor <id> to <deg> / by +<d> -<d>"},
    {"g", h::go_to, nullptr, "Go to <az> <el>"},
    {"h", h::home, nullptr, "Home motor <id>"},
    {"e", h::silent, nullptr, "Engage motors"},
    {"r", h::silent, nullptr, "Release motors"},
    {"p", h::step_positions, nullptr, "Motor positions in steps"},
    {"mv", h::max_velocity, nullptr, "Max velocity [<motor> <v>]"},
    {"ma", h::max_accel, nullptr, "Max acceleration [<motor> <v>]"},
    {"elminmaxhome", h::el_min_max_home, nullptr, "EL min/max/home"},
    {"l", h::list_motors, nullptr, "List motors", unlisted_on, false},
};
constexpr Command g2_nvs_commands[] = {
    {"d", h::nvs_dump, nullptr, "Display [<idx>]"},
    {"e", h::nvs_edit, nullptr, "Edit <idx> [<value>]"},
    {"s", h::nvs_save, nullptr, "Save"},
};
constexpr Command g2_dvb_commands[] = {
    {"rssi", h::dvb_rssi, nullptr, "Average RSSI over <n> reads"},
    {"lnbdc", h::dvb_lnbdc, nullptr, "LNB supply <odu|stb>"},
    {"config", h::dvb_config, nullptr, "BCM configuration"},
    {"qls", h::dvb_quick_lock, nullptr, "Quick lock status"},
    {"def", h::hazard_only, nullptr, "Restore defaults"},
    {"dis", h::dvb_channel, nullptr, "Channel parameters", unlisted_on, false},
};
constexpr Command g2_os_commands[] = {
    {"id", h::os_id, nullptr, "Identification"},
    {"reboot", h::reboot, nullptr, "Reboot"},
};
constexpr Command g2_eeprom_commands[] = {
    {"ee", h::eeprom_read, nullptr, "Read/write <idx> [<v>]"},
    {"inv", h::hazard_only, nullptr, "Invalidate <idx>"},
    {"def", h::hazard_only, nullptr, "Defaults"},
};
constexpr Command g2_adc_commands[] = {
    {"bdid", h::adc_board_id, nullptr, "Board ID"},
    {"bdrevid", h::adc_board_rev, nullptr, "Board revision"},
    {"rssi", h::adc_rssi, nullptr, "Raw RSSI"},
    {"scan", h::adc_scan, nullptr, "AZ scan"},
};
constexpr Command g2_a3981_commands[] = {{"diag", h::a3981_diag, nullptr, "Driver diagnostics"}};
constexpr Command g2_dipswitch_commands[] = {{"dipswitch", h::dipswitch, nullptr, "Read DIP switches"}};
constexpr Command g2_step_commands[] = {
    {"mv", h::step_max_velocity, nullptr, "Max velocity (usteps/s)"},
    {"ma", h::step_accel, nullptr, "Acceleration (usteps/s/ms)"},
};

constexpr Menu g2_mot{"MOT", g2_mot_commands};
constexpr Menu g2_nvs{"NVS", g2_nvs_commands, h::nvs_next};
constexpr Menu g2_dvb{"DVB", g2_dvb_commands};
constexpr Menu g2_os{"OS", g2_os_commands};
constexpr Menu g2_eeprom{"EE", g2_eeprom_commands};
constexpr Menu g2_adc{"ADC", g2_adc_commands};
constexpr Menu g2_a3981{"A3981", g2_a3981_commands};
constexpr Menu g2_dipswitch{"DIPSWITCH", g2_dipswitch_commands};
constexpr Menu g2_gpio{"GPIO", {}};
constexpr Menu g2_latlon{"LATLON", {}};
constexpr Menu g2_peak{"PEAK", {}};
constexpr Menu g2_step{"STEP", g2_step_commands};

constexpr Command g2_root_commands[] = {
    {"a3981", nullptr, &g2_a3981, "A3981 stepper drivers"},
    {"adc", nullptr, &g2_adc, "ADC"},
    {"dipswitch", nullptr, &g2_dipswitch, "DIP switches"},
    {"dvb", nullptr, &g2_dvb, "DVB tuner"},
    {"eeprom", nullptr, &g2_eeprom, "EEPROM"},
    {"gpio", nullptr, &g2_gpio, "GPIO"},
    {"latlon", nullptr, &g2_latlon, "Lat/Lon"},
    {"mot", nullptr, &g2_mot, "Motors"},
    {"nvs", nullptr, &g2_nvs, "Non-volatile storage"},
    {"os", nullptr, &g2_os, "OS"},
    {"peak", nullptr, &g2_peak, "Peaking"},
    {"step", nullptr, &g2_step, "Raw stepper"},
    {"reboot", h::reboot, nullptr, "Reboot"},
    {"stow", h::stow, nullptr, "Stow"},
};
constexpr Menu g2_root{"TRK", g2_root_commands, nullptr, true};

std::vector<BootStep> g2_boot(const Engine& engine)
{
    using K = BootStep::Kind;
    // §6.2 items 1-9 as quoted (items 6-7 paraphrased in the notes are left out).
    std::vector<BootStep> steps = {
        {K::line, "Bootloader v1.01"},
        {K::line, "SPI1 init @ 4 MHz"},
        {K::line, "Motor init: System=12Inch, master=40000 steps, slave=24960 steps"},
        {K::line, "SPI2 init @ 6.857 MHz"},
        {K::line, "EXTENDED_DVB_DEBUG ENABLED"},
        {K::line, "BCM4515 ID 0x4515 Rev B0, FW v113.37"},
        {K::line, "Enabled LNB STB"},
        {K::line, "Ant ID - 12-IN G2"},
        {K::pause, "", 0, 0.0, 0.5},  // NVS load
    };
    const NvsEntry* tracker_disabled = engine.nvs.find(engine.profile.nvs_disable_tracker_index);
    const bool tracker_runs = tracker_disabled != nullptr && tracker_disabled->current == 0.0;
    if (engine.options.g2_boot_homes || tracker_runs) {
        steps.push_back({K::move, "", axis_el, engine.profile.home_el});
        steps.push_back({K::home, "", axis_el});
        steps.push_back({K::move, "", axis_az, engine.profile.az.max});
        steps.push_back({K::move, "", axis_az, engine.profile.home_az});
        steps.push_back({K::home, "", axis_az});
        steps.push_back({K::line, "wrap_min:-42333 wrap_max:2333"});
        steps.push_back({K::line, "Antenna Facing Front"});
    }
    steps.push_back({K::line, "Boot Complete"});
    steps.push_back({K::ready, ""});
    steps.push_back({K::pause, "", 0, 0.0, engine.options.late_boot_line_delay});
    steps.push_back({K::line, "Loc Startup: IDU NOT Present"});
    if (!engine.options.after_boot_line.empty()) {
        steps.push_back({K::line, engine.options.after_boot_line});
    }
    return steps;
}

// ---- Trav'ler HAL 0.0.00 (§3), HAL 2.05 (§4), Pro (§5) ------------------------------------

constexpr Command travler_mot_commands[] = {
    {"a", h::angle, nullptr, "Angle: show, or move motor <id> to <deg>"},
    {"g", h::go_to, nullptr, "Go to <az> <el> <sk>"},
};
constexpr Command travler_nvs_commands[] = {
    {"d", h::nvs_dump, nullptr, "Display"},
    {"e", h::nvs_edit, nullptr, "Edit <idx> [<value>]"},
    {"s", h::nvs_save, nullptr, "Save"},
};
constexpr Command travler_os_commands[] = {
    {"tasks", h::os_tasks, nullptr, "List tasks"},
    {"kill", h::os_kill, nullptr, "Kill <task>"},
};
constexpr Command ngsearch_commands[] = {{"s", h::ngsearch_stop, nullptr, "Stop search"}};

constexpr Menu travler_mot{"MOT", travler_mot_commands};       // INVENTED prompt name
constexpr Menu travler_motor{"MOTOR", travler_mot_commands};   // INVENTED
constexpr Menu travler_nvs{"NVS", travler_nvs_commands, h::nvs_next};
constexpr Menu travler_os{"OS", travler_os_commands};
constexpr Menu ngsearch{"NGSEARCH", ngsearch_commands};        // INVENTED, §14 HAL2.05.3

constexpr Command hal000_root_commands[] = {
    {"mot", nullptr, &travler_mot, "Motor"},
    {"nvs", nullptr, &travler_nvs, "Non-volatile storage"},
    {"os", nullptr, &travler_os, "OS"},
    {"stow", h::stow, nullptr, "Stow"},
    {"reboot", h::reboot, nullptr, "Reboot"},
};
constexpr Menu hal000_root{"TRK", hal000_root_commands, nullptr, true};  // INVENTED prompt name

constexpr Command hal205_root_commands[] = {
    {"motor", nullptr, &travler_motor, "Motor"},
    {"mot", nullptr, &travler_mot, "Motor", [](const Options& o) { return o.hal205_accepts_mot; }},
    {"ngsearch", nullptr, &ngsearch, "Search"},
    {"nvs", nullptr, &travler_nvs, "Non-volatile storage"},
    {"os", nullptr, &travler_os, "OS"},
    {"stow", h::stow, nullptr, "Stow"},
    {"reboot", h::reboot, nullptr, "Reboot"},
};
constexpr Menu hal205_root{"TRK", hal205_root_commands, nullptr, true};

// The Pro's ODU console is taken to be the HAL 0.0.00 one (§5.3 lists the same commands).
constexpr Command pro_idu_commands[] = {{"odu", nullptr, &hal000_root, "Connect to ODU"}};
constexpr Menu pro_idu_root{"IDU", pro_idu_commands, nullptr, true};  // INVENTED, §14 Pro.2

std::vector<BootStep> travler_boot(const Engine& engine)
{
    using K = BootStep::Kind;
    // §3.2: calibration moves, then the marker. Moves and timing INVENTED.
    std::vector<BootStep> steps = {
        {K::pause, "", 0, 0.0, 2.0},
        {K::move, "", axis_az, 0.0},
        {K::move, "", axis_el, 45.0},
    };
    if (engine.profile.variant == Variant::travler_hal000) {
        steps.push_back({K::line, "NoGPS"});
    } else if (engine.profile.variant == Variant::travler_hal205) {
        steps.push_back({K::line, engine.options.hal205_boot_marker == BootMarker::no_gps ? "NoGPS" : "No LNB Voltage"});
    }
    if (!engine.options.after_boot_line.empty() && (engine.profile.variant == Variant::travler_hal000 ||
                                                     engine.profile.variant == Variant::travler_hal205)) {
        steps.push_back({K::line, engine.options.after_boot_line});
    }
    return steps;
}

// ---- Carryout 2003, HAL 1.00.065 (§8) --------------------------------------------------------

constexpr Command carryout_target_commands[] = {{"g", h::go_to, nullptr, "Go to <az> <el>"}};
constexpr Menu carryout_target{"TARGET", carryout_target_commands};  // INVENTED prompt names
constexpr Menu carryout_motor{"MOTOR", {}};
constexpr Menu carryout_dvb{"DVB", {}};
constexpr Menu carryout_os{"OS", {}};
constexpr Menu carryout_nvs{"NVS", travler_nvs_commands, h::nvs_next};
constexpr Command carryout_root_commands[] = {
    {"target", nullptr, &carryout_target, "Send dish to AZ/EL"},
    {"motor", nullptr, &carryout_motor, "Motor"},
    {"dvb", nullptr, &carryout_dvb, "DVB"},
    {"os", nullptr, &carryout_os, "OS"},
    {"nvs", nullptr, &carryout_nvs, "Non-volatile storage"},
};
constexpr Menu carryout_root{"TRK", carryout_root_commands, nullptr, true};

std::vector<BootStep> carryout_boot(const Engine&)
{
    using K = BootStep::Kind;
    // §8.2: stall-based calibration with no console output ("blank screen", §8.1). INVENTED moves.
    return {
        {K::pause, "", 0, 0.0, 2.0},
        {K::move, "", axis_el, 22.0},
        {K::move, "", axis_az, 0.0},
    };
}

constexpr double no_stall = std::numeric_limits<double>::infinity();
// §3.4 time fit: 10 deg ~6.4 s, 90 deg ~13.5 s, 180 deg ~15.7 s. A 20 deg/s, 2 deg/s^2
// trapezoid gives 4.5 / 13.4 / 19 s (INF): right for the big moves a tracker cares about.
constexpr AxisParams travler_az{20.0, 2.0, 0.0, 455.0, 0};
constexpr AxisParams travler_el{20.0, 2.0, 0.0, 95.0, 0};
constexpr AxisParams travler_skew{10.0, 5.0, -90.0, 90.0, 0};  // INVENTED
// §6.4 / Appendix A NVS 80-88.
constexpr AxisParams g2_az{65.0, 400.0, -423.33, 23.33, 40000};
constexpr AxisParams g2_el{45.0, 400.0, 0.0, 90.0, 24960};
constexpr AxisParams unused_axis{1.0, 1.0, 0.0, 0.0, 0};
// §8.5: "~3 one-degree steps/s" in scans including SDR capture. INVENTED 10 deg/s, 20 deg/s^2.
constexpr AxisParams carryout_az{10.0, 20.0, 0.0, 360.0, 0};
constexpr AxisParams carryout_el{10.0, 20.0, 20.0, 90.0, 0};

const VariantProfile profiles[] = {
    {Variant::travler_hal000, "hal000", 57600, &hal000_root, PositionFormat::travler, false, false, false, false,
     false, false, SearchStop::os_kill, false, travler_az, travler_el, travler_skew, 15.0, 90.0, no_stall, 0.0, 0.0,
     0.0, 127, -1, -1, 0, travler_nvs_table, travler_boot, true},
    {Variant::travler_hal205, "hal205", 57600, &hal205_root, PositionFormat::travler, false, false, false, false,
     false, false, SearchStop::ngsearch_stop, false, travler_az, travler_el, travler_skew, 15.0, 90.0, no_stall, 0.0,
     0.0, 0.0, 127, -1, -1, 0, travler_nvs_table, travler_boot, true},
    {Variant::travler_pro, "pro", 57600, &pro_idu_root, PositionFormat::travler, false, false, false, false, false,
     false, SearchStop::os_kill, false, travler_az, travler_el, travler_skew, 12.0, 90.0, 75.0, 0.0, 0.0, 0.0, 127,
     -1, -1, 10, travler_pro_nvs_table, travler_boot, true},
    {Variant::carryout2003, "carryout2003", 57600, &carryout_root, PositionFormat::none, false, false, false, true,
     false, false, SearchStop::runs_out, false, carryout_az, carryout_el, unused_axis, 22.0, 73.0, no_stall, 22.0,
     0.0, 0.0, -1, 102, -1, 0, carryout2003_nvs_table, carryout_boot, false},
    {Variant::carryout_g2, "g2", 115200, &g2_root, PositionFormat::g2, true, true, true, false, true, true,
     SearchStop::nvs_disable_tracker, true, g2_az, g2_el, unused_axis, 18.0, 65.0, no_stall, 18.0, 0.0, 65.0, 101,
     102, 20, 0, g2_nvs_table, g2_boot, true},
};

}  // namespace

const VariantProfile& profile_for(Variant variant)
{
    for (const VariantProfile& profile : profiles)
        if (profile.variant == variant) return profile;
    return profiles[4];
}

std::optional<Variant> parse_variant(std::string_view name)
{
    for (const VariantProfile& profile : profiles)
        if (name == profile.name) return profile.variant;
    return std::nullopt;
}

const char* variant_name(Variant variant) { return profile_for(variant).name; }

std::optional<AzMapping> parse_az_mapping(std::string_view name)
{
    if (name == "nearest") return AzMapping::nearest;
    if (name == "literal") return AzMapping::literal;
    if (name == "wrap_manager") return AzMapping::wrap_manager;
    return std::nullopt;
}

}  // namespace birdcage::sim
