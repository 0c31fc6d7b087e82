// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// One VariantProfile row and one set of menu tables per firmware variant (docs/firmware.md §1).
// Prompt names marked INVENTED are only used with PromptStyle::named; the G2's are known (§6.3).
#include <algorithm>
#include <limits>

#include "engine.hpp"
#include "handlers.hpp"

namespace birdcage::sim {
namespace {

namespace h = handlers;

// The reconstructed G2 console's MOT `l` and DVB `dis` (Options::unlisted_commands).
bool unlisted_on(const Options& options) {
    return options.unlisted_commands;
}

// ---- Carryout G2, firmware 02.02.48 (§6) ---------------------------------------------------
// Two consoles (Options::g2_console): the captured one (sim/transcripts/captured/, the
// default) and the reconstruction this emulator played before any capture existed. One table per
// menu serves both: entries only one of them has carry `captured_only` / `reconstructed_only`.
// MOT> descriptions are the captured listing's, verbatim; the other menus' listings were not
// captured (their command words were), so their descriptions are INVENTED.

bool captured_only(const Options& options) {
    return options.g2_console == G2Console::captured;
}
bool reconstructed_only(const Options& options) {
    return options.g2_console == G2Console::reconstructed;
}
bool reconstructed_unlisted_on(const Options& options) {
    return reconstructed_only(options) && unlisted_on(options);
}

constexpr Command g2_mot_commands[] = {
    {"a", h::angle, nullptr, "Go to angle [[[motor] [[+|-]angle]]]"},
    {"g", h::go_to, nullptr, "Go to <az> <el>", reconstructed_only},  // not on the captured G2 (§6.3)
    {"azscan", h::setter, nullptr, "Scan AZ from EL Min-Max Angle [az_rel_angle] [el_rel_angle] [delay]",
     captured_only},
    {"azscanwxp", h::setter, nullptr,
     "Scan AZ from EL Min-Max with all transponders [motor] [span] [resolution] [num_xp]", captured_only},
    {"e", h::silent, nullptr, "Engage motors"},
    {"ela2s", h::el_angle_to_steps, nullptr, "Elevation Law Test - Angle to Steps [angle]", captured_only},
    {"elminmaxhome", h::el_min_max_home, nullptr, "Display Min, Max & Home Elevation Angles"},
    {"els2a", h::el_steps_to_angle, nullptr, "Elevation Law Test - Steps to Angle [steps]", captured_only},
    {"h", h::home, nullptr, "Home Motors [motor num or * (both)]"},
    {"l", h::list_motors, nullptr, "List Motors in System", captured_only},
    {"l", h::list_motors, nullptr, "List Motors in System", unlisted_on, false},
    {"life", h::setter, nullptr, "Az/El Life test [az_rel_angle] [el_rel_angle]", captured_only},
    {"ma", h::max_accel, nullptr, "Set Max Acceleration [[motor] [deg/sec/sec]]"},
    {"motorboth", h::setter, nullptr, "Both Motor Life test [AZ delta(0-25)] [EL delta(0-25)]", captured_only},
    {"motorlife", h::setter, nullptr, "Motor Life Test [motor_id] [min_angle] [max_angle]", captured_only},
    {"mv", h::max_velocity, nullptr, "Set Max Velocity [motor] [deg/sec]"},
    {"p", h::step_positions, nullptr, "Go To Position [motor] [pos]"},
    {"pid", h::setter, nullptr, "Set PID Parameters [motor] [Kp] [Kv] [Ki]", captured_only},
    {"r", h::silent, nullptr, "Release Motors"},
    {"sd", h::setter, nullptr, "Stall Detect [motor] [dir] [timeout_ms] [iterations (0=forever)]", captured_only},
    {"sp", h::setter, nullptr, "Set Position [motor] [pos]", captured_only},
    {"sw", h::setter, nullptr, "Set Wrap Position [motor] [pos]", captured_only},
    {"v", h::setter, nullptr, "Goto Velocity [motor] [deg/rev]", captured_only},
    {"vms", h::setter, nullptr, "Goto Velocity For Milliseconds [motor] [deg/rev] [ms]", captured_only},
    {"w", h::setter, nullptr, "Wrap Manager [motor] [ON/OFF]", captured_only},
};
constexpr Command g2_nvs_commands[] = {
    {"d", h::nvs_dump, nullptr, "Display [idx]"},
    {"e", h::nvs_edit, nullptr, "Edit [idx] [value]"},
    {"s", h::nvs_save, nullptr, "Save"},
};
constexpr Command g2_dvb_commands[] = {
    {"rssi", h::dvb_rssi, nullptr, "Average RSSI [reads]"},
    {"lnbdc", h::dvb_lnbdc, nullptr, "LNB supply [odu|stb]"},
    {"config", h::dvb_config, nullptr, "BCM configuration"},
    {"qls", h::dvb_quick_lock, nullptr, "Quick lock status"},
    {"def", h::hazard_only, nullptr, "Restore defaults"},
    {"dis", h::dvb_channel, nullptr, "Display channel parameters", captured_only},
    {"dis", h::dvb_channel, nullptr, "Channel parameters", reconstructed_unlisted_on, false},
    {"snr", h::dvb_stream, nullptr, "SNR", captured_only},
    {"agc", h::dvb_stream, nullptr, "AGC", captured_only},
    {"lnbv", h::dvb_stream, nullptr, "LNB voltage", captured_only},
    {"ls", h::dvb_stream, nullptr, "Lock status", captured_only},
    {"nid", h::dvb_stream, nullptr, "Network ID", captured_only},
    {"stats", h::dvb_stream, nullptr, "Statistics", captured_only},
    {"freqs", h::dvb_fixed_reply, nullptr, "Frequency list", captured_only},
    {"range", h::dvb_fixed_reply, nullptr, "Transponder range", captured_only},
    {"pwr", h::dvb_fixed_reply, nullptr, "Power", captured_only},
    {"srch_mode", h::dvb_fixed_reply, nullptr, "Search mode", captured_only},
    {"tabto", h::dvb_fixed_reply, nullptr, "Table timeouts [acq] [nid] [sd]", captured_only},
    {"to", h::dvb_fixed_reply, nullptr, "Tune timeouts [acq] [nid]", captured_only},
    {"di2id", h::dvb_fixed_reply, nullptr, "DiSEqC 2 LNB ID", captured_only},
    {"di2stat", h::dvb_fixed_reply, nullptr, "DiSEqC 2 LNB status", captured_only},
    {"di2conf", h::dvb_fixed_reply, nullptr, "DiSEqC 2 LNB config", captured_only},
    {"di2sc", h::dvb_fixed_reply, nullptr, "DiSEqC 2 short circuit", captured_only},
    {"di2rcs", h::dvb_fixed_reply, nullptr, "DiSEqC 2 switch state", captured_only},
    {"di2cs", h::dvb_fixed_reply, nullptr, "DiSEqC 2 configure switch", captured_only},
    {"diag", h::silent, nullptr, "Diagnostics", captured_only},
    {"table", h::silent, nullptr, "Transponder table", captured_only},
    {"t", h::setter, nullptr, "Transponder [n]", captured_only},
    {"e", h::setter, nullptr, "Edit parameter [n] [value]", captured_only},
    {"h", h::setter, nullptr, "Parameter help [n]", captured_only},
    {"srch", h::silent, nullptr, "Search on/off", captured_only},
    {"shuf", h::silent, nullptr, "Shuffle on/off", captured_only},
    {"tablex", h::silent, nullptr, "Extended table on/off", captured_only},
    {"msw", h::setter, nullptr, "Modulation switch", captured_only},
    {"ovraddr", h::silent, nullptr, "DiSEqC address", captured_only},
    {"rrto", h::silent, nullptr, "DiSEqC reply timeout", captured_only},
    {"tdthresh", h::silent, nullptr, "DiSEqC tone threshold", captured_only},
    {"pretx", h::silent, nullptr, "DiSEqC pre-TX delay", captured_only},
    {"send", h::setter, nullptr, "DiSEqC packet [3-6 bytes]", captured_only},
};
constexpr Command g2_os_commands[] = {
    {"id", h::os_id, nullptr, "Identification"},
    {"reboot", h::reboot, nullptr, "Reboot"},
};
constexpr Command g2_eeprom_commands[] = {
    {"ee", h::eeprom_read, nullptr, "Read/write [idx] [value]"},
    {"inv", h::hazard_only, nullptr, "Invalidate [idx]"},
    {"def", h::hazard_only, nullptr, "Defaults"},
};
constexpr Command g2_adc_commands[] = {
    {"bdid", h::adc_board_id, nullptr, "Board ID"}, {"bdrevid", h::adc_board_rev, nullptr, "Board revision"},
    {"rssi", h::adc_rssi, nullptr, "Raw RSSI"},     {"m", h::silent, nullptr, "Monitor RSSI", captured_only},
    {"scan", h::adc_scan, nullptr, "AZ scan"},
};
constexpr Command g2_a3981_commands[] = {
    {"diag", h::a3981_diag, nullptr, "Driver diagnostics"},
    {"sm", h::a3981_reply, nullptr, "Step size mode", captured_only},
    {"ss", h::a3981_reply, nullptr, "Step size", captured_only},
    {"st", h::setter, nullptr, "Torque", captured_only},
    {"cm", h::a3981_reply, nullptr, "Current control mode", captured_only},
    {"reset", h::a3981_reply, nullptr, "Reset faults", captured_only},
};
constexpr Command g2_dipswitch_commands[] = {{"dipswitch", h::dipswitch, nullptr, "Read DIP switches"}};
constexpr Command g2_gpio_commands[] = {
    {"regs", h::silent, nullptr, "Registers", captured_only},
    {"r", h::setter, nullptr, "Read pin [port] [pin]", captured_only},
    {"w", h::setter, nullptr, "Write pin [port] [pin]", captured_only},
    {"dir", h::setter, nullptr, "Pin direction [bit] [val]", captured_only},
};
constexpr Command g2_latlon_commands[] = {
    {"l", h::latlon, nullptr, "Lat/lon from [satlon1] [satlon2] [satel1] [satel2]", captured_only},
};
constexpr Command g2_peak_commands[] = {
    {"ts", h::peak_switch_test, nullptr, "Switch test", captured_only},
    {"pw", h::setter, nullptr, "Peak power [az] [el]", captured_only},
    {"psnr", h::setter, nullptr, "Peak SNR [az] [el]", captured_only},
    {"pxy1", h::silent, nullptr, "Peak XY [n]", captured_only},
    {"stb", h::peak_stb, nullptr, "STB test", captured_only},
    {"rssits", h::dvb_stream, nullptr, "RSSI test", captured_only},
};
constexpr Command g2_step_commands[] = {
    {"e", h::step_engage, nullptr, "Engage", captured_only},
    {"r", h::silent, nullptr, "Release", captured_only},
    {"p", h::step_reply, nullptr, "Position [motor] [pos]", captured_only},
    {"v", h::setter, nullptr, "Velocity [motor] [vel]", captured_only},
    {"mv", h::step_max_velocity, nullptr, "Max velocity (usteps/s)"},
    {"ma", h::step_accel, nullptr, "Acceleration (usteps/s/ms)"},
    {"pid", h::step_reply, nullptr, "PID", captured_only},
};

constexpr Menu g2_mot{"MOT", g2_mot_commands};
constexpr Menu g2_nvs{"NVS", g2_nvs_commands, h::nvs_next};
constexpr Menu g2_dvb{"DVB", g2_dvb_commands};
constexpr Menu g2_os{"OS", g2_os_commands};
constexpr Menu g2_eeprom{"EE", g2_eeprom_commands};
constexpr Menu g2_adc{"ADC", g2_adc_commands};
constexpr Menu g2_a3981{"A3981", g2_a3981_commands};
constexpr Menu g2_dipswitch{"DIPSWITCH", g2_dipswitch_commands};
constexpr Menu g2_gpio{"GPIO", g2_gpio_commands};
constexpr Menu g2_latlon{"LATLON", g2_latlon_commands};
constexpr Menu g2_peak{"PEAK", g2_peak_commands};
constexpr Menu g2_step{"STEP", g2_step_commands};

// The captured root answers its 12 submenus, `q`, `Q` and `help` and nothing else (§6.3);
// `reboot` and `stow` at the root are the reconstruction's.
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
    {"reboot", h::reboot, nullptr, "Reboot", reconstructed_only},
    {"stow", h::stow, nullptr, "Stow", reconstructed_only},
};
constexpr Menu g2_root{"TRK", g2_root_commands, nullptr, true};

// Homing as a boot step sequence: the captured `h *` output around the moves (§6.3), EL first.
void append_g2_homing(std::vector<BootStep>& steps, const Engine& engine) {
    using K = BootStep::Kind;
    steps.push_back({K::line, "MotorHome:1 timeout:2000"});
    steps.push_back({K::line, "Home TwelInch El   Velocity: 4500"});
    steps.push_back({K::move, "", axis_el, engine.profile.home_el});
    steps.push_back({K::home, "", axis_el});
    steps.push_back({K::line, "EL Stall Timeout"});
    steps.push_back({K::line, "El Home Angle: 6500"});
    steps.push_back({K::line, ""});
    steps.push_back({K::line, "MotorHome:0 timeout:8000"});
    steps.push_back({K::line, "Home TwelInch Az"});
    steps.push_back({K::move, "", axis_az, engine.profile.az.max});
    steps.push_back({K::line, "End MotorAzStall:part1"});
    steps.push_back({K::move, "", axis_az, engine.profile.home_az});
    steps.push_back({K::home, "", axis_az});
    steps.push_back({K::line, "Antenna Facing Front"});
    steps.push_back({K::line, "home:0  wrap_pos:0  wrap_min:-42333  wrap_max:2333"});
}

// The captured boot of a unit with the tracker disabled (§6.2, sim/transcripts/captured/):
// two raw bursts around the bootloader's lines at 0.05 s, the application banner at 0.1 s, then
// `Boot Complete`, an empty line and the location/tuner status lines; `TRK>` about 10 s after
// power-on. Where the 10 s go is not captured: spent before `GPS Not Found` (a GPS search timing
// out, INF).
std::vector<BootStep> g2_captured_boot(const Engine& engine, bool homes) {
    using K = BootStep::Kind;
    std::vector<BootStep> steps = {
        {K::pause, "", 0, 0.0, 0.05},
        {K::raw, std::string("\x01\x00", 2)},
        {K::line, "Bootloader version: 1.01", 0, 0.0, 0.0, true},
        {K::line, "Application is running...", 0, 0.0, 0.0, true},
        {K::raw, "\x98\x80\x96"},
        {K::pause, "", 0, 0.0, 0.05},
        {K::line, "Application Starting Kinetis PCB... power up/reset"},
        {K::line, "Version 02.02.48"},
        {K::line, "Copyright 2013 - Winegard Company"},
    };
    if (homes)
        append_g2_homing(steps, engine);
    steps.push_back({K::line, "Boot Complete"});
    steps.push_back({K::ready, ""});
    steps.push_back({K::line, ""});
    steps.push_back({K::pause, "", 0, 0.0, engine.options.late_boot_line_delay});
    const char* status_lines[] = {"Loc Startup: IDU NOT Present",
                                  "app_dipswitch:101",
                                  "Primary Update:  10100",
                                  "Alternate Update:  11900",
                                  "Toggle Ability Update: 0",
                                  "Alternate2 Update:      0",
                                  "Sat Provider Update: 1",
                                  "DVB:  id:0000, lon:101.00E",
                                  "Tuner = WIDE",
                                  "Signal offset = 80",
                                  "Signal baseline angle = 6500",
                                  "Signal Re-Peak Pct = 25",
                                  "NVS Status: 0  Sleep: 420  Dipswitch: 101",
                                  "Sleep: 420  NVS: 420",
                                  "NoGpsStartUp: 721",
                                  "STATIONARY MODE",
                                  "Enabled LNB ODU 18V"};
    for (const char* line : status_lines)
        steps.push_back({K::line, line});
    // The rest of the ~10 s (homing moves not counted): the pauses so far, and a boot_line_gap
    // after each line that another line follows (Engine::run_boot).
    double elapsed = 0.0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
        if (steps[i].kind == K::pause)
            elapsed += steps[i].seconds;
        const bool gap_follows =
            steps[i].kind == K::line && !steps[i].burst && i + 1 < steps.size() && steps[i + 1].kind == K::line;
        if (gap_follows)
            elapsed += engine.options.boot_line_gap;
    }
    steps.push_back({K::pause, "", 0, 0.0, std::max(0.0, engine.options.g2_boot_seconds - elapsed)});
    steps.push_back({K::line, "GPS Not Found"});
    return steps;
}

// The reconstruction's boot: §6.2 as the predecessor summarised it (items 6-7 paraphrased in the
// notes are left out), homing with a one-line report, `Boot Complete`, `Loc Startup: ...`.
std::vector<BootStep> g2_reconstructed_boot(const Engine& engine, bool homes) {
    using K = BootStep::Kind;
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
    if (homes) {
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
    return steps;
}

std::vector<BootStep> g2_boot(const Engine& engine) {
    const NvsEntry* tracker_disabled = engine.nvs.find(engine.profile.nvs_disable_tracker_index);
    const bool tracker_runs = tracker_disabled != nullptr && tracker_disabled->current == 0.0;
    const bool captured = engine.options.g2_console == G2Console::captured;
    // The captured boot (tracker disabled) does not home; the predecessor said it does.
    const bool homes = engine.options.g2_boot_homes.value_or(!captured) || tracker_runs;
    std::vector<BootStep> steps = captured ? g2_captured_boot(engine, homes) : g2_reconstructed_boot(engine, homes);
    if (!engine.options.after_boot_line.empty())
        steps.push_back({BootStep::Kind::line, engine.options.after_boot_line});
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

constexpr Menu travler_mot{"MOT", travler_mot_commands};      // INVENTED prompt name
constexpr Menu travler_motor{"MOTOR", travler_mot_commands};  // INVENTED
constexpr Menu travler_nvs{"NVS", travler_nvs_commands, h::nvs_next};
constexpr Menu travler_os{"OS", travler_os_commands};
constexpr Menu ngsearch{"NGSEARCH", ngsearch_commands};  // INVENTED, §14 HAL2.05.3

constexpr Command hal000_root_commands[] = {
    {"mot", nullptr, &travler_mot, "Motor"},  {"nvs", nullptr, &travler_nvs, "Non-volatile storage"},
    {"os", nullptr, &travler_os, "OS"},       {"stow", h::stow, nullptr, "Stow"},
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

std::vector<BootStep> travler_boot(const Engine& engine) {
    using K = BootStep::Kind;
    // §3.2: calibration, then the marker. What calibration moves is a switch (TravlerBootMoves);
    // the 2 s before it are INVENTED.
    std::vector<BootStep> steps = {{K::pause, "", 0, 0.0, 2.0}};
    switch (engine.options.travler_boot_moves) {
        case TravlerBootMoves::park:
            steps.push_back({K::move, "", axis_az, 0.0});
            steps.push_back({K::move, "", axis_el, 45.0});
            break;
        case TravlerBootMoves::home_return:
            steps.push_back({K::move, "", axis_az, 0.0});
            steps.push_back({K::move, "", axis_az, engine.motors.axis(axis_az).position()});
            break;
        case TravlerBootMoves::none:
            break;
    }
    if (engine.profile.variant == Variant::travler_hal000) {
        steps.push_back({K::line, "NoGPS"});
    } else if (engine.profile.variant == Variant::travler_hal205) {
        steps.push_back(
            {K::line, engine.options.hal205_boot_marker == BootMarker::no_gps ? "NoGPS" : "No LNB Voltage"});
    }
    if (!engine.options.after_boot_line.empty() &&
        (engine.profile.variant == Variant::travler_hal000 || engine.profile.variant == Variant::travler_hal205)) {
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

std::vector<BootStep> carryout_boot(const Engine&) {
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
    {Variant::travler_hal000,
     "hal000",
     57600,
     &hal000_root,
     PositionFormat::travler,
     false,
     false,
     false,
     false,
     false,
     false,
     SearchStop::os_kill,
     false,
     travler_az,
     travler_el,
     travler_skew,
     15.0,
     90.0,
     no_stall,
     0.0,
     0.0,
     0.0,
     127,
     -1,
     -1,
     0,
     travler_nvs_table,
     travler_boot,
     true},
    {Variant::travler_hal205,
     "hal205",
     57600,
     &hal205_root,
     PositionFormat::travler,
     false,
     false,
     false,
     false,
     false,
     false,
     SearchStop::ngsearch_stop,
     false,
     travler_az,
     travler_el,
     travler_skew,
     15.0,
     90.0,
     no_stall,
     0.0,
     0.0,
     0.0,
     127,
     -1,
     -1,
     0,
     travler_nvs_table,
     travler_boot,
     true},
    {Variant::travler_pro,
     "pro",
     57600,
     &pro_idu_root,
     PositionFormat::travler,
     false,
     false,
     false,
     false,
     false,
     false,
     SearchStop::os_kill,
     false,
     travler_az,
     travler_el,
     travler_skew,
     12.0,
     90.0,
     75.0,
     0.0,
     0.0,
     0.0,
     127,
     -1,
     -1,
     10,
     travler_pro_nvs_table,
     travler_boot,
     true},
    {Variant::carryout2003,
     "carryout2003",
     57600,
     &carryout_root,
     PositionFormat::none,
     false,
     false,
     false,
     true,
     false,
     false,
     SearchStop::runs_out,
     false,
     carryout_az,
     carryout_el,
     unused_axis,
     22.0,
     73.0,
     no_stall,
     22.0,
     0.0,
     0.0,
     -1,
     102,
     -1,
     0,
     carryout2003_nvs_table,
     carryout_boot,
     false},
    {Variant::carryout_g2,
     "g2",
     115200,
     &g2_root,
     PositionFormat::g2,
     true,
     true,
     true,
     false,
     true,
     true,
     SearchStop::nvs_disable_tracker,
     true,
     g2_az,
     g2_el,
     unused_axis,
     18.0,
     65.0,
     no_stall,
     18.0,
     0.0,
     65.0,
     101,
     102,
     20,
     0,
     g2_nvs_table,
     g2_boot,
     true},
};

}  // namespace

const VariantProfile& profile_for(Variant variant) {
    for (const VariantProfile& profile : profiles)
        if (profile.variant == variant)
            return profile;
    return profiles[4];
}

std::optional<Variant> parse_variant(std::string_view name) {
    for (const VariantProfile& profile : profiles)
        if (name == profile.name)
            return profile.variant;
    return std::nullopt;
}

const char* variant_name(Variant variant) {
    return profile_for(variant).name;
}

std::optional<G2Console> parse_g2_console(std::string_view name) {
    if (name == "captured")
        return G2Console::captured;
    if (name == "reconstructed")
        return G2Console::reconstructed;
    return std::nullopt;
}

std::optional<TravlerBootMoves> parse_travler_boot_moves(std::string_view name) {
    for (TravlerBootMoves moves : {TravlerBootMoves::park, TravlerBootMoves::home_return, TravlerBootMoves::none})
        if (name == travler_boot_moves_name(moves))
            return moves;
    return std::nullopt;
}

const char* travler_boot_moves_name(TravlerBootMoves moves) {
    switch (moves) {
        case TravlerBootMoves::park:
            return "park";
        case TravlerBootMoves::home_return:
            return "home-return";
        case TravlerBootMoves::none:
            return "none";
    }
    return "park";
}

std::optional<AzMapping> parse_az_mapping(std::string_view name) {
    if (name == "nearest")
        return AzMapping::nearest;
    if (name == "literal")
        return AzMapping::literal;
    if (name == "wrap_manager")
        return AzMapping::wrap_manager;
    return std::nullopt;
}

}  // namespace birdcage::sim
