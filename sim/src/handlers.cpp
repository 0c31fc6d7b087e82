// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "handlers.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace birdcage::sim::handlers {
namespace {

std::optional<double> parse_number(std::string_view text) {
    const std::string owned(text);
    char* end = nullptr;
    const double value = std::strtod(owned.c_str(), &end);
    if (owned.empty() || end == nullptr || *end != '\0' || !std::isfinite(value))
        return std::nullopt;
    return value;
}

std::optional<int> parse_int(std::string_view text) {
    const auto value = parse_number(text);
    if (!value || *value != std::floor(*value) || std::abs(*value) > 1e9)
        return std::nullopt;
    return static_cast<int>(*value);
}

__attribute__((format(printf, 1, 2))) std::string format(const char* pattern, ...) {
    char text[256];
    va_list arguments;
    va_start(arguments, pattern);
    std::vsnprintf(text, sizeof text, pattern, arguments);
    va_end(arguments);
    return text;
}

long centi(double degrees) {
    return std::lround(degrees * 100.0);
}

constexpr double unhomed_angle = INT_MAX;  // §6.4: uncalibrated axes read 2147483647

// `<label><value>` with Options::position_decimals.
std::string field(Engine& e, const char* label, double value) {
    return format("%s%.*f", label, std::clamp(e.options.position_decimals, 0, 6), value);
}

void print_position(Engine& e) {
    const double el = e.motors.axis(axis_el).position();
    const std::string indent(e.reply_indent(), ' ');
    if (e.profile.position_format == PositionFormat::travler) {
        // §3.3: `AZ = ` / `EL = ` with one space before '='.
        const std::string az = field(e, "AZ = ", e.reported_az());
        const std::string elevation = field(e, "EL = ", el);
        const std::string skew = field(e, "SK = ", e.motors.axis(axis_skew).position());
        if (e.options.travler_position_layout == TravlerPositionLayout::one_line) {
            e.print_line(indent + az + " " + elevation + " " + skew);
        } else {
            for (const std::string& line : {az, elevation, skew})
                e.print_line(indent + line);
        }
        return;
    }
    e.print_line(indent + field(e, "Angle[0] = ", e.homed[axis_az] ? e.reported_az() : unhomed_angle));
    e.print_line(indent + field(e, "Angle[1] = ", e.homed[axis_el] ? el : unhomed_angle));
}

// §6.3 error string (known for EL; the AZ form is the obvious analogue, INVENTED).
bool refuse_if_unhomed(Engine& e, std::size_t axis) {
    if (!e.profile.needs_homing || e.homed[axis])
        return false;
    e.count_hazard();
    e.print_line(format("Step to Position %s angle error: %d", axis == axis_az ? "AZ" : "EL", INT_MAX));
    return true;
}

// Mechanical target for a requested angle, or nullopt after printing the refusal.
std::optional<double> resolve_target(Engine& e, std::size_t axis, double value, bool relative) {
    const Axis& motor = e.motors.axis(axis);
    const double base = motor.target();
    const auto out_of_range = [&](double clamped) -> std::optional<double> {
        if (e.options.out_of_range == OutOfRange::reject) {
            e.print_line(e.options.out_of_range_reply);
            return std::nullopt;
        }
        return clamped;
    };
    if (axis == axis_az) {
        const double min = e.profile.az.min;
        const double max = e.profile.az.max;
        const auto within = [&](double target) -> std::optional<double> {
            if (target < min - 1e-9 || target > max + 1e-9)
                return out_of_range(std::clamp(target, min, max));
            return target;
        };
        switch (e.options.az_mapping) {
            case AzMapping::wrap_manager:
                // Relative moves too: the manager never lets the axis through the wrap point.
                return within(wrap_manager_target(relative ? base + value : value, e.options.az_wrap_point,
                                                  motor.position(), min, max));
            case AzMapping::literal:
                if (relative || (value >= min && value <= max))
                    return within(relative ? base + value : value);
                // No negative absolute numbers exist on a console where '-' means relative (G2): there
                // a number names the angle 360 below it (see AzMapping).
                if (e.profile.relative_moves && value - 360.0 >= min && value - 360.0 <= max)
                    return value - 360.0;
                return within(value);
            case AzMapping::nearest:
                break;
        }
        if (relative)
            return within(base + value);
        // A 0..360 target goes to the branch of the wrap window nearest to where the dish is
        // (§2 "refuses to wind past its wrap limit", docs/tracking.md §2.3); an explicit
        // mechanical angle inside the window (Trav'ler 360..455) is taken literally.
        if (value >= 0.0 && value < 360.0)
            return nearest_wrap_branch(value, base, min, max);
        if (value >= min && value <= max)
            return value;
        return nearest_wrap_branch(value, base, min, max);
    }
    if (axis == axis_el) {
        double target = relative ? base + value : value;
        if (target < e.el_limit_min() || target > e.el_limit_max()) {
            const auto accepted = out_of_range(std::clamp(target, e.el_limit_min(), e.el_limit_max()));
            if (!accepted)
                return std::nullopt;
            target = *accepted;
        }
        if (target > e.profile.el_stall_above) {  // Pro: stalls at ~75 (§5.4, §5.5)
            e.count_hazard();
            target = e.profile.el_stall_above;
        }
        return target;
    }
    return relative ? base + value : value;
}

// Options::g2_overshoot: the captured settling error (§6.4), AZ +0.01 / -0.02 and EL +0.05 / -0.06
// for moves up / down, applied to where the motor stops (the acknowledgement shows the target).
double with_overshoot(const Engine& e, std::size_t axis, double target) {
    if (!e.options.g2_overshoot || e.profile.variant != Variant::carryout_g2 || axis > axis_el)
        return target;
    const bool upward = target >= e.motors.axis(axis).target();
    const double error = axis == axis_az ? (upward ? 0.01 : -0.02) : (upward ? 0.05 : -0.06);
    return target + error;
}

std::optional<std::size_t> parse_axis(Engine& e, std::string_view text) {
    const auto id = parse_int(text);
    if (!id || *id < 0)
        return std::nullopt;
    const int last = e.profile.position_format == PositionFormat::travler ? 2 : 1;
    if (*id > last)
        return std::nullopt;
    return static_cast<std::size_t>(*id);
}

void print_live_position(Engine& e) {
    // §8.4 reconstruction: `el` three tokens after the AZ centidegrees, one before EL's.
    e.print_line(format("az = %ld   el = %ld", centi(e.displayed_az()), centi(e.motors.axis(axis_el).position())));
}

}  // namespace

void angle(Engine& e, const Args& args) {
    if (args.size() == 1) {
        if (!e.options.answer_position_while_moving && e.motors.moving()) {
            e.wait_until_idle(print_position);
        } else {
            print_position(e);
        }
        return;
    }
    if (args.size() == 2 && e.captured_g2()) {
        // `a [[[motor] [[+|-]angle]]]` (the captured listing): one motor's line (INF).
        const auto axis = parse_axis(e, args[1]);
        if (!axis) {
            e.invalid_params();
            return;
        }
        const double value = *axis == axis_az ? e.reported_az() : e.motors.axis(axis_el).position();
        e.print_line(std::string(e.reply_indent(), ' ') + field(e, *axis == axis_az ? "Angle[0] = " : "Angle[1] = ",
                                                                e.homed[*axis] ? value : unhomed_angle));
        return;
    }
    const auto axis = args.size() == 3 ? parse_axis(e, args[1]) : std::nullopt;
    const auto value = args.size() == 3 ? parse_number(args[2]) : std::nullopt;
    if (!axis || !value) {
        e.invalid_params();
        return;
    }
    if (refuse_if_unhomed(e, *axis))
        return;
    const bool relative = e.profile.relative_moves && (args[2].front() == '+' || args[2].front() == '-');
    const auto target = resolve_target(e, *axis, *value, relative);
    if (!target)
        return;
    e.motors.enqueue(*axis, with_overshoot(e, *axis, *target));
    if (e.profile.move_ack_angle) {
        double shown = *target;
        if (*axis == axis_az && e.options.az_report == AzReport::displayed)
            shown = normalize_360(shown);
        e.print_line(std::string(e.reply_indent(), ' ') + field(e, "Angle = ", shown));
    }
    if (e.options.move_ack == MoveAck::after_motion)
        e.wait_until_idle(nullptr);
}

void go_to(Engine& e, const Args& args) {
    const bool with_skew = e.profile.position_format == PositionFormat::travler && args.size() == 4;
    if (args.size() != 3 && !with_skew) {
        e.invalid_params();
        return;
    }
    const auto az = parse_number(args[1]);
    const auto el = parse_number(args[2]);
    const auto skew = with_skew ? parse_number(args[3]) : std::optional<double>(0.0);
    if (!az || !el || !skew) {
        e.invalid_params();
        return;
    }
    if (refuse_if_unhomed(e, axis_az) || refuse_if_unhomed(e, axis_el))
        return;
    const auto az_target = resolve_target(e, axis_az, *az, false);
    if (!az_target)
        return;
    const auto el_target = resolve_target(e, axis_el, *el, false);
    if (!el_target)
        return;
    e.motors.enqueue(axis_az, *az_target);
    e.motors.enqueue(axis_el, *el_target);
    if (with_skew)
        e.motors.enqueue(axis_skew, *skew);
    e.start_goto(e.profile.live_goto_output ? print_live_position : nullptr);
}

namespace {

// The captured homing output (§6.3, `h *`): each axis announces itself, runs to its stop and
// reports; AZ runs to the top of its travel, then back to its zero.
void print_az_home_report(Engine& e) {
    if (e.options.home_report == HomeReport::g2plus_status) {
        e.print_line("AZ - Angle: 1 Wrap: 0");  // §7.1: shape inferred from mjlangan's regex
    } else {
        e.print_line(
            format("home:0  wrap_pos:0  wrap_min:%ld  wrap_max:%ld", centi(e.profile.az.min), centi(e.profile.az.max)));
    }
}

void home_az_captured(Engine& e) {
    e.print_line("MotorHome:0 timeout:8000");
    e.print_line("Home TwelInch Az");
    e.motors.enqueue(axis_az, e.profile.az.max);
    e.homed[axis_az] = true;
    e.wait_until_idle([](Engine& engine) {
        engine.print_line("End MotorAzStall:part1");
        engine.motors.enqueue(axis_az, engine.profile.home_az);
        engine.wait_until_idle([](Engine& done) {
            done.print_line("Antenna Facing Front");
            print_az_home_report(done);
        });
    });
}

void home_captured(Engine& e, bool home_el, bool home_az) {
    if (!home_el) {
        home_az_captured(e);
        return;
    }
    e.print_line("MotorHome:1 timeout:2000");
    e.print_line(format("Home TwelInch El   Velocity: %ld", centi(e.motors.axis(axis_el).params().max_velocity)));
    e.motors.enqueue(axis_el, e.profile.home_el);
    e.homed[axis_el] = true;
    e.wait_until_idle([home_az](Engine& engine) {
        engine.print_line("EL Stall Timeout");
        engine.print_line(format("El Home Angle: %ld", centi(engine.profile.home_el)));
        if (!home_az)
            return;
        engine.print_line("");
        home_az_captured(engine);
    });
}

}  // namespace

void home(Engine& e, const Args& args) {
    if (args.size() != 2 || !(args[1] == "0" || args[1] == "1" || args[1] == "*")) {
        e.invalid_params();
        return;
    }
    const bool home_el = args[1] != "0";
    const bool home_az = args[1] != "1";
    if (e.captured_g2()) {
        home_captured(e, home_el, home_az);
        return;
    }
    if (home_el) {
        e.motors.enqueue(axis_el, e.profile.home_el);
        e.homed[axis_el] = true;
    }
    if (home_az) {
        // Stall detection finds the hard stop at the top of the wrap window, then the axis
        // returns to its zero (§6.3 `h`, §6.4).
        e.motors.enqueue(axis_az, e.profile.az.max);
        e.motors.enqueue(axis_az, e.profile.home_az);
        e.homed[axis_az] = true;
    }
    e.wait_until_idle([home_az](Engine& engine) {
        if (!home_az)
            return;
        if (engine.options.home_report == HomeReport::g2plus_status) {
            engine.print_line("AZ - Angle: 1 Wrap: 0");  // §7.1: shape inferred from mjlangan's regex
        } else {
            engine.print_line(
                format("wrap_min:%ld wrap_max:%ld", centi(engine.profile.az.min), centi(engine.profile.az.max)));
        }
    });
}

namespace {

// The step counter of the angle `a` shows: the capture's `p` reads 19998 where `a` reads 179.98
// (§6.3), although 179.98 lies outside the travel the homing report gives (§6.4).
long motor_steps(const Engine& e, std::size_t axis) {
    const Axis& motor = e.motors.axis(axis);
    const double angle = axis == axis_az ? e.reported_az() : motor.position();
    return std::lround(angle / 360.0 * motor.params().steps_per_rev);
}

}  // namespace

// MOT `p`: the step counters; `p <motor> <pos>` goes to a step position (the captured listing's
// "Go To Position [motor] [pos]"). The reply's text is the capture's paraphrase (§6.3), its
// indentation that of the captured one-line MOT replies (INF).
void step_positions(Engine& e, const Args& args) {
    if (args.size() > 1 && e.captured_g2()) {
        const auto axis = args.size() == 3 ? parse_axis(e, args[1]) : std::nullopt;
        const auto steps = args.size() == 3 ? parse_number(args[2]) : std::nullopt;
        if (!axis || !steps) {
            e.invalid_params();
            return;
        }
        if (refuse_if_unhomed(e, *axis))
            return;
        const auto target =
            resolve_target(e, *axis, *steps * 360.0 / e.motors.axis(*axis).params().steps_per_rev, false);
        if (target)
            e.motors.enqueue(*axis, *target);
        return;
    }
    e.print_line(std::string(e.reply_indent(), ' ') +
                 format("Position[0] = %ld  Position[1] = %ld", motor_steps(e, axis_az), motor_steps(e, axis_el)));
}

void max_velocity(Engine& e, const Args& args) {
    if (args.size() > 1)
        return;             // setting is accepted but not modelled
    if (e.captured_g2()) {  // §6.3, the capture's paraphrase: one line, one decimal
        e.print_line(std::string(e.reply_indent(), ' ') + format("Max Vel[0] = %.1f  Max Vel[1] = %.1f",
                                                                 e.motors.axis(axis_az).params().max_velocity,
                                                                 e.motors.axis(axis_el).params().max_velocity));
        return;
    }
    e.print_line(format("Max Vel [0] = %.2f", e.motors.axis(axis_az).params().max_velocity));
    e.print_line(format("Max Vel [1] = %.2f", e.motors.axis(axis_el).params().max_velocity));
}

void max_accel(Engine& e, const Args& args) {
    if (args.size() > 1)
        return;
    if (e.captured_g2()) {
        e.print_line(std::string(e.reply_indent(), ' ') + format("Accel[0] = %.1f  Accel[1] = %.1f",
                                                                 e.motors.axis(axis_az).params().max_accel,
                                                                 e.motors.axis(axis_el).params().max_accel));
        return;
    }
    e.print_line(format("Accel[0] = %.2f", e.motors.axis(axis_az).params().max_accel));
    e.print_line(format("Accel[1] = %.2f", e.motors.axis(axis_el).params().max_accel));
}

void el_min_max_home(Engine& e, const Args&) {
    e.print_line(std::string(e.captured_g2() ? e.reply_indent() : 0, ' ') +
                 format("Min: %ld  Max: %ld  Home: %ld", centi(e.el_limit_min()), centi(e.el_limit_max()),
                        centi(e.profile.home_el)));
}

// `ela2s <angle>` / `els2a <steps>`: the linear law the capture found (24960 steps per turn,
// angles held to the limits with a `Min:`/`Max:` warning, steps truncated). Reply text INVENTED.
void el_angle_to_steps(Engine& e, const Args& args) {
    const auto angle = args.size() == 2 ? parse_number(args[1]) : std::nullopt;
    if (!angle) {
        e.invalid_params();
        return;
    }
    double held = *angle;
    if (held < e.el_limit_min()) {
        e.print_line(format("Min: %ld", centi(e.el_limit_min())));
        held = e.el_limit_min();
    } else if (held > e.el_limit_max()) {
        e.print_line(format("Max: %ld", centi(e.el_limit_max())));
        held = e.el_limit_max();
    }
    const int per_turn = e.motors.axis(axis_el).params().steps_per_rev;
    e.print_line(std::string(e.reply_indent(), ' ') +
                 format("Steps = %ld", static_cast<long>(held * per_turn / 360.0)));
}

void el_steps_to_angle(Engine& e, const Args& args) {
    const auto steps = args.size() == 2 ? parse_number(args[1]) : std::nullopt;
    if (!steps) {
        e.invalid_params();
        return;
    }
    const int per_turn = e.motors.axis(axis_el).params().steps_per_rev;
    e.print_line(std::string(e.reply_indent(), ' ') + format("Angle = %.2f", *steps * 360.0 / per_turn));
}

// A command that needs arguments (§6.3: `st` without them answers `Invalid params`); with them it
// is accepted and, in this emulator, has no effect (motor tests, PID, wrap and position registers,
// velocity modes, DiSEqC packets: no client of this project uses them).
void setter(Engine& e, const Args& args) {
    if (args.size() < 2)
        e.invalid_params();
}

void silent(Engine&, const Args&) {}

void list_motors(Engine& e, const Args&) {
    if (e.captured_g2()) {  // §6.3, verbatim
        e.print_line("Motors:");
        e.print_line("    0 - AZIMUTH: local");
        e.print_line("    1 - ELEVATION: local");
        return;
    }
    // The reconstruction: "list motors: 0 AZIMUTH, 1 ELEVATION", one per line INVENTED.
    e.print_line("0 AZIMUTH");
    e.print_line("1 ELEVATION");
}

void nvs_dump(Engine& e, const Args& args) {
    if (args.size() >= 2) {
        const auto index = parse_int(args[1]);
        const NvsEntry* entry = index ? e.nvs.find(*index) : nullptr;
        if (entry == nullptr)
            return;
        e.print_line(NvsTable::header());
        e.print_line(NvsTable::rule());
        e.print_line(NvsTable::row(*entry));
        e.nvs_cursor = entry->index;
        return;
    }
    e.print_line(NvsTable::header());
    e.print_line(NvsTable::rule());
    std::size_t shown = 0;
    for (const NvsEntry& entry : e.nvs.entries()) {
        if (e.profile.nvs_page_rows != 0 && entry.index <= e.nvs_cursor)
            continue;
        e.print_line(NvsTable::row(entry));
        e.nvs_cursor = entry.index;
        if (e.profile.nvs_page_rows != 0 && ++shown == e.profile.nvs_page_rows)
            return;
    }
    e.nvs_cursor = -1;  // the next page starts over
}

void nvs_edit(Engine& e, const Args& args) {
    const auto index = args.size() >= 2 ? parse_int(args[1]) : std::nullopt;
    NvsEntry* entry = index ? e.nvs.find(*index) : nullptr;
    if (entry == nullptr || args.size() > 3) {
        e.invalid_params();
        return;
    }
    e.nvs_cursor = entry->index;
    if (args.size() == 2) {
        e.print_line(NvsTable::row(*entry));
        return;
    }
    e.count_hazard();
    const auto value = NvsTable::parse_value(*entry, args[2]);
    if (!value) {
        e.invalid_params();
        return;
    }
    const double old_value = entry->current;
    entry->current = *value;  // pending until `s`, effective after reboot (§2)
    e.print_line(NvsTable::edit_row(*entry, old_value));
}

void nvs_save(Engine& e, const Args&) {
    e.count_hazard();
    e.nvs.save_all();
    // Davidson's verbatim transcript (§6.3).
    e.print_line("    Saving ... ");
    e.print_line("Flash file flashx:bank0 opened");
    e.print_line("Flash sector cache enabled.");
    e.print_line("Flash doneSuccess");
}

// §6.3: any unrecognised input in NVS> reads the next index.
void nvs_next(Engine& e, const Args&) {
    const NvsEntry* entry = e.nvs.next_after(e.nvs_cursor);
    if (entry == nullptr)
        return;
    e.print_line(NvsTable::row(*entry));
    e.nvs_cursor = entry->index;
}

void os_id(Engine& e, const Args&) {
    // Appendix B.
    for (const char* line :
         {"NVS Version:    1.02.13", "System ID:  TWELINCH", " K60-144pin", " Silicon Rev 2.4", " Mask Set 4N22D",
          " 512 kBytes of P-flash", " P-flash only", " 128 kBytes of RAM", " Board Rev ID:         A",
          " Board ID:             STATIONARY", " Ant ID:               12-IN G2", " Software version:     02.02.48",
          " CCLK:                 96000000", " BCLK:                 48000000", " Flash Base Address:   65536",
          " Flash Size:           458752"})
        e.print_line(line);
}

void os_tasks(Engine& e, const Args&) {
    // §14 HAL0.8: the listing is unknown; INVENTED, only the task name `Search` is known.
    e.print_line("Shell");
    e.print_line("Motor");
    if (e.search)
        e.print_line("Search");
}

void os_kill(Engine& e, const Args& args) {
    if (args.size() != 2) {
        e.invalid_params();
        return;
    }
    if (args[1] == "Search" && e.profile.search_stop == SearchStop::os_kill && e.search)
        e.stop_search();
}

void ngsearch_stop(Engine& e, const Args&) {
    if (e.profile.search_stop == SearchStop::ngsearch_stop && e.search)
        e.stop_search();
}

void reboot(Engine& e, const Args&) {
    e.count_hazard();
    e.reboot();
}

void stow(Engine& e, const Args&) {
    e.count_hazard();
    if (e.search)
        e.stop_search();
    e.motors.enqueue(axis_el, e.profile.stow_el);  // firmware limits do not apply to stow
}

void dvb_rssi(Engine& e, const Args& args) {
    const auto count = args.size() >= 2 ? parse_int(args[1]) : std::optional<int>(1);
    if (!count || *count < 1 || args.size() > 2) {
        e.invalid_params();
        return;
    }
    const int reads = std::min(*count, 100000);
    // n samples at a 20 ms interval (§6.3); the reply comes when they are done.
    e.wait_for(reads * 0.02, [reads](Engine& engine) {
        long sum = 0;
        int current = 0;
        for (int i = 0; i < reads; ++i) {
            current = engine.read_rssi();
            sum += current;
        }
        engine.print_line(format("iterations:%d  interval(msec):20", reads));
        engine.print_line(format(" Reads:%d  RSSI[avg: %ld  cur: %d]", reads,
                                 std::lround(static_cast<double>(sum) / reads), current));
    });
}

void dvb_lnbdc(Engine& e, const Args& args) {
    // §6.3: reply text undocumented; prints nothing.
    if (args.size() == 2 && args[1] == "odu") {
        e.lnb_supply = LnbSupply::odu_13v;
    } else if (args.size() == 2 && args[1] == "stb") {
        e.lnb_supply = LnbSupply::stb_18v;
    } else {
        e.invalid_params();
    }
}

void dvb_config(Engine& e, const Args&) {
    e.print_line("BCM Hardware=  ID: 0x4515  VER: 0xB0");
    e.print_line("BCM Firmware=  MAJOR VER: 0x71 (113)  MINOR VER: 0x25 (37)");
    e.print_line("BCM Strap Config: 0x25018");
}

void dvb_quick_lock(Engine& e, const Args&) {
    const auto line = [](Engine& engine) { engine.print_line(format("Lock:0  rssi:%d  cnt:0", engine.read_rssi())); };
    if (!e.captured_g2()) {  // the reconstruction printed one line
        line(e);
        return;
    }
    line(e);
    e.start_stream(0.1, false, line);  // §6.3: streams about every 100 ms until interrupted
}

// DVB/PEAK streaming commands (§6.3, §6.5): a line per period until a byte arrives. `ls` and
// `rssits` end the submenu's shell when interrupted (`Terminating shell.`, back at TRK>). Line
// texts are the capture's samples; periods INVENTED except `rssits` (a minute).
void dvb_stream(Engine& e, const Args& args) {
    const std::string_view word = args.front();
    const auto rssi = [](Engine& engine) { return engine.read_rssi(); };
    auto reads = std::make_shared<long>(0);
    if (word == "snr") {
        e.start_stream(0.1, false,
                       [reads](Engine& en) { en.print_line(format("Reads:%ld  SNR[avg: 0.0  cur: 0.0]", ++*reads)); });
    } else if (word == "agc") {
        e.start_stream(0.1, false, [reads](Engine& en) {
            en.print_line(
                format("Reads:%ld  RF_AGC[avg: 1327353088  cur: 1327353088] IF_AGC[avg: 2684354560  cur: "
                       "2684354560]  SNR: 0.0  NID: FFFF/none",
                       ++*reads));
        });
    } else if (word == "lnbv") {
        e.start_stream(0.1, false, [reads](Engine& en) {
            const bool low = en.lnb_supply == LnbSupply::odu_13v;
            en.print_line(format("Reads:%ld  LNB Voltage (mV): %d  ( ADC value: %d )", ++*reads, low ? 13182 : 18204,
                                 low ? 118 : 163));
        });
    } else if (word == "nid") {
        e.start_stream(0.1, false, [](Engine& en) { en.print("nid: FFFF/none\r"); });  // overwritten in place
    } else if (word == "stats") {
        e.start_stream(0.1, false, nullptr);  // silent without a lock
    } else if (word == "ls") {
        e.count_hazard();
        e.start_stream(0.5, true, [reads](Engine& en) {
            en.print_line(format("Xp:%ld  Freq:974000 SymRate:20000 Mode:blind_scan no_lock", *reads % 32 + 1));
            ++*reads;
        });
    } else if (word == "rssits") {
        e.count_hazard();
        e.start_stream(60.0, true, [rssi](Engine& en) { en.print_line(format("%d", rssi(en))); });
    }
}

void dvb_fixed_reply(Engine& e, const Args& args) {
    // One-shot DVB replies as the capture paraphrases them (§6.3); with arguments (the timeouts'
    // setters, `di2cs`'s switch configuration) accepted silently.
    const std::string_view word = args.front();
    if (args.size() > 1)
        return;
    static const std::pair<std::string_view, std::string_view> replies[] = {
        {"freqs", "Non-Stacked"},
        {"range", "Transponder Range: [ 1 - 32 ]"},
        {"pwr", "SDS and DiSEqC core power enabled"},
        {"srch_mode", "Auto Search Mode: 1"},
        {"tabto", "Timeout (msec):  Acq:4000  NID:20000  Signal Detect:0"},
        {"to", "Timeout (msec):  Acq:500  NID:12000"},
        {"di2id", "LNB Read HW ID FAIL"},
        {"di2stat", "LNB Read Status FAIL"},
        {"di2conf", "LNB Read Config FAIL"},
        {"di2sc", "LNB Short Circuit FAIL"},
        {"di2rcs", "LNB Switch State FAIL"},
        {"di2cs", "No Parameters Specified"},
    };
    for (const auto& [command, reply] : replies)
        if (command == word)
            e.print_line(reply);
}

// §6.3: "the channel parameters"; the layout and values are INVENTED.
void dvb_channel(Engine& e, const Args&) {
    const bool at_13v = e.lnb_supply == LnbSupply::odu_13v;
    if (!e.captured_g2()) {
        e.print_line(format("Freq:1450000  SymRate:20000  Pol:%s  Lock:0", at_13v ? "V" : "H"));  // INVENTED
        return;
    }
    // The captured table (§6.7), taken after `lnbdc odu`. Its row 5 at 18 V is not captured: the
    // boot's `Enabled LNB ODU 18V` suggests the same label with the other voltage (INF).
    static constexpr const char* head[] = {
        "Power Mode:           ON",
        "Search Transponders:  ON",
        "Auto Search Mode:     1",
        "Shuffle Mode:         ON",
        "Frequency List:       Non-Stacked",
        "",
        "Num  Parameter            Current                  Default",
        "1    Frequency            1090640 (kHz)            974000 (kHz)",
        "2    Symbol Rate          0 (PeakScanEnabled)      20000 (ksps)",
        "3    Trans_Mod_CRate      blind_scan               blind_scan",
        "4    Blind Scan Mode      ___trb_dvb_dss_____      ___trb_dvb_dss_____",
    };
    static constexpr const char* tail[] = {
        "6    LNB Tone (ODU)       off                      off",
        "7    Roll-off             0.35                     0.35",
        "8    LPF Cutoff           0 (auto)                 0 (MHz)",
        "9    Carrier Offset       0 (kHz)                  0 (kHz)",
        "10   FreqSearchRange      5000 (kHz)               5000 (kHz)",
        "11   DCII Mode            dcii_qpsk_comb           dcii_qpsk_comb",
        "12   Spectral Inv         scan                     scan",
        "13   PScnSymRtRngMin      18000 (ksps)             18000 (ksps)",
        "14   PScnSymRtRngMax      24000 (ksps)             24000 (ksps)",
        "15   SignalDetectMode      off                     off",
    };
    for (const char* line : head)
        e.print_line(line);
    e.print_line(format("5    LNB Polarity         ODU:%s                  ---", at_13v ? "13V" : "18V"));
    for (const char* line : tail)
        e.print_line(line);
}

void hazard_only(Engine& e, const Args&) {
    e.count_hazard();
}

void eeprom_read(Engine& e, const Args& args) {
    const auto index = args.size() >= 2 ? parse_int(args[1]) : std::nullopt;
    if (!index) {
        e.invalid_params();
        return;
    }
    if (!e.captured_g2()) {
        e.print_line(format("Index:%d Read value = 0", *index));  // the reconstruction's, INVENTED
        return;
    }
    // §6.3: 17 indices; the captured unit's dump (indices 1-5 valid, the rest the 0x00010101
    // sentinel). Out of range verbatim; the read texts are the capture's paraphrase.
    if (*index < 0 || *index > 16) {
        e.print_line(format("Index out of bounds:%d Min:0 Max:16", *index));
        return;
    }
    if (args.size() > 2)
        return;  // a write: accepted, not modelled
    constexpr long valid[] = {0, 0, 22897, 3748, 4346, 11637};
    if (*index >= 1 && *index <= 5) {
        e.print_line(format("Read value = %ld", valid[*index]));
    } else {
        e.print_line("Failed to read. val:65793");
    }
}

void adc_board_id(Engine& e, const Args&) {
    e.print_line("STATIONARY");
}
void adc_board_rev(Engine& e, const Args&) {
    e.print_line("A");
}

void adc_rssi(Engine& e, const Args&) {
    std::uniform_int_distribution<int> noise(233, 238);  // raw ADC floor (§6.3 ADC>)
    e.print_line(format("%d", noise(e.rng)));
}

void adc_scan(Engine& e, const Args& args) {
    if (args.size() == 1) {
        // §6.5: targets 2147483647 and blocks forever; nothing recovers but a power cycle.
        e.count_hazard();
        e.kill_shell("");
    }
}

void a3981_diag(Engine& e, const Args&) {
    e.print_line("AZ DIAG: OK");
    e.print_line("EL DIAG: OK");
}

// A3981 `ss` and `reset` as captured; `sm` and `cm` as the capture paraphrases them (§6.3).
void a3981_reply(Engine& e, const Args& args) {
    const std::string_view word = args.front();
    if (word == "ss") {
        e.print_line("KEY: FULL-16, HALF-8, QTR-4, EIGHTH-2, SIXTEENTH-1");
        e.print_line("AZ Step Size:1");
        e.print_line("EL Step Size:1");
    } else if (word == "sm") {
        e.print_line("AZ Step Size Mode = AUTO");
        e.print_line("EL Step Size Mode = AUTO");
    } else if (word == "cm") {
        e.print_line("AZ: Mode = AUTO");
        e.print_line("EL: Mode = AUTO");
    } else if (word == "reset") {
        e.print_line("Az/El A3981 Faults Reset.");
    }
}

// LATLON `l <satlon1> <satlon2> <satel1> <satel2>` (§6.3): the echo line as captured; the position
// is the captured example's for every input (the firmware's algorithm is unknown).
void latlon(Engine& e, const Args& args) {
    if (args.size() != 5) {
        e.invalid_params();
        return;
    }
    long centis[4];
    for (std::size_t i = 0; i < 4; ++i) {
        const auto value = parse_number(args[i + 1]);
        if (!value) {
            e.invalid_params();
            return;
        }
        centis[i] = centi(*value);
    }
    e.print_line(format(" anglesentered = %ld %ld %ld %ld", centis[0], centis[1], centis[2], centis[3]));
    e.print_line("    Lat = 4295  Lon = 25655");
}

// PEAK `ts` (§6.5): probes a DiSEqC switch for ever; nothing typed stops it, only a power cycle.
void peak_switch_test(Engine& e, const Args&) {
    e.count_hazard();
    e.start_stream(
        0.1, false, [](Engine& engine) { engine.print_line("0b0000 0"); }, true);
}

// PEAK `stb` (§6.3, as captured): the supply is left at STB.
void peak_stb(Engine& e, const Args&) {
    for (const char* line : {"Enabled LNB ODU 18V", "Even_sig = 504", "Enabled LNB STB", "Odd_sig = 232",
                             "Enabled LNB STB", "Odd_sig = 233 Ctr = 0"})
        e.print_line(line);
}

void dipswitch(Engine& e, const Args&) {
    e.print_line("val:ffffff01");
    e.print_line("app_dipswitch:101");
}

// STEP> replies: the capture's paraphrases (§6.3), one line each; the reconstruction printed one
// line per motor.
void step_max_velocity(Engine& e, const Args&) {
    if (e.captured_g2()) {
        e.print_line("Max Vel [0] = 7222    Max Vel [1] = 3120");
        return;
    }
    e.print_line("Max Vel [0] = 7222");
    e.print_line("Max Vel [1] = 3120");
}

void step_accel(Engine& e, const Args&) {
    if (e.captured_g2()) {
        e.print_line("Accel[0] = 44         Accel[1] = 28");
        return;
    }
    e.print_line("Accel[0] = 44");
    e.print_line("Accel[1] = 28");
}

void step_engage(Engine& e, const Args&) {
    e.print_line("Motors engaged");
}

void step_reply(Engine& e, const Args& args) {
    if (args.front() == "pid") {
        if (args.size() == 1)
            e.print_line("Kp=250  Kv=50");
        return;
    }
    if (args.size() > 1)
        return;  // `p <motor> <pos>`: a raw step move, not modelled
    e.print_line(format("Step Pos[0] = %-9ld Step Pos[1] = %ld", motor_steps(e, axis_az), motor_steps(e, axis_el)));
}

}  // namespace birdcage::sim::handlers
