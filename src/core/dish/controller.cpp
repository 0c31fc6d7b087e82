// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "dish/controller.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "console/synchroniser.hpp"
#include "firmware/protocol.hpp"
#include "tracking/leapfrog.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto skip_init_sync_budget = 5000ms;     // skip_init: the dish is said to be up already
constexpr double unexpected_motion_degrees = 0.5;  // idle drift that means the firmware moves the dish
// Two readings closer than this are of a dish at rest (replies print two decimals)...
constexpr double at_rest_degrees = 0.02;
// ...if this much dish time lies between them: two readings a moment apart agree on a dish at speed
// (a console answering fast, a loaded machine reading twice before the emulator's clock moved on);
// over this span they differ for any motion faster than 0.08 deg/s.
constexpr auto at_rest_span = 250ms;
// How often a dish not yet known at rest after initialisation is read (as a leg is followed).
constexpr auto start_motion_poll = 100ms;
// A dish that moves on its own is waited for while it may still cross its whole travel on both
// axes this many times (a calibration that goes to a stop and back, then the leg the backend had
// sent before it saw the motion), and a margin, before the backend moves it from wherever it is.
constexpr int start_motion_crossings = 3;
constexpr auto start_motion_margin = 3000ms;

std::string degrees_text(double value) {
    return format_degrees(value);
}

}  // namespace

Controller::Controller(Transport& transport, ControllerOptions options)
    : profile_(birdcage::profile(options.variant)),
      options_(std::move(options)),
      session_(transport, profile_, options_.log),
      el_min_(profile_.el_min),
      el_max_(profile_.el_max),
      // A travel with negative angles (G2) has no negative absolute numbers: '-' is a relative move (§6.3).
      wrap_(azmap::Travel{{profile_.az_min, profile_.az_max}, profile_.az_min < 0.0}, options_.az_mapping,
            options_.log),
      reader_(session_, profile_, wrap_, state_, [this] { return now(); }),
      menus_(session_, profile_, options_.log) {
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
                 std::string(name) + " " + degrees_text(*user) + " is beyond the " + std::string(profile_.short_name) +
                     " limits; using " + degrees_text(limit));
        }
    };
    override_limit(options_.el_min, el_min_, "el_min");
    override_limit(options_.el_max, el_max_, "el_max");
    if (el_min_ > el_max_) {
        emit(options_.log, LogLevel::warning, "el_min > el_max; using the variant's limits");
        el_min_ = profile_.el_min;
        el_max_ = profile_.el_max;
    }
    session_.set_event_sink(options_.console_events);
    session_.set_requests(backend_requests);  // its moves, homes, search stop and LNB switch
    driver_ = make_move_driver(MoveContext{session_, profile_, state_, wrap_, reader_, options_.log,
                                           [this] { return now(); }, el_min_, el_max_});
}

Controller::~Controller() = default;

Clock::time_point Controller::now() const {
    return options_.clock.now();
}

// A booting, idle or noisy console is brought to a confirmed prompt by the one synchroniser
// (never on a single line: see synchroniser.hpp); it also says at default verbosity that it waits.
// A ready line heard as the latest output (by a poll, or by the synchroniser) is acted on at once:
// no poke, because each moment lets the TV search swing the dish further (docs/reliability.md).
Result<bool> Controller::wait_for_boot() {
    auto at_ready_line = [this](const std::string& ready_line) -> Result<bool> {
        emit(options_.log, LogLevel::warning,
             "dish booted (its ready line \"" + ready_line + "\"): stopping its TV search at once");
        return {true, Status::ok()};
    };
    if (session_.just_booted()) {
        const std::string ready_line = session_.last_boot_line();
        session_.clear_reboot_seen();
        return at_ready_line(ready_line);
    }
    session_.clear_reboot_seen();
    const auto synced = session_.synchronise(console_sync_settings(profile_, boot_budget_));
    if (!synced) {
        return {false, Status{synced.status.code, "the " + std::string(profile_.display_name) +
                                                      " console did not come into sync: " + synced.status.message}};
    }
    if (!synced.value.ready_line.empty()) {
        return at_ready_line(synced.value.ready_line);
    }
    if (synced.value.boot_heard) {
        emit(options_.log, LogLevel::warning, "dish booted (last boot output \"" + synced.value.last_boot_line + "\")");
    }
    return {false, Status::ok()};
}

Status Controller::in_submenu(std::string_view menu, const std::function<Status(ConsoleSession&)>& work) {
    if (leg_in_flight()) {
        return {Errc::busy, "a leg is in flight; the motor menu must stay open"};
    }
    return menus_.visit(menu, work);
}

// Read-only: the firmware's TV search runs after boot unless NVS "Disable Tracker Proc?" is TRUE
// (docs/firmware.md 6.2, Appendix A). The backend never writes NVS; it only warns.
Status Controller::check_tracker_disabled() {
    if (profile_.tracker_disable_nvs_index < 0) {
        return Status::ok();
    }
    tracker_checked_ = true;
    const auto entry = menus_.read_nvs(profile_.tracker_disable_nvs_index);
    if (!entry) {
        return entry.status;
    }
    if (entry.value && entry.value->current == "FALSE") {
        tracker_enabled_ = true;
        emit(options_.log, LogLevel::warning,
             "NVS " + std::to_string(entry.value->index) + " (" + entry.value->name +
                 ") is FALSE: the firmware's TV-satellite search runs after every boot and will move the dish on "
                 "its own. Set it to TRUE yourself (nvs, e " +
                 std::to_string(entry.value->index) + " TRUE, s, reboot); the backend never writes NVS.");
    }
    return Status::ok();
}

void Controller::carry_over(const Controller& before) {
    if (before.state_.last_position && before.state_.last_position_at) {
        state_.record(*before.state_.last_position, *before.state_.last_position_at, before.state_.position_estimated);
    }
    wrap_ = before.wrap_;
    driver_->take_learning_from(*before.driver_);
}

Status Controller::reinitialize(std::chrono::milliseconds boot_budget) {
    const Status st = initialize_within(std::min(boot_budget, options_.boot_timeout));
    if (st) {
        driver_->recovered();
    }
    return st;
}

Status Controller::initialize() {
    return initialize_within(options_.boot_timeout);
}

// From whatever the console shows to the motor menu: synchronise (waiting out a boot), leave any
// submenu, stop the TV search, enter the motor menu.
Status Controller::open_motor_menu() {
    if (options_.skip_init) {
        emit(options_.log, LogLevel::verbose, "skip_init: assuming the dish is booted and in its motor menu");
        if (profile_.prompt_known()) {
            if (const auto synced = session_.synchronise(console_sync_settings(profile_, skip_init_sync_budget));
                !synced) {
                return synced.status;
            }
        }
        return Status::ok();
    }
    const Result<bool> booted = wait_for_boot();
    if (!booted) {
        return booted.status;
    }
    if (booted.value) {
        // At its root after the boot: the steps that only leave submenus (`q`, a bare line) would
        // delay the stop, so the stop's own command is the first thing the dish hears.
        Span<const ConsoleStep> search_kill = profile_.search_kill;
        while (!search_kill.empty() && (search_kill.front().command == "q" || search_kill.front().command.empty())) {
            search_kill = search_kill.subspan(1);
        }
        const Status killed = menus_.run_steps(search_kill, "stopping the TV search");
        if (killed) {
            return menus_.enter_motor_menu("entering the motor menu");
        }
        if (killed.code != Errc::timeout) {
            return killed;
        }
        // A firmware that prints more after its ready line answers only once it has finished: it
        // kept the input, so its prompt is found the usual way and the whole stop sent again.
        emit(options_.log, LogLevel::verbose,
             "no answer right after the ready line (" + killed.message + "); waiting for the console's prompt");
        if (const Result<bool> again = wait_for_boot(); !again) {
            return again.status;
        }
    }
    if (Status left = menus_.leave_submenus(); !left) {
        return left;
    }
    if (Status killed = menus_.run_steps(profile_.search_kill, "stopping the TV search"); !killed) {
        return killed;
    }
    return menus_.enter_motor_menu("entering the motor menu");
}

Status Controller::initialize_within(std::chrono::milliseconds boot_budget) {
    boot_budget_ = boot_budget;
    initialised_ = false;
    homing_.reset();
    // Whatever was commanded before is void (a reboot stops the axes, a hang-up loses replies).
    driver_->reset();
    forget_target();
    wrap_.recheck_branch();
    if (Status opened = open_motor_menu(); !opened) {
        return opened;
    }
    if (profile_.prompt_known() && session_.menu() != menu_for_prompt(profile_, profile_.motor_prompt)) {
        return Status{Errc::protocol, "expected the motor prompt " + std::string(profile_.motor_prompt) +
                                          ", console shows " + session_.last_prompt()};
    }
    session_.clear_reboot_seen();
    start_rest_.reset();
    replan_at_rest_ = false;
    moves_regardless_ = false;
    driver_->watch_motion_of_its_own(true);
    if (!profile_.position_query.empty()) {
        const auto position = reader_.ask(query_timeout);
        if (position) {
            start_rest_.emplace(position.value, now());
        }
        if (!position && position.status.code != Errc::not_homed) {
            if (position.status.code == Errc::disconnected || position.status.code == Errc::io) {
                return position.status;
            }
            emit(options_.log, LogLevel::warning, "initial position query failed: " + position.status.message);
        }
    }
    warn_if_unhomed();
    motor_menu_ = session_.menu();  // where every later reply must come from (needs_reinit())
    initialised_ = true;
    emit(options_.log, LogLevel::verbose, "initialised: " + describe());
    return Status::ok();
}

bool Controller::moved_on_its_own(const AzEl& before, const AzEl& now) const {
    return std::fabs(azimuth_difference(before.az, now.az)) > unexpected_motion_degrees ||
           std::fabs(before.el - now.el) > unexpected_motion_degrees;
}

Result<AzEl> Controller::query_position() {
    if (homing_) {
        return {state_.last_position.value_or(AzEl{}), Status{Errc::busy, "homing: the console is busy until it ends"}};
    }
    if (profile_.position_query.empty()) {
        if (state_.last_position) {
            return {*state_.last_position, Status::ok()};
        }
        return {
            {},
            Status{Errc::unsupported, "this dish cannot report its position at rest and none has been commanded yet"}};
    }
    const auto before = state_.last_position;
    const auto mech_before = wrap_.mechanical();
    // Not yet known at rest after initialisation counts: a jump there is as likely noise.
    const bool at_rest = initialised_ && !homing_ && driver_->idle() && !(start_rest_ && start_rest_->moving);
    auto position = reader_.ask(query_timeout);
    // At rest a reading far from the last one is either the dish moving on its own or a reply that
    // lost bytes on the line (`123.45` -> `13.45` still parses). Ask again: a real position repeats,
    // a corrupted one is refused and the previous position kept.
    if (position && before && at_rest && moved_on_its_own(*before, position.value)) {
        const AzEl first = position.value;
        const auto again = reader_.ask(query_timeout);
        if (!again || moved_on_its_own(first, again.value)) {
            state_.last_position = before;
            wrap_.restore_mechanical(mech_before);
            if (start_rest_ && !start_rest_->moving) {
                // Right after initialisation this may also be a dish still moving fast: either
                // way only two readings that agree tell where it is (note_start_reading()).
                start_rest_->start_moving(now());
            }
            return {*before, Status{Errc::protocol, "inconsistent position readings (az " + degrees_text(first.az) +
                                                        " el " + degrees_text(first.el) +
                                                        ", then not repeated): line noise? keeping the last position"}};
        }
        position = again;
    }
    // The dish moving on its own at rest is the firmware's TV search (tracker enabled): find out
    // why once, read-only (docs/firmware.md 6.2).
    if (position && before && at_rest && !tracker_checked_ && profile_.tracker_disable_nvs_index >= 0 &&
        moved_on_its_own(*before, position.value)) {
        emit(options_.log, LogLevel::warning,
             "the dish moves on its own while idle; checking whether its tracker is enabled");
        if (Status checked = check_tracker_disabled(); !checked) {
            return {position.value, checked};
        }
    }
    if (position) {
        note_start_reading(position.value);
    }
    return position;
}

Status Controller::poll_at_rest() {
    if (!profile_.position_query.empty() || homing_) {
        return query_position().status;
    }
    // A prompt ends a reply; where prompts are unknown a reply would also end on the quiet gap with
    // nothing in it, as if answered: only a prompt or a line of text counts.
    const ReplyComplete spoke = [](Span<const std::string> lines) { return !lines.empty(); };
    constexpr std::string_view pokes[] = {"", "?"};
    for (const std::string_view poke : pokes) {
        if (sign_of_life_poke_ && *sign_of_life_poke_ != poke) {
            continue;
        }
        const auto reply = session_.transact(poke, query_timeout, spoke);
        if (!reply.value.prompt.empty() || !reply.value.lines.empty()) {
            sign_of_life_poke_ = poke;
            return reply.status;  // answered (a fault line in the answer is still reported)
        }
        if (!reply && reply.status.code != Errc::timeout) {
            return reply.status;
        }
    }
    const std::string asked = !sign_of_life_poke_           ? "a bare line ending nor to ?"
                              : sign_of_life_poke_->empty() ? "a bare line ending"
                                                            : "?";
    return {Errc::timeout, "no answer to " + asked + " within " + std::to_string(query_timeout.count()) +
                               " ms (this dish cannot report its position at rest)"};
}

// The first reading after initialisation may be of a dish still moving: a search stopped just
// before brakes for seconds, a boot move may still run. A leg sent then is misjudged (the firmware
// runs it only once the axis has stopped, so it looks stopped short, and the azimuth mapping
// learnt from it is wrong), and a branch assumed from a reading in motion is not where the dish
// rests. So until readings agree over at_rest_span legs wait and service() reads the dish (idle()
// only once it is seen moving). A dish seen moving must stay still for longer: between two moves its firmware has
// queued (a calibration's legs) a motor that starts late leaves it still for seconds.
void Controller::note_start_reading(const AzEl& reading) {
    if (!start_rest_) {
        return;
    }
    StartRest& rest = *start_rest_;
    const auto t = now();
    const bool same = std::fabs(azimuth_difference(rest.still.az, reading.az)) < at_rest_degrees &&
                      std::fabs(rest.still.el - reading.el) < at_rest_degrees;
    if (!same) {
        if (!rest.moving) {
            rest.start_moving(t);
            emit(options_.log, LogLevel::verbose,
                 "the dish still moves after initialisation (az " + degrees_text(rest.still.az) + " el " +
                     degrees_text(rest.still.el) + ", then az " + degrees_text(reading.az) + " el " +
                     degrees_text(reading.el) + "): moves wait until it is at rest");
        }
        rest.still = rest.last = reading;
        rest.still_at = t;
        return;
    }
    rest.last = reading;
    const auto span =
        rest.moving ? std::max<std::chrono::milliseconds>(at_rest_span, driver_->startup_allowance()) : at_rest_span;
    if (t - rest.still_at < span) {
        return;
    }
    if (rest.moving) {
        emit(options_.log, LogLevel::verbose,
             "the dish is at rest at az " + degrees_text(reading.az) + " el " + degrees_text(reading.el));
        wrap_.judge_branch_at_rest();
    }
    end_start_rest();
}

// The dish moved on its own while a leg waited to start (its firmware still ran something else, and
// runs the leg after it): the legs were dropped, and the target is planned again where it rests.
void Controller::enter_start_motion(const AzEl& reading) {
    emit(options_.log, LogLevel::verbose,
         "the dish moves on its own (az " + degrees_text(reading.az) + " el " + degrees_text(reading.el) +
             "): moves wait until it is at rest");
    start_rest_.emplace(reading, now());
    start_rest_->start_moving(now());
    replan_at_rest_ = true;
}

void Controller::end_start_rest() {
    start_rest_.reset();
    if (!std::exchange(replan_at_rest_, false) || !state_.target) {
        return;
    }
    const AzEl target = *state_.target;
    forget_target();
    if (Status planned = set_target(target); !planned) {
        emit(options_.log, LogLevel::warning, "the target could not be planned again: " + planned.message);
    }
}

// A dish seen moving since initialisation, read until it rests; bounded: one that moves on its
// own for longer (a TV search the firmware keeps running) is moved from wherever it is.
Status Controller::service_start_motion() {
    const auto t = now();
    const auto crossing = estimated_move_time(profile_, Axis::azimuth, profile_.az_max - profile_.az_min) +
                          estimated_move_time(profile_, Axis::elevation, el_max_ - el_min_) +
                          driver_->startup_allowance();
    const auto budget = start_motion_crossings * crossing + start_motion_margin;
    if (start_rest_->moving && t - start_rest_->since > budget) {
        emit(options_.log, LogLevel::warning,
             "the dish keeps moving on its own at az " + degrees_text(start_rest_->last.az) + " el " +
                 degrees_text(start_rest_->last.el) + ": moving it from wherever it is");
        move_regardless();
        return Status::ok();
    }
    if (t - start_rest_->polled < start_motion_poll) {
        return Status::ok();
    }
    start_rest_->polled = t;
    const auto position = reader_.ask(query_timeout);
    if (!position) {
        return position.status;
    }
    note_start_reading(position.value);
    // Moving at this reading: a G2 whose TV search is enabled never rests on its own (docs/firmware.md 6.2).
    if (start_rest_ && start_rest_->moving && start_rest_->still_at >= t && profile_.tracker_disable_nvs_index >= 0 &&
        !tracker_checked_) {
        if (Status checked = check_tracker_disabled(); !checked) {
            return checked;
        }
        if (tracker_enabled_) {
            emit(options_.log, LogLevel::warning, "the TV search keeps the dish moving: moving it from wherever it is");
            move_regardless();
        }
    }
    return Status::ok();
}

// A dish that does not rest on its own is moved from wherever it is, and its motion no longer
// stops the legs (they would wait for it forever).
void Controller::move_regardless() {
    moves_regardless_ = true;
    driver_->watch_motion_of_its_own(false);
    end_start_rest();
}

Status Controller::set_target(AzEl target, double az_rate_dps, const std::optional<wrap::PassAhead>& ahead) {
    if (!std::isfinite(target.az) || !std::isfinite(target.el)) {
        return Status{Errc::invalid_argument, "target must be finite"};
    }
    if (state_.unhomed) {
        return Status{Errc::not_homed, "the axes are not homed; moves are refused"};
    }
    if (!std::isfinite(az_rate_dps)) {
        az_rate_dps = 0.0;
    }
    // Gpredict's 0..360 and -180..180 modes (and Hamlib's -180..540) all reduce to a display
    // azimuth; the cable-wrap branch is the move driver's choice.
    AzEl wanted{normalize_azimuth(target.az), std::clamp(target.el, el_min_, el_max_)};
    if (options_.az_min && options_.az_max && *options_.az_min < *options_.az_max) {
        const double clamped = std::clamp(wanted.az, *options_.az_min, *options_.az_max);
        if (clamped != wanted.az) {
            emit(options_.log, LogLevel::verbose,
                 "azimuth " + degrees_text(wanted.az) + " clamped to " + degrees_text(clamped) + " (az_min/az_max)");
            wanted.az = clamped;
        }
    }
    if (wanted.el != target.el) {
        emit(options_.log, LogLevel::verbose,
             "elevation " + degrees_text(target.el) + " clamped to " + degrees_text(wanted.el));
    }
    const std::optional<AzEl> previous = state_.target;
    if (previous && std::fabs(azimuth_difference(previous->az, wanted.az)) < same_angle_degrees &&
        std::fabs(previous->el - wanted.el) < same_angle_degrees) {
        return Status::ok();
    }
    state_.target = wanted;
    AzEl command = wanted;
    if (options_.leapfrog && state_.last_position) {
        command = apply_leapfrog(wanted, *state_.last_position);
        command.el = std::clamp(command.el, el_min_, el_max_);
    }
    driver_->plan(wanted, command, previous, az_rate_dps, ahead);
    return Status::ok();
}

void Controller::forget_target() {
    state_.target.reset();
    wrap_.forget_target();
}

Status Controller::service() {
    if (initialised_ && session_.reboot_seen()) {
        initialised_ = false;
        homing_.reset();
        driver_->reset();
        return Status{Errc::not_initialised, "the dish printed boot output: it rebooted; initialise again"};
    }
    if (!initialised_) {
        return idle() ? Status::ok() : Status{Errc::not_initialised, "initialize() has not succeeded"};
    }
    if (homing_) {
        return service_homing();
    }
    if (start_rest_) {
        return service_start_motion();
    }
    const Status status = driver_->service();
    if (driver_->took_motion_of_its_own() && state_.last_position) {
        enter_start_motion(*state_.last_position);
    }
    return status;
}

void Controller::cancel_pending() {
    forget_target();
    driver_->cancel();
}

bool Controller::needs_reinit() const {
    if (!initialised_ || driver_->sync_lost() || session_.reboot_seen()) {
        return true;
    }
    return !motor_menu_.empty() && !session_.menu().empty() && session_.menu() != motor_menu_;
}

// Not yet known at rest is not moving: legs wait (service()), but nothing is under way.
bool Controller::idle() const {
    return !homing_ && !(start_rest_ && start_rest_->moving) && driver_->idle();
}

// Homing holds the shell like a leg does: the console must stay in the motor menu.
bool Controller::leg_in_flight() const {
    return homing_ || driver_->leg_in_flight();
}

MovingAxes Controller::moving_axes() const {
    return driver_->moving_axes();
}

std::string dish_identity(const FirmwareProfile& profile, bool auto_detected) {
    return std::string(profile.display_name) + (auto_detected ? " (auto-detected)" : "");
}

// The rate is the one the port was opened at. No word on the variant's usual rate: a dish that
// answered runs at this one (or the line is a USB adapter that ignores it); the advice belongs to
// a dish that does not answer, where the synchroniser gives it. On a pty (the emulator) no rate
// applies, so none is named: the G2's "57600 baud" there would read as a wrong setting.
std::string Controller::describe() const {
    std::string text = dish_identity(profile_, options_.detect) + ": ";
    if (!initialised_) {
        text += "not initialised, ";
    }
    if (state_.unhomed) {
        text += "axes NOT homed, ";
    }
    if (tracker_enabled_) {
        text += "TV search ON, ";
    }
    text += homing_ ? "homing" : idle() ? "idle" : "moving";
    text += "; [" + std::string(profile_.short_name) + ", " +
            (options_.line_is_pty ? std::string("pty, no line speed") : std::to_string(line_baud()) + " baud");
    if (!session_.last_prompt().empty()) {
        text += ", prompt " + session_.last_prompt();
    }
    text += "]";
    if (!options_.detection_note.empty()) {
        text += "; " + options_.detection_note;
    }
    if (state_.unhomed) {
        text += "; reset (R 1) homes the axes";
    }
    if (tracker_enabled_) {
        text += "; WARNING: NVS " + std::to_string(profile_.tracker_disable_nvs_index) +
                " Disable Tracker Proc? is FALSE (the TV search will move the dish)";
    }
    if (state_.last_position) {
        text +=
            "; position az " + degrees_text(state_.last_position->az) + " el " + degrees_text(state_.last_position->el);
        text += state_.position_estimated ? " (last commanded; this dish cannot report its position at rest)"
                                          : " (read back)";
    } else {
        text += "; position unknown";
    }
    if (state_.target) {
        text += "; target az " + degrees_text(state_.target->az) + " el " + degrees_text(state_.target->el);
    }
    if (const auto waypoint = driver_->azimuth_waypoint()) {
        // A stop lands here, not at the target: say so while it can still happen.
        text += "; azimuth by waypoints: the leg under way ends at az " + degrees_text(*waypoint);
    }
    text += "; el limits " + degrees_text(el_min_) + ".." + degrees_text(el_max_);
    text += options_.leapfrog ? "; leapfrog on" : "; leapfrog off";
    return text;
}

MotorTiming Controller::learnt_motor() const {
    return driver_->learnt_motor();
}

std::optional<double> Controller::learnt_step_seconds(Axis axis) const {
    return driver_->learnt_step_seconds(axis);
}

}  // namespace birdcage
