#include "handlers.hpp"

#include <algorithm>
#include <climits>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

namespace birdcage::sim::handlers {
namespace {

std::optional<double> parse_number(std::string_view text)
{
    const std::string owned(text);
    char* end = nullptr;
    const double value = std::strtod(owned.c_str(), &end);
    if (owned.empty() || end == nullptr || *end != '\0' || !std::isfinite(value)) return std::nullopt;
    return value;
}

std::optional<int> parse_int(std::string_view text)
{
    const auto value = parse_number(text);
    if (!value || *value != std::floor(*value) || std::abs(*value) > 1e9) return std::nullopt;
    return static_cast<int>(*value);
}

__attribute__((format(printf, 1, 2))) std::string format(const char* pattern, ...)
{
    char text[256];
    va_list arguments;
    va_start(arguments, pattern);
    std::vsnprintf(text, sizeof text, pattern, arguments);
    va_end(arguments);
    return text;
}

long centi(double degrees) { return std::lround(degrees * 100.0); }

constexpr double unhomed_angle = INT_MAX;  // §6.4: uncalibrated axes read 2147483647

// `<label><value>` with Options::position_decimals.
std::string field(Engine& e, const char* label, double value)
{
    return format("%s%.*f", label, std::clamp(e.options.position_decimals, 0, 6), value);
}

void print_position(Engine& e)
{
    const double el = e.motors.axis(axis_el).position();
    const std::string indent(static_cast<std::size_t>(std::clamp(e.options.position_indent, 0, 16)), ' ');
    if (e.profile.position_format == PositionFormat::travler) {
        // §3.3: `AZ = ` / `EL = ` with one space before '='.
        const std::string az = field(e, "AZ = ", e.reported_az());
        const std::string elevation = field(e, "EL = ", el);
        const std::string skew = field(e, "SK = ", e.motors.axis(axis_skew).position());
        if (e.options.travler_position_layout == TravlerPositionLayout::one_line) {
            e.print_line(indent + az + " " + elevation + " " + skew);
        } else {
            for (const std::string& line : {az, elevation, skew}) e.print_line(indent + line);
        }
        return;
    }
    e.print_line(indent + field(e, "Angle[0] = ", e.homed[axis_az] ? e.reported_az() : unhomed_angle));
    e.print_line(indent + field(e, "Angle[1] = ", e.homed[axis_el] ? el : unhomed_angle));
}

// §6.3 error string (known for EL; the AZ form is the obvious analogue, INVENTED).
bool refuse_if_unhomed(Engine& e, std::size_t axis)
{
    if (!e.profile.needs_homing || e.homed[axis]) return false;
    e.count_hazard();
    e.print_line(format("Step to Position %s angle error: %d", axis == axis_az ? "AZ" : "EL", INT_MAX));
    return true;
}

// Mechanical target for a requested angle, or nullopt after printing the refusal.
std::optional<double> resolve_target(Engine& e, std::size_t axis, double value, bool relative)
{
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
            if (target < min - 1e-9 || target > max + 1e-9) return out_of_range(std::clamp(target, min, max));
            return target;
        };
        switch (e.options.az_mapping) {
        case AzMapping::wrap_manager:
            // Relative moves too: the manager never lets the axis through the wrap point.
            return within(wrap_manager_target(relative ? base + value : value, e.options.az_wrap_point,
                                              motor.position(), min, max));
        case AzMapping::literal:
            if (relative || (value >= min && value <= max)) return within(relative ? base + value : value);
            // No negative absolute numbers exist on a console where '-' means relative (G2): there
            // a number names the angle 360 below it (see AzMapping).
            if (e.profile.relative_moves && value - 360.0 >= min && value - 360.0 <= max) return value - 360.0;
            return within(value);
        case AzMapping::nearest:
            break;
        }
        if (relative) return within(base + value);
        // A 0..360 target goes to the branch of the wrap window nearest to where the dish is
        // (§2 "refuses to wind past its wrap limit", docs/tracking.md §2.3); an explicit
        // mechanical angle inside the window (Trav'ler 360..455) is taken literally.
        if (value >= 0.0 && value < 360.0) return nearest_wrap_branch(value, base, min, max);
        if (value >= min && value <= max) return value;
        return nearest_wrap_branch(value, base, min, max);
    }
    if (axis == axis_el) {
        double target = relative ? base + value : value;
        if (target < e.el_limit_min() || target > e.el_limit_max()) {
            const auto accepted = out_of_range(std::clamp(target, e.el_limit_min(), e.el_limit_max()));
            if (!accepted) return std::nullopt;
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

std::optional<std::size_t> parse_axis(Engine& e, std::string_view text)
{
    const auto id = parse_int(text);
    if (!id || *id < 0) return std::nullopt;
    const int last = e.profile.position_format == PositionFormat::travler ? 2 : 1;
    if (*id > last) return std::nullopt;
    return static_cast<std::size_t>(*id);
}

void print_live_position(Engine& e)
{
    // §8.4 reconstruction: `el` three tokens after the AZ centidegrees, one before EL's.
    e.print_line(format("az = %ld   el = %ld", centi(e.displayed_az()), centi(e.motors.axis(axis_el).position())));
}

}  // namespace

void angle(Engine& e, const Args& args)
{
    if (args.size() == 1) {
        if (!e.options.answer_position_while_moving && e.motors.moving()) {
            e.wait_until_idle(print_position);
        } else {
            print_position(e);
        }
        return;
    }
    const auto axis = args.size() == 3 ? parse_axis(e, args[1]) : std::nullopt;
    const auto value = args.size() == 3 ? parse_number(args[2]) : std::nullopt;
    if (!axis || !value) {
        e.unknown_command();
        return;
    }
    if (refuse_if_unhomed(e, *axis)) return;
    const bool relative = e.profile.relative_moves && (args[2].front() == '+' || args[2].front() == '-');
    const auto target = resolve_target(e, *axis, *value, relative);
    if (!target) return;
    e.motors.enqueue(*axis, *target);
    if (e.profile.move_ack_angle) {
        double shown = *target;
        if (*axis == axis_az && e.options.az_report == AzReport::displayed) shown = normalize_360(shown);
        e.print_line(field(e, "Angle = ", shown));
    }
    if (e.options.move_ack == MoveAck::after_motion) e.wait_until_idle(nullptr);
}

void go_to(Engine& e, const Args& args)
{
    const bool with_skew = e.profile.position_format == PositionFormat::travler && args.size() == 4;
    if (args.size() != 3 && !with_skew) {
        e.unknown_command();
        return;
    }
    const auto az = parse_number(args[1]);
    const auto el = parse_number(args[2]);
    const auto skew = with_skew ? parse_number(args[3]) : std::optional<double>(0.0);
    if (!az || !el || !skew) {
        e.unknown_command();
        return;
    }
    if (refuse_if_unhomed(e, axis_az) || refuse_if_unhomed(e, axis_el)) return;
    const auto az_target = resolve_target(e, axis_az, *az, false);
    if (!az_target) return;
    const auto el_target = resolve_target(e, axis_el, *el, false);
    if (!el_target) return;
    e.motors.enqueue(axis_az, *az_target);
    e.motors.enqueue(axis_el, *el_target);
    if (with_skew) e.motors.enqueue(axis_skew, *skew);
    e.start_goto(e.profile.live_goto_output ? print_live_position : nullptr);
}

void home(Engine& e, const Args& args)
{
    if (args.size() != 2 || !(args[1] == "0" || args[1] == "1" || args[1] == "*")) {
        e.unknown_command();
        return;
    }
    const bool home_el = args[1] != "0";
    const bool home_az = args[1] != "1";
    if (home_el) {
        e.motors.enqueue(axis_el, e.profile.home_el);
        e.homed[axis_el] = true;
    }
    if (home_az) {
        // Stall detection finds the hard stop at the top of the wrap window, then the axis
        // returns to its zero (§6.2 item 11, §6.4).
        e.motors.enqueue(axis_az, e.profile.az.max);
        e.motors.enqueue(axis_az, e.profile.home_az);
        e.homed[axis_az] = true;
    }
    e.wait_until_idle([home_az](Engine& engine) {
        if (!home_az) return;
        if (engine.options.home_report == HomeReport::g2plus_status) {
            engine.print_line("AZ - Angle: 1 Wrap: 0");  // §7.1: shape inferred from mjlangan's regex
        } else {
            engine.print_line(format("wrap_min:%ld wrap_max:%ld", centi(engine.profile.az.min), centi(engine.profile.az.max)));
        }
    });
}

void step_positions(Engine& e, const Args&)
{
    const auto steps = [&](std::size_t axis) {
        const Axis& motor = e.motors.axis(axis);
        return std::lround(motor.position() / 360.0 * motor.params().steps_per_rev);
    };
    e.print_line(format("Position[0] = %ld  Position[1] = %ld", steps(axis_az), steps(axis_el)));
}

void max_velocity(Engine& e, const Args& args)
{
    if (args.size() > 1) return;  // setting is accepted but not modelled
    e.print_line(format("Max Vel [0] = %.2f", e.motors.axis(axis_az).params().max_velocity));
    e.print_line(format("Max Vel [1] = %.2f", e.motors.axis(axis_el).params().max_velocity));
}

void max_accel(Engine& e, const Args& args)
{
    if (args.size() > 1) return;
    e.print_line(format("Accel[0] = %.2f", e.motors.axis(axis_az).params().max_accel));
    e.print_line(format("Accel[1] = %.2f", e.motors.axis(axis_el).params().max_accel));
}

void el_min_max_home(Engine& e, const Args&)
{
    e.print_line(format("Min: %ld  Max: %ld  Home: %ld", centi(e.el_limit_min()), centi(e.el_limit_max()),
                        centi(e.profile.home_el)));
}

void silent(Engine&, const Args&) {}

void nvs_dump(Engine& e, const Args& args)
{
    if (args.size() >= 2) {
        const auto index = parse_int(args[1]);
        const NvsEntry* entry = index ? e.nvs.find(*index) : nullptr;
        if (entry == nullptr) return;
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
        if (e.profile.nvs_page_rows != 0 && entry.index <= e.nvs_cursor) continue;
        e.print_line(NvsTable::row(entry));
        e.nvs_cursor = entry.index;
        if (e.profile.nvs_page_rows != 0 && ++shown == e.profile.nvs_page_rows) return;
    }
    e.nvs_cursor = -1;  // the next page starts over
}

void nvs_edit(Engine& e, const Args& args)
{
    const auto index = args.size() >= 2 ? parse_int(args[1]) : std::nullopt;
    NvsEntry* entry = index ? e.nvs.find(*index) : nullptr;
    if (entry == nullptr || args.size() > 3) {
        e.unknown_command();
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
        e.unknown_command();
        return;
    }
    const double old_value = entry->current;
    entry->current = *value;  // pending until `s`, effective after reboot (§2)
    e.print_line(NvsTable::edit_row(*entry, old_value));
}

void nvs_save(Engine& e, const Args&)
{
    e.count_hazard();
    e.nvs.save_all();
    // Davidson's verbatim transcript (§6.3).
    e.print_line("    Saving ... ");
    e.print_line("Flash file flashx:bank0 opened");
    e.print_line("Flash sector cache enabled.");
    e.print_line("Flash doneSuccess");
}

// §6.3: any unrecognised input in NVS> reads the next index.
void nvs_next(Engine& e, const Args&)
{
    const NvsEntry* entry = e.nvs.next_after(e.nvs_cursor);
    if (entry == nullptr) return;
    e.print_line(NvsTable::row(*entry));
    e.nvs_cursor = entry->index;
}

void os_id(Engine& e, const Args&)
{
    // Appendix B.
    for (const char* line :
         {"NVS Version:    1.02.13", "System ID:  TWELINCH", " K60-144pin", " Silicon Rev 2.4", " Mask Set 4N22D",
          " 512 kBytes of P-flash", " P-flash only", " 128 kBytes of RAM", " Board Rev ID:         A",
          " Board ID:             STATIONARY", " Ant ID:               12-IN G2", " Software version:     02.02.48",
          " CCLK:                 96000000", " BCLK:                 48000000", " Flash Base Address:   65536",
          " Flash Size:           458752"})
        e.print_line(line);
}

void os_tasks(Engine& e, const Args&)
{
    // §14 HAL0.8: the listing is unknown; INVENTED, only the task name `Search` is known.
    e.print_line("Shell");
    e.print_line("Motor");
    if (e.search) e.print_line("Search");
}

void os_kill(Engine& e, const Args& args)
{
    if (args.size() != 2) {
        e.unknown_command();
        return;
    }
    if (args[1] == "Search" && e.profile.search_stop == SearchStop::os_kill && e.search) e.stop_search();
}

void ngsearch_stop(Engine& e, const Args&)
{
    if (e.profile.search_stop == SearchStop::ngsearch_stop && e.search) e.stop_search();
}

void reboot(Engine& e, const Args&)
{
    e.count_hazard();
    e.reboot();
}

void stow(Engine& e, const Args&)
{
    e.count_hazard();
    if (e.search) e.stop_search();
    e.motors.enqueue(axis_el, e.profile.stow_el);  // firmware limits do not apply to stow
}

void dvb_rssi(Engine& e, const Args& args)
{
    const auto count = args.size() >= 2 ? parse_int(args[1]) : std::optional<int>(1);
    if (!count || *count < 1 || args.size() > 2) {
        e.unknown_command();
        return;
    }
    const int reads = std::min(*count, 100000);
    // n samples at a 20 ms interval (§6.3); the reply comes when they are done.
    e.wait_for(reads * 0.02, [reads](Engine& engine) {
        long sum = 0;
        int current = 0;
        for (int i = 0; i < reads; ++i) {
            current = engine.sky.read(engine.displayed_az(), engine.motors.axis(axis_el).position(), engine.lnb_supply);
            sum += current;
        }
        engine.print_line(format("iterations:%d  interval(msec):20", reads));
        engine.print_line(format(" Reads:%d  RSSI[avg: %ld  cur: %d]", reads, std::lround(static_cast<double>(sum) / reads), current));
    });
}

void dvb_lnbdc(Engine& e, const Args& args)
{
    // §6.3: reply text undocumented; prints nothing.
    if (args.size() == 2 && args[1] == "odu") {
        e.lnb_supply = LnbSupply::odu_13v;
    } else if (args.size() == 2 && args[1] == "stb") {
        e.lnb_supply = LnbSupply::stb_18v;
    } else {
        e.unknown_command();
    }
}

void dvb_config(Engine& e, const Args&)
{
    e.print_line("BCM Hardware=  ID: 0x4515  VER: 0xB0");
    e.print_line("BCM Firmware=  MAJOR VER: 0x71 (113)  MINOR VER: 0x25 (37)");
    e.print_line("BCM Strap Config: 0x25018");
}

void dvb_quick_lock(Engine& e, const Args&)
{
    e.print_line(format("Lock:0  rssi:%d  cnt:0", e.sky.read(e.displayed_az(), e.motors.axis(axis_el).position(), e.lnb_supply)));
}

void hazard_only(Engine& e, const Args&) { e.count_hazard(); }

void eeprom_read(Engine& e, const Args& args)
{
    const auto index = args.size() >= 2 ? parse_int(args[1]) : std::nullopt;
    if (!index) {
        e.unknown_command();
        return;
    }
    e.print_line(format("Index:%d Read value = 0", *index));  // value INVENTED
}

void adc_board_id(Engine& e, const Args&) { e.print_line("STATIONARY"); }
void adc_board_rev(Engine& e, const Args&) { e.print_line("A"); }

void adc_rssi(Engine& e, const Args&)
{
    std::uniform_int_distribution<int> noise(233, 238);  // raw ADC floor (§6.3 ADC>)
    e.print_line(format("%d", noise(e.rng)));
}

void adc_scan(Engine& e, const Args& args)
{
    if (args.size() == 1) {
        // §6.5: targets 2147483647 and blocks forever; nothing recovers but a power cycle.
        e.count_hazard();
        e.kill_shell("");
    }
}

void a3981_diag(Engine& e, const Args&)
{
    e.print_line("AZ DIAG: OK");
    e.print_line("EL DIAG: OK");
}

void dipswitch(Engine& e, const Args&)
{
    e.print_line("val:ffffff01");
    e.print_line("app_dipswitch:101");
}

void step_max_velocity(Engine& e, const Args&)
{
    e.print_line("Max Vel [0] = 7222");
    e.print_line("Max Vel [1] = 3120");
}

void step_accel(Engine& e, const Args&)
{
    e.print_line("Accel[0] = 44");
    e.print_line("Accel[1] = 28");
}

}  // namespace birdcage::sim::handlers
