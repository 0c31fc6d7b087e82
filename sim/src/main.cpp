// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-sim: run one emulated dish on a pty until SIGINT/SIGTERM. Every Options switch has a
// long option here (`--flag value` or `--flag=value`); sim/README.md says what each one means.
#include <pthread.h>
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "birdcage_sim/dialect.hpp"
#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/motor.hpp"
#include "birdcage_sim/sky.hpp"
#include "birdcage_sim/sky_geometry.hpp"
#include "birdcage_sim/transcript.hpp"
#include "birdcage_version.hpp"

namespace {

using birdcage::sim::Options;

// A usage error: one line on stderr, exit status 2.
struct UsageError {
    std::string message;
};

std::optional<double> number(std::string_view text) {
    const std::string owned(text);
    char* end = nullptr;
    const double value = std::strtod(owned.c_str(), &end);
    if (owned.empty() || end != owned.c_str() + owned.size())
        return std::nullopt;
    return value;
}

double number_at_least(std::string_view flag, std::string_view text, double min, double max = 1e18) {
    const auto value = number(text);
    if (!value || *value < min || *value > max) {
        char range[64];
        std::snprintf(range, sizeof range, max < 1e18 ? "%g..%g" : ">= %g", min, max);
        throw UsageError{std::string(flag) + ": expected a number " + range + ", got '" + std::string(text) + "'"};
    }
    return *value;
}

long integer_in(std::string_view flag, std::string_view text, double min, double max) {
    const double value = number_at_least(flag, text, min, max);
    if (value != static_cast<double>(static_cast<long>(value)))
        throw UsageError{std::string(flag) + ": expected a whole number, got '" + std::string(text) + "'"};
    return static_cast<long>(value);
}

bool yes_no(std::string_view flag, std::string_view text) {
    if (text == "yes" || text == "on" || text == "true" || text == "1")
        return true;
    if (text == "no" || text == "off" || text == "false" || text == "0")
        return false;
    throw UsageError{std::string(flag) + ": expected yes or no, got '" + std::string(text) + "'"};
}

// One of `names` (its index), else a usage error listing them.
template <typename Enum>
Enum choice(std::string_view flag, std::string_view text, std::initializer_list<std::pair<const char*, Enum>> names) {
    std::string list;
    for (const auto& [name, value] : names) {
        if (text == name)
            return value;
        list += list.empty() ? "" : "|";
        list += name;
    }
    throw UsageError{std::string(flag) + ": expected " + list + ", got '" + std::string(text) + "'"};
}

struct Flag {
    const char* name;
    const char* value;  // nullptr: takes no value
    const char* help;
    std::function<void(Options&, std::string_view flag, std::string_view value)> apply;
};

using birdcage::sim::AzReport;
using birdcage::sim::BootMarker;
using birdcage::sim::G2RootQ;
using birdcage::sim::HelpLayout;
using birdcage::sim::HomeReport;
using birdcage::sim::LineEnding;
using birdcage::sim::MoveAck;
using birdcage::sim::OutOfRange;
using birdcage::sim::PromptStyle;
using birdcage::sim::ReplayMode;
using birdcage::sim::TravlerPositionLayout;

bool have_variant = false;
// --lat/--lon/--alt make Options::station only together (checked after parsing).
bool have_lat = false, have_lon = false, have_alt = false;
// --sky-at: print the sky's positions at this UTC and exit (no dish).
std::optional<double> sky_at;

double utc_value(std::string_view flag, std::string_view text) {
    const auto utc = birdcage::sim::parse_utc(text);
    if (!utc)
        throw UsageError{std::string(flag) + ": expected an ISO-8601 UTC time (YYYY-MM-DDTHH:MM:SS[.fff]Z), got '" +
                         std::string(text) + "'"};
    return *utc;
}

birdcage::sim::Station& station_of(Options& o) {
    if (!o.station)
        o.station.emplace();
    return *o.station;
}

// `az_index=A,el_index=E,tilt_north=N,tilt_east=W`, any subset, the terms of docs/sky.md §1.
birdcage::sim::Mount mount_value(std::string_view flag, std::string_view text) {
    birdcage::sim::Mount mount;
    while (!text.empty()) {
        const std::size_t comma = text.find(',');
        const std::string_view term = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view{} : text.substr(comma + 1);
        const std::size_t equals = term.find('=');
        const std::string_view key = term.substr(0, equals);
        if (equals == std::string_view::npos)
            throw UsageError{std::string(flag) + ": expected TERM=DEG, got '" + std::string(term) + "'"};
        const double value =
            number_at_least(std::string(flag) + " " + std::string(key), term.substr(equals + 1), -360.0, 360.0);
        if (key == "az_index") {
            mount.az_index = value;
        } else if (key == "el_index") {
            mount.el_index = value;
        } else if (key == "tilt_north") {
            mount.tilt_north = value;
        } else if (key == "tilt_east") {
            mount.tilt_east = value;
        } else {
            throw UsageError{std::string(flag) + ": unknown term '" + std::string(key) +
                             "' (az_index, el_index, tilt_north, tilt_east)"};
        }
    }
    return mount;
}
// --dialect: draw the console from --seed (sim/README.md, "Dialects"); other flags override it.
enum class DialectMode { off, random, describe };
DialectMode dialect_mode = DialectMode::off;

const std::vector<Flag>& flags() {
    static const std::vector<Flag> table = {
        // --- the dish and the session ---
        {"--variant", "hal205|g2|hal000|pro|carryout2003", "firmware variant (default: the transcript's)",
         [](Options& o, std::string_view f, std::string_view v) {
             const auto variant = birdcage::sim::parse_variant(v);
             if (!variant)
                 throw UsageError{std::string(f) + ": unknown variant '" + std::string(v) + "'"};
             o.variant = *variant;
             have_variant = true;
         }},
        {"--dialect", "random|describe", "draw a console from --seed; describe prints it and exits",
         [](Options&, auto f, auto v) {
             dialect_mode =
                 choice<DialectMode>(f, v, {{"random", DialectMode::random}, {"describe", DialectMode::describe}});
         }},
        {"--link", "PATH", "symlink to the pty slave", [](Options& o, auto, auto v) { o.link_path = v; }},
        {"--time-scale", "X", "simulated seconds per real second (> 0)",
         [](Options& o, auto f, auto v) { o.time_scale = number_at_least(f, v, 1e-6); }},
        {"--booting", nullptr, "start at power-on (boot log first)",
         [](Options& o, auto, auto) { o.already_booted = false; }},
        {"--search", nullptr, "the TV-satellite search is running",
         [](Options& o, auto, auto) { o.search_running = true; }},
        {"--az", "DEG", "true azimuth at start",
         [](Options& o, auto f, auto v) { o.start_az = number_at_least(f, v, -1e6); }},
        {"--el", "DEG", "true elevation at start",
         [](Options& o, auto f, auto v) { o.start_el = number_at_least(f, v, -1e6); }},
        {"--seed", "N", "seed of every random choice",
         [](Options& o, auto f, auto v) { o.seed = static_cast<std::uint32_t>(integer_in(f, v, 0, 4294967295.0)); }},
        {"--trace", nullptr, "log << client and >> dish bytes to stderr",
         [](Options& o, auto, auto) {
             o.trace = [](bool from_client, std::string_view bytes) {
                 std::cerr << (from_client ? "<< " : ">> ") << birdcage::sim::escape_chunk(bytes) << '\n';
             };
         }},
        // --- the sky (docs/sky.md) ---
        {"--mount", "az_index=A,el_index=E,tilt_north=N,tilt_east=W",
         "how the dish's axes sit against the sky, docs/sky.md section 1 (any subset; default all 0)",
         [](Options& o, auto f, auto v) { o.mount = mount_value(f, v); }},
        {"--lat", "DEG", "station latitude: the G2 hears the real sky (geostationary belt, Sun) over it",
         [](Options& o, auto f, auto v) {
             station_of(o).lat_deg = number_at_least(f, v, -90.0, 90.0);
             have_lat = true;
         }},
        {"--lon", "DEG", "station longitude, east positive (with --lat)",
         [](Options& o, auto f, auto v) {
             station_of(o).lon_deg = number_at_least(f, v, -180.0, 360.0);
             have_lon = true;
         }},
        {"--alt", "M", "station height above the WGS84 ellipsoid in metres (default 0)",
         [](Options& o, auto f, auto v) {
             station_of(o).alt_m = number_at_least(f, v, -1000.0, 100000.0);
             have_alt = true;
         }},
        {"--epoch", "ISO-8601-UTC", "UTC of emulated time 0 (default: the wall clock at start)",
         [](Options& o, auto f, auto v) { o.epoch = utc_value(f, v); }},
        {"--truth", "FILE", "write where the axes and the beam are (CSV, sim/README.md) as the dish moves",
         [](Options& o, auto, auto v) { o.truth_path = v; }},
        {"--sky-at", "ISO-8601-UTC", "print the Sun's and the belt's look angles at the station (CSV) and exit",
         [](Options&, auto f, auto v) { sky_at = utc_value(f, v); }},
        {"--replay", "TRANSCRIPT", "answer from a transcript (strict)",
         [](Options& o, auto, auto v) {
             o.transcript_path = v;
             if (o.replay == ReplayMode::off)
                 o.replay = ReplayMode::strict;
         }},
        {"--lenient", nullptr, "replay hands over to the model on a mismatch",
         [](Options& o, auto, auto) { o.replay = ReplayMode::lenient; }},
        // --- line faults (real time) ---
        {"--idle-noise", "BPS", "random bytes per real second while idle",
         [](Options& o, auto f, auto v) { o.line_faults.idle_noise_bps = number_at_least(f, v, 0.0); }},
        {"--invert", nullptr, "swapped RX pair: every dish byte inverted",
         [](Options& o, auto, auto) { o.line_faults.inverted_polarity = true; }},
        {"--ignore-input", nullptr, "swapped TX pair: the dish hears nothing",
         [](Options& o, auto, auto) { o.line_faults.ignore_input = true; }},
        {"--drop", "P", "each dish byte lost with probability P",
         [](Options& o, auto f, auto v) { o.line_faults.drop_probability = number_at_least(f, v, 0.0, 1.0); }},
        {"--pace", "BAUD", "wire pacing in real time, 10 bits per byte (0 = off)",
         [](Options& o, auto f, auto v) { o.line_faults.pace_baud = static_cast<int>(integer_in(f, v, 0, 1e9)); }},
        // --- open questions of docs/firmware.md ---
        {"--echo", "yes|no", "echo typed characters (default yes)",
         [](Options& o, auto f, auto v) { o.echo = yes_no(f, v); }},
        {"--line-ending", "crlf|lf|lfcr|cr", "output line ending (default crlf)",
         [](Options& o, auto f, auto v) {
             o.line_ending = choice<LineEnding>(f, v,
                                                {{"crlf", LineEnding::crlf},
                                                 {"lf", LineEnding::lf},
                                                 {"lfcr", LineEnding::lfcr},
                                                 {"cr", LineEnding::cr}});
         }},
        {"--unknown-reply", "TEXT",
         "unknown-command reply, empty = none (default: captured G2 'Invalid command', else 'Unknown command')",
         [](Options& o, auto, auto v) { o.unknown_command_reply = v; }},
        {"--out-of-range", "clamp|reject", "out-of-range move (default clamp)",
         [](Options& o, auto f, auto v) {
             o.out_of_range = choice<OutOfRange>(f, v, {{"clamp", OutOfRange::clamp}, {"reject", OutOfRange::reject}});
         }},
        {"--out-of-range-reply", "TEXT", "printed when rejecting (default 'Angle out of range')",
         [](Options& o, auto, auto v) { o.out_of_range_reply = v; }},
        {"--move-ack", "immediate|after-motion", "when `a <id> <deg>` returns its prompt (default immediate)",
         [](Options& o, auto f, auto v) {
             o.move_ack =
                 choice<MoveAck>(f, v, {{"immediate", MoveAck::immediate}, {"after-motion", MoveAck::after_motion}});
         }},
        {"--position-while-moving", "answer|wait", "`a` while moving (default answer)",
         [](Options& o, auto f, auto v) {
             o.answer_position_while_moving = choice<bool>(f, v, {{"answer", true}, {"wait", false}});
         }},
        {"--az-report", "displayed|mechanical", "AZ in `a` replies (default displayed 0..360)",
         [](Options& o, auto f, auto v) {
             o.az_report =
                 choice<AzReport>(f, v, {{"displayed", AzReport::displayed}, {"mechanical", AzReport::mechanical}});
         }},
        {"--az-mapping", "nearest|literal|wrap_manager", "how an AZ target maps onto the travel (default nearest)",
         [](Options& o, auto f, auto v) {
             const auto mapping = birdcage::sim::parse_az_mapping(v);
             if (!mapping)
                 throw UsageError{std::string(f) + ": expected nearest|literal|wrap_manager, got '" + std::string(v) +
                                  "'"};
             o.az_mapping = *mapping;
         }},
        {"--az-wrap-point", "DEG", "wrap_manager: display azimuth of the wrap point (default 0, north)",
         [](Options& o, auto f, auto v) { o.az_wrap_point = number_at_least(f, v, 0.0, 360.0); }},
        {"--g-aborts", "yes|no", "any byte aborts `g` (default yes, carryout2003 no)",
         [](Options& o, auto f, auto v) { o.g_aborts_on_input = yes_no(f, v); }},
        {"--g2-console", "captured|reconstructed",
         "which G2 console: the captured 02.02.48 one or the pre-capture reconstruction (default captured)",
         [](Options& o, auto f, auto v) {
             const auto console = birdcage::sim::parse_g2_console(v);
             if (!console)
                 throw UsageError{std::string(f) + ": expected captured|reconstructed, got '" + std::string(v) + "'"};
             o.g2_console = *console;
         }},
        {"--g2-root-q", "kill|harmless|restart",
         "G2 `q` at TRK> (default kill; harmless reprints TRK>; restart prints `Terminating shell.` and a new TRK>)",
         [](Options& o, auto f, auto v) {
             o.g2_root_q = choice<G2RootQ>(
                 f, v, {{"kill", G2RootQ::kill}, {"harmless", G2RootQ::harmless}, {"restart", G2RootQ::restart}});
         }},
        {"--g2-homed", "yes|no", "G2 axes calibrated at start (default yes)",
         [](Options& o, auto f, auto v) { o.g2_homed = yes_no(f, v); }},
        {"--g2-boot-homes", "yes|no", "G2 boot homes with NVS 20 TRUE (default: captured no, reconstructed yes)",
         [](Options& o, auto f, auto v) { o.g2_boot_homes = yes_no(f, v); }},
        {"--g2-boot-calibrated", "yes|no",
         "G2 axes keep their calibration through a boot without homing (default: captured yes, reconstructed no)",
         [](Options& o, auto f, auto v) { o.g2_boot_calibrated = yes_no(f, v); }},
        {"--g2-boot-seconds", "S", "captured G2: seconds from power-on to TRK> (default 10)",
         [](Options& o, auto f, auto v) { o.g2_boot_seconds = number_at_least(f, v, 0.0); }},
        {"--g2-overshoot", "yes|no",
         "G2 moves settle 0.01-0.06 deg past the target in the direction of travel (default no)",
         [](Options& o, auto f, auto v) { o.g2_overshoot = yes_no(f, v); }},
        {"--home-report", "wrap-limits|g2plus", "what `h` prints after AZ homing (default wrap-limits)",
         [](Options& o, auto f, auto v) {
             o.home_report = choice<HomeReport>(
                 f, v, {{"wrap-limits", HomeReport::wrap_limits}, {"g2plus", HomeReport::g2plus_status}});
         }},
        {"--prompt-style", "named|bare|bare-root",
         "Trav'ler/Carryout prompts `TRK>`, `>` everywhere, or `>` at the root only (default named)",
         [](Options& o, auto f, auto v) {
             o.prompt_style = choice<PromptStyle>(
                 f, v, {{"named", PromptStyle::named}, {"bare", PromptStyle::bare}, {"bare-root", PromptStyle::bare_root}});
         }},
        {"--prompt-space", "yes|no", "a space after the prompt (default no)",
         [](Options& o, auto f, auto v) { o.prompt_space = yes_no(f, v); }},
        {"--prompt-prefix", "TEXT", "a tag before every prompt, any variant (e.g. \"WG \"; default none)",
         [](Options& o, auto, auto v) { o.prompt_prefix = std::string(v); }},
        {"--prompt-suffix", "TEXT", "marks after every prompt's '>', any variant (e.g. $; default none)",
         [](Options& o, auto, auto v) { o.prompt_suffix = std::string(v); }},
        {"--hal205-marker", "nogps|no-lnb-voltage", "HAL 2.05 boot-complete line (default nogps)",
         [](Options& o, auto f, auto v) {
             o.hal205_boot_marker = choice<BootMarker>(
                 f, v, {{"nogps", BootMarker::no_gps}, {"no-lnb-voltage", BootMarker::no_lnb_voltage}});
         }},
        {"--travler-boot-moves", "park|home-return|none",
         "Trav'ler power-up calibration moves (default park: AZ 0, EL 45; home-return: AZ to 0 and back; none)",
         [](Options& o, auto f, auto v) {
             const auto moves = birdcage::sim::parse_travler_boot_moves(v);
             if (!moves)
                 throw UsageError{std::string(f) + ": expected park|home-return|none, got '" + std::string(v) + "'"};
             o.travler_boot_moves = *moves;
         }},
        {"--boot-moves-overlap", "S",
         "the boot goes on S s after its first move starts while the moves run on (default: it waits for them)",
         [](Options& o, auto f, auto v) { o.boot_moves_overlap = number_at_least(f, v, 0.0); }},
        {"--boot-move-pause", "S", "standstill between two of the boot's moves (default 0)",
         [](Options& o, auto f, auto v) { o.boot_move_pause = number_at_least(f, v, 0.0); }},
        {"--hal205-mot", "yes|no", "HAL 2.05 accepts `mot` as well as `motor` (default no)",
         [](Options& o, auto f, auto v) { o.hal205_accepts_mot = yes_no(f, v); }},
        {"--pro-q-returns-to-idu", "yes|no", "Pro `q` at the ODU root returns to the IDU (default no)",
         [](Options& o, auto f, auto v) { o.pro_q_at_odu_root_returns_to_idu = yes_no(f, v); }},
        {"--carryout-search-seconds", "S", "2003 Carryout search duration (default 600)",
         [](Options& o, auto f, auto v) { o.carryout_search_seconds = number_at_least(f, v, 0.0); }},
        {"--carryout-live-period", "S", "2003 Carryout `g` live line period (default 0.25)",
         [](Options& o, auto f, auto v) { o.carryout_live_line_period = number_at_least(f, v, 0.001); }},
        {"--rssi-floor", "N", "G2 RSSI floor (default 401)",
         [](Options& o, auto f, auto v) { o.rssi_floor = number_at_least(f, v, 0.0); }},
        {"--position-decimals", "N", "decimals in position replies (default 2)",
         [](Options& o, auto f, auto v) { o.position_decimals = static_cast<int>(integer_in(f, v, 0, 6)); }},
        {"--position-indent", "N", "spaces before position lines (default: captured G2 4, else 0)",
         [](Options& o, auto f, auto v) { o.position_indent = static_cast<int>(integer_in(f, v, 0, 16)); }},
        {"--position-layout", "one-line|per-axis", "Trav'ler `a` reply (default one-line)",
         [](Options& o, auto f, auto v) {
             o.travler_position_layout = choice<TravlerPositionLayout>(
                 f, v,
                 {{"one-line", TravlerPositionLayout::one_line}, {"per-axis", TravlerPositionLayout::line_per_axis}});
         }},
        {"--help-layout", "available|described|words|one-line|comma-line|colon-table|tab-table|labelled-line",
         "`?` listing (default: captured G2 available, else described)",
         [](Options& o, auto f, auto v) {
             o.help_layout = choice<HelpLayout>(f, v,
                                                {{"available", HelpLayout::available},
                                                 {"described", HelpLayout::described},
                                                 {"words", HelpLayout::words},
                                                 {"one-line", HelpLayout::one_line},
                                                 {"comma-line", HelpLayout::comma_line},
                                                 {"colon-table", HelpLayout::colon_table},
                                                 {"tab-table", HelpLayout::tab_table},
                                                 {"labelled-line", HelpLayout::labelled_line}});
         }},
        {"--unlisted", "yes|no", "G2 accepts MOT `l` and DVB `dis` without listing them in `?` (default no)",
         [](Options& o, auto f, auto v) { o.unlisted_commands = yes_no(f, v); }},
        {"--help-upper", "yes|no", "upper-case command words in `?` (default no)",
         [](Options& o, auto f, auto v) { o.help_upper_case = yes_no(f, v); }},
        {"--boot-line-gap", "S", "simulated seconds between boot lines (default 0.05)",
         [](Options& o, auto f, auto v) { o.boot_line_gap = number_at_least(f, v, 0.0); }},
        {"--line-rate", "yes|no", "pace all output at the variant's baud in simulated time (default no)",
         [](Options& o, auto f, auto v) { o.pace_at_line_rate = yes_no(f, v); }},
        {"--late-line-delay", "S", "G2: seconds from `Boot Complete` to `Loc Startup: ...` (default 0.05)",
         [](Options& o, auto f, auto v) { o.late_boot_line_delay = number_at_least(f, v, 0.0); }},
        {"--boot-input-drop-ms", "MS", "input dropped this long after the last boot line (default 0)",
         [](Options& o, auto f, auto v) { o.boot_input_drop = number_at_least(f, v, 0.0) / 1000.0; }},
        {"--motor-startup-delay", "S", "seconds from a move command to the first motion (default 0)",
         [](Options& o, auto f, auto v) { o.motor.startup_delay = number_at_least(f, v, 0.0); }},
        {"--motor-speed", "AZ,EL", "top speeds in deg/s (default: the variant's)",
         [](Options& o, auto f, auto v) {
             const auto comma = v.find(',');
             if (comma == std::string_view::npos)
                 throw UsageError{std::string(f) + ": expected AZ,EL"};
             o.motor.az_velocity = number_at_least(f, v.substr(0, comma), 1e-3);
             o.motor.el_velocity = number_at_least(f, v.substr(comma + 1), 1e-3);
         }},
        {"--motor-accel", "A", "acceleration in deg/s^2, both axes (default: the variant's)",
         [](Options& o, auto f, auto v) { o.motor.accel = number_at_least(f, v, 1e-3); }},
        {"--after-boot-line", "TEXT", "one more line after the last documented boot line (default none)",
         [](Options& o, auto, auto v) { o.after_boot_line = v; }},
        {"--idle-line", "TEXT", "unsolicited line printed every --idle-line-period",
         [](Options& o, auto, auto v) { o.idle_line = v; }},
        {"--idle-line-period", "S", "seconds between unsolicited lines (default 0 = never)",
         [](Options& o, auto f, auto v) { o.idle_line_period = number_at_least(f, v, 0.0); }},
    };
    return table;
}

void print_help() {
    std::cout
        << "Usage: birdcage-sim --variant VARIANT [options]   (--flag VALUE or --flag=VALUE)\n\n"
           "Runs one emulated Winegard dish console on a pty, prints `device: <path>`, stops on SIGINT/SIGTERM.\n"
           "Simulated seconds run --time-scale times faster than real ones. sim/README.md cites the evidence.\n\n";
    for (const Flag& flag : flags()) {
        std::string head = std::string("  ") + flag.name + (flag.value ? std::string(" ") + flag.value : "");
        std::cout << head;
        if (head.size() < 40) {
            std::cout << std::string(40 - head.size(), ' ');
        } else {
            std::cout << "\n" << std::string(40, ' ');
        }
        std::cout << flag.help << '\n';
    }
    std::cout << "  --help                                this text\n"
                 "  --version                             the program's version\n\n"
                 "Exit status: 0 stopped by a signal, 1 the emulator failed (e.g. a strict replay diverged),\n"
                 "2 usage error.\n";
}

Options parse(int argc, char** argv, Options options = {}) {
    for (int i = 1; i < argc; ++i) {
        std::string_view arg = argv[i];
        std::optional<std::string_view> inline_value;
        if (const std::size_t equals = arg.find('='); arg.starts_with("--") && equals != std::string_view::npos) {
            inline_value = arg.substr(equals + 1);
            arg = arg.substr(0, equals);
        }
        const auto& table = flags();
        const auto flag = std::find_if(table.begin(), table.end(), [&](const Flag& f) { return arg == f.name; });
        if (flag == table.end())
            throw UsageError{"unknown option '" + std::string(arg) + "' (see --help)"};
        std::string_view value;
        if (flag->value == nullptr) {
            if (inline_value)
                throw UsageError{std::string(arg) + " takes no value"};
        } else if (inline_value) {
            value = *inline_value;
        } else if (i + 1 < argc) {
            value = argv[++i];
        } else {
            throw UsageError{std::string(arg) + ": missing value " + flag->value};
        }
        flag->apply(options, arg, value);
    }
    if (options.replay != ReplayMode::off && options.transcript_path.empty())
        throw UsageError{"--lenient needs --replay"};
    if (have_lat != have_lon || (have_alt && !have_lat))
        throw UsageError{"--lat and --lon go together (--alt with them)"};
    if (sky_at && !options.station)
        throw UsageError{"--sky-at needs --lat and --lon"};
    return options;
}

// --sky-at: the sky of the real-sky model, for a check against an independent implementation
// (tests/sim/sky_positions.py) and for tests that need to know what a dish there hears.
// dish_az/dish_el: where the dish's axes point at it (--mount); peak_13v/peak_18v: counts above
// the floor at the beam's centre on each LNB supply (the belt's amplitudes follow --seed).
void print_sky(const Options& options, double utc) {
    using namespace birdcage::sim;
    const SkyModel sky(options.seed, options.rssi_floor, *options.station);
    const auto row = [&](const std::string& name, const std::string& longitude, AzEl at, double peak_13v,
                         double peak_18v) {
        const AzEl dish = sky_to_dish(options.mount, at);
        std::printf("%s,%s,%.6f,%.6f,%.6f,%.6f,%.1f,%.1f\n", name.c_str(), longitude.c_str(), at.az, at.el,
                    normalize_360(dish.az), dish.el, peak_13v, peak_18v);
    };
    std::printf("name,longitude_deg,sky_az,sky_el,dish_az,dish_el,peak_13v,peak_18v\n");
    row("Sun", "", sun_direction(*options.station, utc), SkyModel::sun_amplitude, SkyModel::sun_amplitude);
    for (std::size_t i = 0; i < sky.belt().size(); ++i) {
        const Satellite& satellite = sky.belt()[i];
        char longitude[32];
        std::snprintf(longitude, sizeof longitude, "%g", geostationary_catalogue()[i].longitude_deg);
        row(satellite.name, longitude, {satellite.az, satellite.el}, satellite.amplitude_13v, satellite.amplitude_18v);
    }
}

}  // namespace

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        if (std::string_view(argv[i]) == "--help" || std::string_view(argv[i]) == "-h") {
            print_help();
            return 0;
        }
        if (std::string_view(argv[i]) == "--version") {
            std::cout << "birdcage-sim " BIRDCAGE_VERSION "\n";
            return 0;
        }
    }
    Options options;
    try {
        options = parse(argc, argv);
    } catch (const UsageError& error) {
        std::cerr << "birdcage-sim: " << error.message << '\n';
        return 2;
    }
    if (sky_at) {
        print_sky(options, *sky_at);
        return 0;
    }
    if (!have_variant && !options.transcript_path.empty()) {
        try {
            const auto variant_name = birdcage::sim::load_transcript(options.transcript_path).header("Variant");
            const auto variant = variant_name ? birdcage::sim::parse_variant(*variant_name) : std::nullopt;
            if (variant) {
                options.variant = *variant;
                have_variant = true;
            }
        } catch (const std::exception& error) {
            std::cerr << "birdcage-sim: " << error.what() << '\n';
            return 1;
        }
    }
    if (!have_variant) {
        std::cerr << "birdcage-sim: --variant is required (hal205|g2|hal000|pro|carryout2003; see --help)\n";
        return 2;
    }
    if (dialect_mode != DialectMode::off) {
        // The drawn console first, then every flag again so that an explicit one wins.
        const birdcage::sim::Dialect dialect = birdcage::sim::draw_dialect(options.variant, options.seed);
        if (dialect_mode == DialectMode::describe) {
            std::cout << birdcage::sim::describe_console(dialect);
            return 0;
        }
        options = parse(argc, argv, dialect.options);
    }

    // Block the signals before the console thread exists so that only sigwait sees them.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    try {
        birdcage::sim::Emulator emulator(options);
        std::cout << "device: " << emulator.device_path() << std::endl;
        // A strict replay that fails has nothing more to say: report the diff and stop.
        const timespec check_period{0, 100'000'000};
        bool reported_complete = false;
        // At every exit, also a failed replay: how many hazards the dish received, and which.
        const auto report_hazards = [&emulator] {
            const auto lines = emulator.hazard_commands();
            std::cerr << "birdcage-sim: hazards received: " << emulator.hazards_received();
            for (std::size_t i = 0; i < lines.size() && i < 20; ++i)
                std::cerr << (i == 0 ? " (" : ", ") << '"' << lines[i] << '"';
            std::cerr << (lines.empty() ? "" : lines.size() > 20 ? ", ...)" : ")") << '\n';
        };
        for (;;) {
            if (sigtimedwait(&stop_signals, nullptr, &check_period) >= 0)
                break;
            if (const auto failure = emulator.replay_failure()) {
                std::cerr << *failure;
                report_hazards();
                return 1;
            }
            if (!reported_complete && emulator.replay_complete()) {
                std::cerr << "birdcage-sim: replay complete\n";
                reported_complete = true;
            }
        }
        report_hazards();
    } catch (const std::exception& error) {
        std::cerr << "birdcage-sim: " << error.what() << '\n';
        return 1;
    }
    return 0;
}
