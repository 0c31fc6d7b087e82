#include "birdcage/controller.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "birdcage/leapfrog.hpp"
#include "birdcage/protocol.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto menu_step_timeout = 3000ms;    // one menu command and its reply
constexpr auto query_timeout = 2000ms;        // `a`: ~60 bytes even at 57600 baud is ~11 ms
constexpr auto resync_timeout = 1500ms;
constexpr auto home_timeout = 180000ms;        // `h <id>` blocks the shell until the axis is homed
constexpr auto skip_init_sync_budget = 5000ms;   // skip_init: the dish is said to be up already
constexpr auto poll_interval = 100ms;         // >= 10 Hz position polls while a leg runs (tracking.md 1.2)
constexpr auto still_window = 2000ms;         // an axis unchanged this long has stopped
constexpr auto leg_margin = 3000ms;           // added to 2 x the estimated move time
constexpr auto unknown_prompt_send_timeout = 1000ms;
constexpr double stillness_degrees = 0.02;    // position changes smaller than this are noise
constexpr double unexpected_motion_degrees = 0.5;  // idle drift that means the firmware moves the dish
// A target this far (display azimuth) from the previous one is a new pass or another satellite.
constexpr double new_pass_jump_degrees = 30.0;
// A reading this far outside 0..360 cannot be a displayed azimuth ("-0.00" and "360.00" can).
constexpr double beyond_display_degrees = 0.5;
// After a re-initialisation the mechanical estimate is kept if the dish still reads within this.
constexpr double same_branch_recheck_degrees = 1.0;
// The 2003 Carryout prints a live position line within this long after `g` starts a move: the
// upstream client reads 1 s after writing `g` and parses one (firmware notes 8.4). A `g` that needed
// a move and printed none in this window did not run as a move (the console is not in `target`).
constexpr auto first_live_line_window = 1000ms;

std::string degrees_text(double value) { return format_degrees(value); }

double axis_value(AzEl position, Axis axis) { return axis == Axis::azimuth ? position.az : position.el; }

// Consecutive readings further apart than this were not one continuous path (the estimate's branch
// was wrong, or the readings too sparse to follow the axis): the leg teaches nothing about the mapping.
constexpr double path_jump_degrees = 90.0;

double axis_error(Axis axis, double from, double to) {
    return axis == Axis::azimuth ? std::fabs(azimuth_difference(from, to)) : std::fabs(to - from);
}

}  // namespace

Controller::Controller(Transport& transport, ControllerOptions options)
    : profile_(birdcage::profile(options.variant)),
      options_(std::move(options)),
      session_(transport, profile_, options_.log),
      el_min_(profile_.el_min),
      el_max_(profile_.el_max),
      az_window_{profile_.az_min, profile_.az_max},
      az_usable_(wrap::usable_window(az_window_)),
      // A travel with negative angles (G2) has no negative absolute numbers: '-' is a relative move (§6.3).
      az_travel_{az_window_, az_window_.min < 0.0},
      az_learner_(az_travel_, options_.az_mapping) {
    auto override_limit = [this](const std::optional<double>& user, double& limit, const char* name) {
        if (!user) {
            return;
        }
        if (!std::isfinite(*user)) {
            emit(options_.log, LogLevel::warning, std::string("ignoring non-finite ") + name);
            return;
        }
        limit = std::clamp(*user, profile_.el_min, profile_.el_max);
        if (limit != *user) {
            emit(options_.log, LogLevel::warning,
                 std::string(name) + " " + degrees_text(*user) + " is beyond the " +
                     std::string(profile_.short_name) + " limits; using " + degrees_text(limit));
        }
    };
    override_limit(options_.el_min, el_min_, "el_min");
    override_limit(options_.el_max, el_max_, "el_max");
    if (el_min_ > el_max_) {
        emit(options_.log, LogLevel::warning, "el_min > el_max; using the variant's limits");
        el_min_ = profile_.el_min;
        el_max_ = profile_.el_max;
    }
}

Clock::time_point Controller::now() const { return options_.clock.now(); }

Status Controller::run_steps(std::span<const ConsoleStep> steps, std::string_view purpose) {
    for (const auto& step : steps) {
        const auto reply = session_.transact(step.command, menu_step_timeout);
        if (!reply) {
            return Status{reply.status.code, std::string(purpose) + ": " + reply.status.message};
        }
        if (step.settle.count() > 0) {
            if (const auto heard = session_.listen(step.settle); !heard) {
                return heard.status;
            }
        }
    }
    return Status::ok();
}

// A booting, idle or noisy console is brought to a confirmed prompt by the one synchroniser
// (never on a single line: see synchroniser.hpp); it also says at default verbosity that it waits.
Status Controller::wait_for_boot() {
    session_.clear_reboot_seen();
    const auto synced = session_.synchronise(console_sync_settings(profile_, boot_budget_));
    if (!synced) {
        return Status{synced.status.code, "the " + std::string(profile_.display_name) +
                                              " console did not come into sync: " + synced.status.message};
    }
    if (synced.value.boot_heard) {
        emit(options_.log, LogLevel::warning, "dish booted (last boot output \"" + synced.value.last_boot_line + "\")");
    }
    return Status::ok();
}

Status Controller::leave_submenus() {
    if (!profile_.prompt_known()) {
        // The clients' idiom (firmware.md 2): `q` leaves a submenu, a bare line clears the input.
        static constexpr std::array<ConsoleStep, 2> back_to_root{{{"q", 0ms}, {"", 0ms}}};
        return run_steps(back_to_root, "leaving submenus");
    }
    // Known prompts: `q` only from a submenu we have seen the prompt of (the guard refuses the rest).
    for (int attempt = 0; attempt < 4; ++attempt) {
        if (session_.menu().empty()) {
            if (Status synced = session_.resync(resync_timeout); !synced) {
                return synced;
            }
        }
        if (session_.menu() == "root") {
            return Status::ok();
        }
        if (const auto left = session_.transact("q", menu_step_timeout); !left) {
            return left.status;
        }
    }
    return Status{Errc::protocol, "could not reach the root menu (last prompt " + session_.last_prompt() + ")"};
}

Status Controller::in_submenu(std::string_view menu, const std::function<Status(ConsoleSession&)>& work) {
    if (in_flight_) {
        return {Errc::busy, "a leg is in flight; the motor menu must stay open"};
    }
    if (Status left = leave_submenus(); !left) {
        return left;
    }
    Status worked = Status::ok();
    if (const auto entered = session_.transact(menu, menu_step_timeout); !entered) {
        worked = entered.status;
    } else {
        worked = work(session_);
    }
    // Back to the motor menu even when the work failed: the next leg must find it open.
    Status back = leave_submenus();
    if (back) {
        back = run_steps(profile_.motor_menu_entry, "returning to the motor menu");
    }
    if (!back) {
        emit(options_.log, LogLevel::warning, "could not return to the motor menu from " + std::string(menu) + ": " + back.message);
        return back;
    }
    return worked;
}

Status Controller::check_homing() {
    if (!profile_.has(quirk_requires_homing) || !unhomed_) {
        return Status::ok();
    }
    emit(options_.log, LogLevel::error,
         "the dish's axes are not homed (it reports INT_MAX); moves are refused until it is homed: "
         "use reset (rotctl R 1), which runs h 1 and h 0");
    return Status::ok();
}

// Read-only: the firmware's TV search runs after boot unless NVS "Disable Tracker Proc?" is TRUE
// (firmware.md 6.2 item 14, Appendix A). The backend never writes NVS; it only warns.
Status Controller::check_tracker_disabled() {
    if (profile_.tracker_disable_nvs_index < 0) {
        return Status::ok();
    }
    tracker_checked_ = true;
    if (Status left = leave_submenus(); !left) {
        return left;
    }
    const std::array<std::string, 2> steps{"nvs", build_nvs_dump(profile_.tracker_disable_nvs_index)};
    std::optional<NvsEntry> entry;
    for (const auto& step : steps) {
        const auto reply = session_.transact(step, menu_step_timeout);
        if (!reply) {
            emit(options_.log, LogLevel::warning, "could not read NVS " + std::to_string(profile_.tracker_disable_nvs_index) +
                                                      ": " + reply.status.message);
            break;
        }
        for (const auto& line : reply.value.lines) {
            if (auto parsed = parse_g2_nvs_line(line); parsed && parsed->index == profile_.tracker_disable_nvs_index) {
                entry = parsed;
            }
        }
    }
    if (session_.menu() == "nvs") {
        if (const auto left = session_.transact("q", menu_step_timeout); !left) {
            return left.status;
        }
    }
    if (Status back = run_steps(profile_.motor_menu_entry, "re-entering the motor menu"); !back) {
        return back;
    }
    if (entry && entry->current == "FALSE") {
        tracker_enabled_ = true;
        emit(options_.log, LogLevel::warning,
             "NVS " + std::to_string(entry->index) + " (" + entry->name +
                 ") is FALSE: the firmware's TV-satellite search runs after every boot and will move the dish on "
                 "its own. Set it to TRUE yourself (nvs, e " + std::to_string(entry->index) +
                 " TRUE, s, reboot); the backend never writes NVS.");
    }
    return Status::ok();
}

Status Controller::home() {
    if (profile_.home_commands.empty()) {
        return Status{Errc::unsupported, std::string(profile_.display_name) +
                                             " has no homing command (it calibrates at power-up only)"};
    }
    if (!initialised_) {
        return Status{Errc::not_initialised, "initialize() has not succeeded"};
    }
    pending_.clear();
    in_flight_.reset();
    forget_target();
    commanded_az_.reset();
    commanded_el_.reset();
    // Homing recalibrates the axes: the branch is the start assumption again (G2: AZ 0, 6.4).
    mech_az_.reset();
    for (const auto command : profile_.home_commands) {
        emit(options_.log, LogLevel::verbose, "homing: " + std::string(command));
        const auto reply = session_.transact(command, home_timeout);
        if (!reply) {
            return Status{reply.status.code, "homing (" + std::string(command) + "): " + reply.status.message};
        }
    }
    unhomed_ = false;
    session_.set_axes_unhomed(false);
    const auto position = ask_position(query_timeout);
    if (!position) {
        return Status{position.status.code, "after homing: " + position.status.message};
    }
    emit(options_.log, LogLevel::verbose, "homed: " + describe());
    return Status::ok();
}

Status Controller::reinitialize(std::chrono::milliseconds boot_budget) {
    return initialize_within(std::min(boot_budget, options_.boot_timeout));
}

Status Controller::initialize() { return initialize_within(options_.boot_timeout); }

Status Controller::initialize_within(std::chrono::milliseconds boot_budget) {
    boot_budget_ = boot_budget;
    initialised_ = false;
    sync_lost_ = false;
    pending_.clear();
    in_flight_.reset();
    // Whatever was commanded before is void (a reboot stops the axes, a hang-up loses replies).
    forget_target();
    commanded_az_.reset();
    commanded_el_.reset();
    // The mechanical estimate survives a hang-up or lost sync, not a reboot (which recalibrates
    // and moves the dish): the first reading decides (note_azimuth_reading()).
    recheck_branch_ = true;
    if (options_.skip_init) {
        emit(options_.log, LogLevel::verbose, "skip_init: assuming the dish is booted and in its motor menu");
        if (profile_.prompt_known()) {
            if (const auto synced = session_.synchronise(console_sync_settings(profile_, skip_init_sync_budget)); !synced) {
                return synced.status;
            }
        }
    } else {
        if (Status booted = wait_for_boot(); !booted) {
            return booted;
        }
        if (Status left = leave_submenus(); !left) {
            return left;
        }
        if (Status killed = run_steps(profile_.search_kill, "stopping the TV search"); !killed) {
            return killed;
        }
        if (Status entered = run_steps(profile_.motor_menu_entry, "entering the motor menu"); !entered) {
            return entered;
        }
    }
    if (profile_.prompt_known() && session_.menu() != menu_for_prompt(profile_, profile_.motor_prompt)) {
        return Status{Errc::protocol, "expected the motor prompt " + std::string(profile_.motor_prompt) +
                                          ", console shows " + session_.last_prompt()};
    }
    session_.clear_reboot_seen();
    if (!profile_.position_query.empty()) {
        const auto position = ask_position(query_timeout);
        if (!position && position.status.code != Errc::not_homed) {
            if (position.status.code == Errc::disconnected || position.status.code == Errc::io) {
                return position.status;
            }
            emit(options_.log, LogLevel::warning, "initial position query failed: " + position.status.message);
        }
    }
    if (Status homing = check_homing(); !homing) {
        return homing;
    }
    motor_menu_ = session_.menu();   // where every later reply must come from (needs_reinit())
    initialised_ = true;
    emit(options_.log, LogLevel::verbose, "initialised: " + describe());
    return Status::ok();
}

Result<AzEl> Controller::ask_position(std::chrono::milliseconds timeout) {
    const auto complete = [this](std::span<const std::string> lines) {
        return parse_position(profile_, lines).status.code != Errc::protocol;
    };
    const auto reply = session_.transact(profile_.position_query, timeout, complete);
    fault_reported_ = reply.status.code == Errc::protocol;  // the session's only protocol error: a fault line
    if (fault_reported_) {
        leg_fault_ = reply.status.message;   // reported once by the service (take_fault())
    }
    if (!reply && reply.status.code != Errc::protocol) {
        return {{}, reply.status};
    }
    auto position = parse_position(profile_, reply.value.lines);
    if (position.status.code == Errc::not_homed) {
        unhomed_ = true;
        session_.set_axes_unhomed(true);
        return position;
    }
    if (!position) {
        return position;
    }
    unhomed_ = false;
    session_.set_axes_unhomed(false);
    note_azimuth_reading(position.value.az);
    position.value.az = normalize_azimuth(position.value.az);
    last_position_ = position.value;
    last_position_at_ = now();
    position_estimated_ = false;
    if (!reply) {
        position.status = reply.status;  // a valid position, but the dish also reported a fault
    }
    return position;
}

Result<AzEl> Controller::query_position() {
    if (profile_.has(quirk_no_position_query)) {
        if (last_position_) {
            return {*last_position_, Status::ok()};
        }
        return {{}, Status{Errc::unsupported, "this dish cannot report its position at rest and none has been commanded yet"}};
    }
    const auto before = last_position_;
    const auto mech_before = mech_az_;
    auto position = ask_position(query_timeout);
    // At rest a reading far from the last one is either the dish moving on its own or a reply that
    // lost bytes on the line (`123.45` -> `13.45` still parses). Ask again: a real position repeats,
    // a corrupted one is refused and the previous position kept.
    if (position && before && idle() && initialised_ && !position_estimated_ &&
        (std::fabs(azimuth_difference(before->az, position.value.az)) > unexpected_motion_degrees ||
         std::fabs(before->el - position.value.el) > unexpected_motion_degrees)) {
        const AzEl first = position.value;
        const auto again = ask_position(query_timeout);
        if (!again || std::fabs(azimuth_difference(first.az, again.value.az)) > unexpected_motion_degrees ||
            std::fabs(first.el - again.value.el) > unexpected_motion_degrees) {
            last_position_ = before;
            mech_az_ = mech_before;
            return {*before, Status{Errc::protocol, "inconsistent position readings (az " + degrees_text(first.az) +
                                                         " el " + degrees_text(first.el) +
                                                         ", then not repeated): line noise? keeping the last position"}};
        }
        position = again;
    }
    // The dish moving on its own at rest is the firmware's TV search (tracker enabled): find out
    // why once, read-only (firmware.md 6.2 item 14).
    if (position && before && idle() && initialised_ && !tracker_checked_ && profile_.tracker_disable_nvs_index >= 0 &&
        (std::fabs(azimuth_difference(before->az, position.value.az)) > unexpected_motion_degrees ||
         std::fabs(before->el - position.value.el) > unexpected_motion_degrees)) {
        emit(options_.log, LogLevel::warning, "the dish moves on its own while idle; checking whether its tracker is enabled");
        if (Status checked = check_tracker_disabled(); !checked) {
            return {position.value, checked};
        }
    }
    return position;
}

Status Controller::set_target(AzEl target, double az_rate_dps) {
    if (!std::isfinite(target.az) || !std::isfinite(target.el)) {
        return Status{Errc::invalid_argument, "target must be finite"};
    }
    if (unhomed_) {
        return Status{Errc::not_homed, "the axes are not homed; moves are refused"};
    }
    if (!std::isfinite(az_rate_dps)) {
        az_rate_dps = 0.0;
    }
    // Gpredict's 0..360 and -180..180 modes (and Hamlib's -180..540) all reduce to a display
    // azimuth; the cable-wrap branch is the backend's choice (choose_azimuth_branch()).
    AzEl wanted{normalize_azimuth(target.az), std::clamp(target.el, el_min_, el_max_)};
    if (options_.az_min && options_.az_max && *options_.az_min < *options_.az_max) {
        const double clamped = std::clamp(wanted.az, *options_.az_min, *options_.az_max);
        if (clamped != wanted.az) {
            emit(options_.log, LogLevel::verbose, "azimuth " + degrees_text(wanted.az) + " clamped to " +
                                                      degrees_text(clamped) + " (az_min/az_max)");
            wanted.az = clamped;
        }
    }
    if (wanted.el != target.el) {
        emit(options_.log, LogLevel::verbose, "elevation " + degrees_text(target.el) + " clamped to " +
                                                  degrees_text(wanted.el));
    }
    if (current_target_ && std::fabs(azimuth_difference(current_target_->az, wanted.az)) < same_angle_degrees &&
        std::fabs(current_target_->el - wanted.el) < same_angle_degrees) {
        return Status::ok();
    }
    const std::optional<AzEl> previous = current_target_;
    current_target_ = wanted;

    AzEl command = wanted;
    if (options_.leapfrog && last_position_) {
        command = apply_leapfrog(wanted, *last_position_);
        command.el = std::clamp(command.el, el_min_, el_max_);
    }

    pending_.clear();
    if (profile_.move_style == MoveStyle::combined_g) {
        // `g az el` takes 0..360 only (Carryout 2003, whose travel is 0..360): no branch to choose.
        Leg leg;
        leg.combined = true;
        leg.target = command;
        pending_.push_back(leg);
        ++move_count_;
        return Status::ok();
    }

    // The mechanical azimuth: the target's branch, plus the leapfrog lead, inside the usable window.
    target_mech_az_ = choose_azimuth_branch(wanted, previous, az_rate_dps);
    const wrap::Window plan = az_learner_.plan_window(az_usable_);
    const double command_mech =
        std::clamp(*target_mech_az_ + azimuth_difference(wanted.az, command.az), plan.min, plan.max);
    command.az = azmap::command_value(command_mech, az_travel_);

    auto needed = [this](Axis axis, double value) {
        const auto& commanded = axis == Axis::azimuth ? commanded_az_ : commanded_el_;
        if (commanded) {
            return std::fabs(*commanded - value) >= same_angle_degrees;
        }
        // Nothing commanded on this axis yet: skip the leg only if the dish already reads the target
        // (arrival_tolerance is for ending a leg in motion; skipping by it would leave up to that
        // much pointing error, e.g. after a TV search stopped the dish near the target).
        if (axis == Axis::azimuth) {
            return !mech_az_ || std::fabs(*mech_az_ - value) >= same_angle_degrees;
        }
        return !last_position_ || std::fabs(last_position_->el - value) >= same_angle_degrees;
    };
    Leg az_leg;
    az_leg.axis = Axis::azimuth;
    az_leg.target = command;
    az_leg.mech_az = command_mech;
    az_leg.final_mech_az = command_mech;
    Leg el_leg;
    el_leg.axis = Axis::elevation;
    el_leg.target = command;
    // Alternate which axis goes first so neither starves the other (seeds 003/004).
    const bool az_first = move_count_ % 2 == 0;
    ++move_count_;
    for (const Leg& leg : az_first ? std::array<Leg, 2>{az_leg, el_leg} : std::array<Leg, 2>{el_leg, az_leg}) {
        if (needed(leg.axis, leg.axis == Axis::azimuth ? leg.mech_az : leg.target.el)) {
            pending_.push_back(leg);
        }
    }
    return Status::ok();
}

// Where continuity is measured from: the branch of the previous target (not the dish's momentary
// position, which may be half-way through a long slew to it), else where the azimuth leg in
// flight ends, else the dish's estimated mechanical azimuth.
std::optional<double> Controller::branch_reference() const {
    if (target_mech_az_) {
        return target_mech_az_;
    }
    if (in_flight_ && !in_flight_->combined && in_flight_->axis == Axis::azimuth) {
        return in_flight_->final_mech_az;
    }
    if (mech_az_) {
        return mech_az_;
    }
    return commanded_az_;
}

// The rule (tracking.md §2.3: no avoidable unwinds; unwind, when unavoidable, away from the
// limit stops):
//  - normally the target's branch nearest the previous target (continuity), if it lies inside
//    the wrap window less the margins;
//  - when a pass starts (the caller's rate hint is non-zero and the target is within
//    pass_start_band_deg of el_min, rising), the branch nearest the previous target among those
//    with room for a whole pass (pass_span_deg) ahead in the direction of motion, else the one
//    with the most room ahead: the one unwind a pass that does not fit needs then happens at its
//    end, as late and as low as possible, instead of near its culmination;
//  - when the continuous branch lies outside the window (the limit is reached), the branch with
//    the most room ahead in the direction of motion (the nearest without a rate hint).
// A pass is started once: later targets of the same pass (same direction, no jump) keep
// continuity, so the descent towards el_min at its end never triggers the pass-start rule.
double Controller::choose_azimuth_branch(AzEl wanted, const std::optional<AzEl>& previous, double az_rate_dps) {
    const int direction = az_rate_dps > 0.0 ? 1 : (az_rate_dps < 0.0 ? -1 : 0);
    const bool jumped = previous && std::fabs(azimuth_difference(previous->az, wanted.az)) > new_pass_jump_degrees;
    if (direction == 0 || jumped) {
        pass_direction_.reset();
    }
    const bool new_pass = direction != 0 && pass_direction_ != direction;
    const bool falling = previous && !jumped && wanted.el < previous->el - same_angle_degrees;
    const bool pass_starting = new_pass && !falling && wanted.el <= el_min_ + wrap::pass_start_band_deg;
    if (direction != 0) {
        pass_direction_ = direction;
    }
    // Nothing read or commanded yet: continuity from the start assumption (wrap::start_branch()).
    // The window the firmware's mapping (as far as it is known) lets absolute commands reach.
    const wrap::Window plan = az_learner_.plan_window(az_usable_);
    const double reference = branch_reference().value_or(std::clamp(0.0, plan.min, plan.max));
    const wrap::Choice choice = wrap::choose_branch(wanted.az, reference, direction, pass_starting, plan);
    if (choice.reason != wrap::Reason::continuous) {
        std::string message = "azimuth " + degrees_text(wanted.az) + ": mechanical " +
                              degrees_text(choice.mechanical) + " instead of " + degrees_text(choice.continuous) +
                              " (" + std::string(wrap::reason_text(choice.reason));
        if (direction != 0) {
            message += "; " + degrees_text(wrap::room_ahead(choice.mechanical, direction, plan)) +
                       " deg of room ahead " + (direction > 0 ? "clockwise" : "anticlockwise");
        }
        message += "; window " + degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")";
        emit(options_.log, LogLevel::verbose, message);
    }
    return choice.mechanical;
}

void Controller::forget_target() {
    current_target_.reset();
    target_mech_az_.reset();
    pass_direction_.reset();
}

// Keeps the mechanical azimuth estimate. The reply may carry the displayed 0..360 azimuth or the
// mechanical one (firmware.md §14 G2.4; the Trav'ler README says `a` shows the wrap, 3.3): a
// reading outside 0..360 (twice in a row, inside the travel) proves the latter, and readings are
// then taken literally; otherwise each is unwrapped to the branch nearest the estimate, which
// follows the dish as long as it turns less than 180 deg between readings (legs are at most
// wrap::max_leg_deg). The first reading's branch is the start assumption (wrap::start_branch()).
void Controller::note_azimuth_reading(double reported) {
    const std::optional<double> before = mech_az_;
    const std::optional<Clock::time_point> before_at = mech_az_at_;
    update_mechanical_azimuth(reported);
    const auto t = now();
    mech_az_at_ = t;
    if (!in_flight_ || in_flight_->combined || in_flight_->axis != Axis::azimuth || !mech_az_) {
        return;
    }
    Leg& leg = *in_flight_;
    // Readings that report the branch follow the axis whatever the gap; displayed ones only while
    // the axis cannot have turned half a circle in between.
    const double gap_s = before_at ? std::chrono::duration<double>(t - *before_at).count() : 0.0;
    const bool followed = az_report_mechanical_ || gap_s * profile_.az_speed_dps < path_jump_degrees;
    if (!before || std::fabs(*mech_az_ - *before) > path_jump_degrees || !followed) {
        leg.path_known = false;
    }
    leg.lowest = std::min(leg.lowest, *mech_az_);
    leg.highest = std::max(leg.highest, *mech_az_);
}

void Controller::update_mechanical_azimuth(double reported) {
    const double display = normalize_azimuth(reported);
    const bool beyond_display = reported < -beyond_display_degrees || reported >= 360.0 + beyond_display_degrees;
    const bool inside_travel = reported >= az_window_.min - 1.0 && reported <= az_window_.max + 1.0;
    if (beyond_display && inside_travel) {
        // Only a mechanical report can read like this: it names the branch.
        if (!az_report_mechanical_ && ++beyond_display_readings_ >= 2) {
            az_report_mechanical_ = true;
            emit(options_.log, LogLevel::verbose, "the dish reports its mechanical azimuth (read " +
                                                      degrees_text(reported) + "): readings are taken literally");
        }
        mech_az_ = reported;
        recheck_branch_ = false;
        return;
    }
    if (!beyond_display) {
        beyond_display_readings_ = 0;
    }
    if (az_report_mechanical_ && inside_travel) {
        mech_az_ = reported;
        recheck_branch_ = false;
        return;
    }
    if (recheck_branch_ && mech_az_ &&
        std::fabs(azimuth_difference(*mech_az_, display)) > same_branch_recheck_degrees) {
        emit(options_.log, LogLevel::verbose,
             "after (re)initialisation the dish reads azimuth " + degrees_text(display) + ", not " +
                 degrees_text(normalize_azimuth(*mech_az_)) + ": it moved, its cable-wrap branch is assumed afresh");
        mech_az_.reset();
    }
    recheck_branch_ = false;
    if (!mech_az_) {
        mech_az_ = wrap::start_branch(display, az_window_);
        if (wrap::branches(display, az_window_).size() > 1) {
            emit(options_.log, LogLevel::verbose,
                 "azimuth " + degrees_text(display) + " has two cable-wrap branches; assuming mechanical " +
                     degrees_text(*mech_az_) + " (the one nearest AZ 0)");
        }
        return;
    }
    mech_az_ = wrap::unwrap_reading(display, *mech_az_, az_window_);
}

double Controller::leg_distance(const Leg& leg) const {
    if (leg.combined) {
        if (!last_position_) {
            return 180.0;
        }
        return std::max(std::fabs(azimuth_difference(last_position_->az, leg.target.az)),
                        std::fabs(leg.target.el - last_position_->el));
    }
    if (leg.axis == Axis::azimuth) {
        return mech_az_ ? std::fabs(leg.mech_az - *mech_az_) : wrap::max_leg_deg;
    }
    if (!last_position_) {
        return el_max_ - el_min_;
    }
    return std::fabs(leg.target.el - last_position_->el);
}

Status Controller::send_leg(Leg& leg) {
    const double distance = leg_distance(leg);
    const auto estimate = leg.combined ? std::max(estimated_move_time(profile_, Axis::azimuth, distance),
                                                  estimated_move_time(profile_, Axis::elevation, distance))
                                       : estimated_move_time(profile_, leg.axis, distance);
    leg.budget = estimate * 2 + leg_margin;
    const std::string command =
        leg.combined ? build_combined_move(leg.target) : build_axis_move(leg.axis, axis_value(leg.target, leg.axis));
    // With prompts, wait for the prompt (the G2 may hold it until the move ends); without, the
    // quiet gap ends the reply and the move is followed by polling.
    const auto timeout = profile_.prompt_known() ? leg.budget + 2000ms : unknown_prompt_send_timeout;
    ReplyComplete complete;
    if (profile_.move_ack == MoveAckFormat::g2_angle) {
        complete = [](std::span<const std::string> lines) { return static_cast<bool>(parse_g2_move_ack(lines)); };
    }
    const auto reply = session_.transact(command, timeout, complete);
    if (!reply && reply.status.code != Errc::timeout) {
        if (reply.status.code == Errc::not_homed) {
            unhomed_ = true;
        }
        return reply.status;
    }
    if (!reply) {
        // Expected for `g` where prompts are unknown: the live output runs until the move ends.
        emit(options_.log, leg.combined ? LogLevel::verbose : LogLevel::warning,
             "no prompt after " + command + "; assuming the move runs");
    } else if (profile_.move_ack == MoveAckFormat::g2_angle) {
        const auto ack = parse_g2_move_ack(reply.value.lines);
        if (ack.status.code == Errc::not_homed) {
            unhomed_ = true;
            session_.set_axes_unhomed(true);
            return ack.status;
        }
        if (!ack) {
            emit(options_.log, LogLevel::warning, "move not acknowledged: " + ack.status.message);
        } else if (axis_error(leg.axis, ack.value, axis_value(leg.target, leg.axis)) > 0.01) {
            emit(options_.log, LogLevel::verbose, "dish acknowledged " + degrees_text(ack.value) + " for " + command);
        } else if (leg.axis == Axis::azimuth && std::fabs(ack.value - leg.target.az) > 1.0 &&
                   std::fabs(ack.value - leg.mech_az) > 1.0) {
            // A mechanical acknowledgement (e.g. -60.00 for `a 0 300.00`) names the branch taken.
            emit(options_.log, LogLevel::warning,
                 "dish acknowledged " + degrees_text(ack.value) + " for " + command + ", not the intended mechanical " +
                     degrees_text(leg.mech_az) + ": its wrap mapping differs from the backend's model");
        }
    }
    if (leg.combined) {
        commanded_az_ = leg.target.az;
        commanded_el_ = leg.target.el;
        // Live output that arrived with the reply is the first position sample.
        leg.live_seen = static_cast<bool>(note_live_output(reply.value.lines));
        leg.needs_motion = distance > profile_.arrival_tolerance;
    } else if (leg.axis == Axis::azimuth) {
        commanded_az_ = leg.mech_az;
        leg.path_known = mech_az_.has_value();
        leg.from_mech = leg.lowest = leg.highest = mech_az_.value_or(leg.mech_az);
        leg.expected_end.reset();
    } else {
        commanded_el_ = leg.target.el;
    }
    leg.sent_at = now();
    leg.last_change = leg.sent_at;
    leg.last_seen.reset();
    last_poll_ = leg.sent_at;
    emit(options_.log, LogLevel::verbose,
         "sent " + command + " (estimated " + std::to_string(estimate.count()) + " ms)");
    in_flight_ = leg;
    if (leg.combined && reply && !reply.value.prompt.empty()) {
        // A prompt with no live line for a move that needed one proves nothing yet: the shell may
        // run `g` in the background, or not be in `target` at all (service_combined_leg() decides).
        if (in_flight_->live_seen || !in_flight_->needs_motion || !live_output_proven_) {
            finish_combined_leg("ended (prompt after the move)");
        }
    }
    if (leg.combined && leg.live_seen) {
        live_output_proven_ = true;
    }
    return Status::ok();
}

void Controller::finish_leg(std::string_view how) {
    if (!in_flight_) {
        return;
    }
    emit(options_.log, LogLevel::verbose, "leg " + std::string(how));
    in_flight_.reset();
}

Status Controller::service_axis_leg() {
    Leg& leg = *in_flight_;
    const auto t = now();
    if (t - last_poll_ < poll_interval) {
        return Status::ok();
    }
    last_poll_ = t;
    const bool over_budget = t - leg.sent_at > leg.budget;
    const auto position = ask_position(query_timeout);
    if (!position && position.status.code != Errc::protocol) {
        if (position.status.code == Errc::timeout && !over_budget) {
            return Status::ok();  // some consoles answer only once the motor stops
        }
        finish_leg("abandoned: " + position.status.message);
        return position.status;
    }
    if (!position) {
        if (!fault_reported_ && !over_budget) {
            return Status::ok();  // an unusable reply; poll again
        }
        finish_leg("abandoned: " + position.status.message);  // e.g. AZ MOTOR STALLED
        if (fault_reported_) {
            // The firmware dropped its queued moves (firmware.md 6.3): so do we. The target is
            // forgotten, so the client sending the same P again retries the move.
            pending_.clear();
            forget_target();
            commanded_az_.reset();
            commanded_el_.reset();
        }
        return position.status;
    }
    // Azimuth in mechanical degrees (ask_position() keeps mech_az_): arriving on the display
    // azimuth of the wrong branch is not arriving.
    const bool azimuth = leg.axis == Axis::azimuth && mech_az_;
    if (azimuth) {
        observe_azimuth_leg(leg, false);
    }
    const double seen = azimuth ? *mech_az_ : axis_value(position.value, leg.axis);
    const double goal = azimuth ? leg.expected_end.value_or(leg.mech_az) : axis_value(leg.target, leg.axis);
    const auto error = [&](double from, double to) {
        return azimuth ? std::fabs(to - from) : axis_error(leg.axis, from, to);
    };
    const auto end_azimuth_leg = [&](std::string_view how) {
        observe_azimuth_leg(leg, true);
        const bool elsewhere = std::fabs(*mech_az_ - leg.mech_az) > path_jump_degrees;
        finish_leg(how);
        if (elsewhere) {
            replan_after_surprise();
        }
    };
    if (error(seen, goal) <= profile_.arrival_tolerance) {
        if (azimuth) {
            end_azimuth_leg("arrived");
        } else {
            finish_leg("arrived");
        }
        return Status::ok();
    }
    if (!leg.last_seen || error(*leg.last_seen, seen) > stillness_degrees) {
        leg.last_seen = seen;
        leg.last_change = t;
    } else if (t - leg.last_change >= still_window && t - leg.sent_at >= still_window) {
        emit(options_.log, LogLevel::warning, "axis " + std::to_string(static_cast<int>(leg.axis)) + " stopped at " +
                                                  degrees_text(seen) + ", short of " + degrees_text(goal));
        if (azimuth) {
            end_azimuth_leg("stopped");
        } else {
            finish_leg("stopped");
        }
        return Status::ok();
    }
    if (t - leg.sent_at > leg.budget) {   // the budget may have grown with what this poll taught
        finish_leg("timed out");
        return Status{Errc::timeout, "axis " + std::to_string(static_cast<int>(leg.axis)) + " did not reach " +
                                         degrees_text(goal) + " in " + std::to_string(leg.budget.count()) + " ms"};
    }
    return Status::ok();
}

Status Controller::service_combined_leg() {
    Leg& leg = *in_flight_;
    const auto t = now();
    if (t - last_poll_ < poll_interval) {
        return Status::ok();
    }
    last_poll_ = t;
    // Sending anything during `g` may abort it (firmware notes 2, 3.5; 8.5 leaves it open for the
    // 2003 Carryout): listen instead.
    const auto heard = session_.listen(poll_interval);
    if (!heard) {
        finish_leg("abandoned: " + heard.status.message);
        return heard.status;
    }
    const Result<AzEl> sample = note_live_output(heard.value.lines);
    if (sample) {
        leg.live_seen = true;
        live_output_proven_ = true;
    }
    if (sample && axis_error(Axis::azimuth, sample.value.az, leg.target.az) <= profile_.arrival_tolerance &&
        axis_error(Axis::elevation, sample.value.el, leg.target.el) <= profile_.arrival_tolerance) {
        finish_leg("arrived");
        return Status::ok();
    }
    // A prompt after live output ends the move; one before any (the shell may run `g` in the
    // background) ends it only where nothing else can (no move needed, no live output known).
    if (!heard.value.prompt.empty() && (leg.live_seen || !leg.needs_motion || !live_output_proven_)) {
        finish_combined_leg("ended (prompt after the move)");
        return Status::ok();
    }
    // A silent reboot leaves the 2003 Carryout at its root, booting, with no boot line (8.1, 8.2),
    // and a bare `>` prompt may look the same in every menu. What gives it away on any reading of
    // the firmware: this console has printed live positions during `g` before, and now a `g` that
    // needed a move printed none in the window the upstream client relies on, or its live output
    // stopped short of the target with no prompt after it. Either way the console is not where the
    // backend left it: re-initialise (needs_reinit()), which waits out a boot.
    if (live_output_proven_ && leg.needs_motion && !leg.live_seen && t - leg.sent_at >= first_live_line_window) {
        return lose_sync("the dish printed no live position within " +
                         std::to_string(first_live_line_window.count()) + " ms of " +
                         build_combined_move(leg.target) + ": it did not run the move");
    }
    if (t - leg.sent_at > leg.budget) {
        if (leg.live_seen) {
            return lose_sync("the live position stopped at az " + degrees_text(last_position_->az) + " el " +
                             degrees_text(last_position_->el) + ", short of the target, and no prompt followed");
        }
        // No readback at rest: report the commanded position, and say so in describe().
        last_position_ = leg.target;
        last_position_at_ = t;
        position_estimated_ = true;
        finish_leg("assumed complete (estimated move time elapsed)");
    }
    return Status::ok();
}

Status Controller::lose_sync(const std::string& why) {
    emit(options_.log, LogLevel::warning, why + "; the console is not where it was left (a silent reboot?): re-initialising");
    finish_leg("abandoned");
    pending_.clear();
    sync_lost_ = true;
    return Status{Errc::not_initialised, why};
}

Status Controller::service() {
    if (initialised_ && session_.reboot_seen()) {
        initialised_ = false;
        pending_.clear();
        in_flight_.reset();
        return Status{Errc::not_initialised, "the dish printed boot output: it rebooted; initialise again"};
    }
    if (!initialised_) {
        return idle() ? Status::ok() : Status{Errc::not_initialised, "initialize() has not succeeded"};
    }
    if (in_flight_) {
        const Status status = in_flight_->combined ? service_combined_leg() : service_axis_leg();
        if (in_flight_ || !status) {
            return status;
        }
    }
    if (!pending_.empty()) {
        Leg leg = pending_.front();
        pending_.pop_front();
        if (!leg.combined && leg.axis == Axis::azimuth) {
            plan_azimuth_leg(leg);
        }
        return send_leg(leg);
    }
    return Status::ok();
}

// Feeds the mapping learner with an azimuth leg (whole or so far). When the evidence changes, the
// leg's end is where the reading now planned with takes it, and the budget allows for the long way
// round the firmware may be taking.
void Controller::observe_azimuth_leg(Leg& leg, bool at_rest) {
    if (!leg.path_known || !mech_az_) {
        return;
    }
    const auto learnt = az_learner_.observe({leg.target.az, leg.from_mech, leg.lowest, leg.highest,
                                             at_rest ? std::optional<double>(*mech_az_) : std::nullopt});
    if (!learnt) {
        return;
    }
    emit(options_.log, LogLevel::verbose, *learnt);
    const auto point = az_learner_.wrap_point();
    leg.expected_end = azmap::predict(az_learner_.planning(), leg.target.az, leg.from_mech, az_travel_, point.value_or(0.0));
    const auto whole_travel = estimated_move_time(profile_, Axis::azimuth, az_window_.span());
    leg.budget = std::max(leg.budget, std::chrono::duration_cast<std::chrono::milliseconds>(now() - leg.sent_at) +
                                          whole_travel * 2 + leg_margin);
}

// The dish ended an azimuth leg on another branch than planned (the mapping was not the one planned
// with): the legs queued under that plan are dropped and the current target is put on a branch of
// what is now known, from where the dish is.
void Controller::replan_after_surprise() {
    std::erase_if(pending_, [](const Leg& leg) { return !leg.combined && leg.axis == Axis::azimuth; });
    if (!current_target_ || !mech_az_) {
        target_mech_az_.reset();
        return;
    }
    const wrap::Window plan = az_learner_.plan_window(az_usable_);
    const double mechanical = wrap::choose_branch(current_target_->az, *mech_az_, 0, false, plan).mechanical;
    target_mech_az_ = mechanical;
    emit(options_.log, LogLevel::verbose, "azimuth " + degrees_text(current_target_->az) + " re-planned on mechanical " +
                                              degrees_text(mechanical) + " from " + degrees_text(*mech_az_) +
                                              " (window " + degrees_text(plan.min) + ".." + degrees_text(plan.max) + ")");
    if (std::fabs(mechanical - *mech_az_) < same_angle_degrees) {
        return;
    }
    Leg leg;
    leg.axis = Axis::azimuth;
    leg.target = *current_target_;
    leg.mech_az = leg.final_mech_az = mechanical;
    leg.target.az = azmap::command_value(mechanical, az_travel_);
    pending_.push_front(leg);
}

// An azimuth leg longer than wrap::max_leg_deg goes by waypoints (see wrap::next_waypoint() for
// why), each planned from where the dish is when it is sent; the rest of the leg stays queued.
void Controller::plan_azimuth_leg(Leg& leg) {
    const double from = mech_az_ ? *mech_az_ : commanded_az_.value_or(leg.final_mech_az);
    leg.mech_az = leg.waypoints_left > 0 ? wrap::next_waypoint(from, leg.final_mech_az) : leg.final_mech_az;
    leg.target.az = azmap::command_value(leg.mech_az, az_travel_);
    if (leg.mech_az == leg.final_mech_az) {
        return;
    }
    Leg rest = leg;
    rest.mech_az = rest.final_mech_az;
    rest.target.az = azmap::command_value(rest.final_mech_az, az_travel_);
    --rest.waypoints_left;
    pending_.push_front(rest);
    emit(options_.log, LogLevel::verbose,
         "azimuth by waypoints: " + degrees_text(leg.target.az) + " (mechanical " + degrees_text(leg.mech_az) +
             ") on the way from " + degrees_text(from) + " to mechanical " + degrees_text(leg.final_mech_az));
}

Result<AzEl> Controller::note_live_output(std::span<const std::string> lines) {
    auto sample = parse_carryout_live(lines);
    if (sample) {
        note_azimuth_reading(sample.value.az);
        sample.value.az = normalize_azimuth(sample.value.az);
        last_position_ = sample.value;
        last_position_at_ = now();
        position_estimated_ = false;
    }
    return sample;
}

void Controller::finish_combined_leg(std::string_view how) {
    if (!last_position_ || position_estimated_) {
        // The dish printed no live sample: the commanded position is all we know.
        last_position_ = in_flight_ ? in_flight_->target : last_position_;
        last_position_at_ = now();
        position_estimated_ = true;
    }
    finish_leg(how);
}

void Controller::cancel_pending() {
    pending_.clear();
    forget_target();
    // A running `g` on firmware where any byte aborts it (firmware.md 2, 3.5): a bare line ending
    // is the documented way to stop it. Where the byte does not abort, it waits for the move to end.
    if (in_flight_ && in_flight_->combined && profile_.has(quirk_g_aborts_on_input)) {
        if (const auto heard = session_.listen(0ms); heard) {
            note_live_output(heard.value.lines);
        }
        const auto reply = session_.transact("", menu_step_timeout);
        note_live_output(reply.value.lines);
        if (!reply.value.prompt.empty()) {
            // Some firmware reads the byte only once the move is over (firmware notes 8.5): a
            // prompt after a live line at the target is an arrival, not an abort.
            const bool arrived = last_position_ &&
                                 axis_error(Axis::azimuth, last_position_->az, in_flight_->target.az) <= profile_.arrival_tolerance &&
                                 axis_error(Axis::elevation, last_position_->el, in_flight_->target.el) <= profile_.arrival_tolerance;
            emit(options_.log, LogLevel::verbose,
                 arrived ? "stop: the running g had reached its target; the line ending did not abort it"
                         : "stop: sent a line ending to abort the running g");
            finish_leg(arrived ? "arrived" : "aborted by stop");
        }
    }
}

bool Controller::needs_reinit() const {
    if (!initialised_ || sync_lost_ || session_.reboot_seen()) {
        return true;
    }
    return !motor_menu_.empty() && !session_.menu().empty() && session_.menu() != motor_menu_;
}

bool Controller::idle() const { return !in_flight_ && pending_.empty(); }

std::optional<Controller::LegMotion> Controller::leg_motion() const {
    if (!in_flight_ || in_flight_->combined || !last_position_ || !last_position_at_) {
        return std::nullopt;
    }
    const Axis axis = in_flight_->axis;
    // Display degrees: an azimuth leg may command a number beyond 360 (az_mapping.hpp).
    const double to = axis == Axis::azimuth ? normalize_azimuth(in_flight_->target.az) : in_flight_->target.el;
    return LegMotion{axis, axis_value(*last_position_, axis), to, *last_position_at_, in_flight_->sent_at};
}

std::string Controller::describe() const {
    std::string text = std::string(profile_.display_name) + (options_.detect ? " (auto-detected)" : "") + " [" +
                       std::string(profile_.short_name) + ", " +
                       std::to_string(options_.line_baud > 0 ? options_.line_baud : profile_.baud) + " baud";
    if (options_.line_baud > 0 && options_.line_baud != profile_.baud) {
        text += " (this firmware usually runs at " + std::to_string(profile_.baud) + ")";
    }
    if (!session_.last_prompt().empty()) {
        text += ", prompt " + session_.last_prompt();
    }
    text += "]";
    if (!options_.detection_note.empty()) {
        text += "; " + options_.detection_note;
    }
    text += initialised_ ? "; initialised" : "; not initialised";
    if (unhomed_) {
        text += "; axes NOT homed (reset, R 1, homes them)";
    }
    if (tracker_enabled_) {
        text += "; WARNING: NVS " + std::to_string(profile_.tracker_disable_nvs_index) +
                " Disable Tracker Proc? is FALSE (the TV search will move the dish)";
    }
    if (last_position_) {
        text += "; position az " + degrees_text(last_position_->az) + " el " + degrees_text(last_position_->el);
        text += position_estimated_ ? " (last commanded; this dish cannot report its position at rest)" : " (read back)";
    } else {
        text += "; position unknown";
    }
    if (current_target_) {
        text += "; target az " + degrees_text(current_target_->az) + " el " + degrees_text(current_target_->el);
    }
    text += "; el limits " + degrees_text(el_min_) + ".." + degrees_text(el_max_);
    text += options_.leapfrog ? "; leapfrog on" : "; leapfrog off";
    return text;
}

std::string Controller::describe_wrap() const {
    if (az_window_.span() <= 360.0) {
        return "azimuth 0..360, no cable-wrap overlap; azimuth mapping " + az_learner_.describe();
    }
    std::string text = "cable wrap " + degrees_text(az_window_.min) + ".." + degrees_text(az_window_.max) +
                       " (commanded within " + degrees_text(az_usable_.min) + ".." + degrees_text(az_usable_.max) + ")";
    if (mech_az_) {
        text += "; mechanical az " + degrees_text(*mech_az_) +
                (az_report_mechanical_
                     ? " (reported by the dish)"
                     : " (from 0..360 readings; the branch at start was assumed to be the one nearest AZ 0: "
                       "where the G2 homes, the reading itself on a window starting at 0)");
    } else {
        text += "; mechanical az unknown";
    }
    if (target_mech_az_) {
        text += "; target mechanical az " + degrees_text(*target_mech_az_);
    }
    text += "; azimuth mapping " + az_learner_.describe();
    return text;
}

}  // namespace birdcage
