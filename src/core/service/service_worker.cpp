// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "service/service_worker.hpp"

#include "console/detect.hpp"
#include "dish/receiver.hpp"
#include "firmware/protocol.hpp"
#include "service/recovery.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace birdcage {
namespace {

// A dish counts as fast enough to steer ahead (choose_mode_from_dish) when a small step takes it at
// most this long from command to arrival: the G2 about 0.15 s, the emulated Trav'ler over 1 s.
constexpr double fast_step_s = 0.6;
// A fit of one target slower than this (real milliseconds) is logged: it delays the next leg.
constexpr long slow_fit_ms = 50;

}  // namespace

ServiceWorker::ServiceWorker(ServiceMailbox& mailbox, std::unique_ptr<Transport> transport, ControllerOptions options,
                             ServiceTiming timing, TransportFactory reopen)
    : mailbox_(mailbox),
      transport_(std::move(transport)),
      options_(std::move(options)),
      controller_(options_.detect ? nullptr : std::make_unique<Controller>(*transport_, options_)),
      profile_(controller_ ? &controller_->profile() : &probe_profile()),
      timing_(timing),
      reopen_(std::move(reopen)) {}

void ServiceWorker::set_pointing(PointingOptions pointing) {
    pointing_ = pointing;
    predictor_ = TargetPredictor(pointing.predictor);
    if (controller_) {
        predictor_.set_dish_limits(controller_->el_min(), controller_->el_max());
    }
}

Status ServiceWorker::detect() {
    const auto found = detect_variant(*transport_, options_.log, options_.boot_timeout);
    if (!found) {
        return found.status;
    }
    options_.variant = found.value.variant;
    options_.detection_note = found.value.evidence;
    if (found.value.maybe_inside) {
        const double cap = birdcage::profile(*found.value.maybe_inside).el_max;
        options_.el_max = std::min(options_.el_max.value_or(cap), cap);
    }
    controller_ = std::make_unique<Controller>(*transport_, options_);
    return Status::ok();
}

Status ServiceWorker::start() {
    if (!controller_) {
        if (Status st = detect(); !st) {
            return st;
        }
    }
    profile_ = &controller_->profile();
    if (!pointing_.mode) {
        pointing_.mode = profile_->predictive_by_default ? PointingMode::predictive : PointingMode::none;
        mode_from_dish_ = true;
    }
    predictor_.set_dish_limits(controller_->el_min(), controller_->el_max());
    if (Status st = controller_->initialize(); !st) {
        // A dish heard booting may yet take minutes (a Carryout calibrates for 10-15): the caller
        // is not held for it. A silent line, or any other failure, fails the start.
        if (st.code != Errc::timeout || !controller_->boot_heard()) {
            return st;
        }
        emit(options_.log, LogLevel::warning,
             "the dish is still booting: it is initialised in the background (" + st.message + ")");
        begin_recovery("initialising: the dish was still booting when opened");
        published_.initialising = true;
        publish(st, true);
        return Status::ok();
    }
    read_lnb_supply_at_open();
    // A dish that answers its menus but not a position query is still usable for moves; the error
    // is published and reported by position() until a poll succeeds.
    const Status first = controller_->poll_at_rest();
    last_poll_ = options_.clock.now();
    published_.last_answer_at = Clock::now();
    publish(first, true);
    return Status::ok();
}

// The LNB supply survives a restart of rotctld (the dish stays powered): what the backend reports
// is read from the tuner, or unknown, never the boot default assumed (docs/receiver.md).
void ServiceWorker::read_lnb_supply_at_open() {
    if (profile_->receiver_menu.empty()) {
        return;
    }
    const Result<LnbSupply> supply = read_lnb_supply(*controller_);
    if (supply) {
        mailbox_.set_lnb_supply(supply.value);
        emit(options_.log, LogLevel::verbose,
             "LNB supply read from the dish: " + std::to_string(lnb_volts(supply.value)) + " V");
        return;
    }
    emit(options_.log, LogLevel::warning,
         "the LNB supply could not be read from the dish (" + supply.status.message +
             "): unknown until set (V LNB 13|18) or the dish reboots");
}

void ServiceWorker::run() {
    Clock::duration period{0};
    while (mailbox_.wait(options_.clock.to_real(period), published_.recovering)) {
        period = step();
    }
}

Clock::duration ServiceWorker::step() {
    const ServiceMail mail = mailbox_.take();
    const bool was_recovering = published_.recovering;
    const Outcome outcome = was_recovering ? recover(mail) : work_on(mail);
    const std::string fault = controller_->take_fault();

    bool entered_recovery = false;
    if (!was_recovering) {
        const RecoveryVerdict verdict =
            classify_step(StepOutcome{outcome.status, outcome.talked, controller_->needs_reinit(), !fault.empty()},
                          consecutive_failures_, timing_.failures_before_recovery);
        consecutive_failures_ = verdict.consecutive_failures;
        if (verdict.action == RecoveryAction::reopen) {
            link_down_ = true;
        }
        if (verdict.action != RecoveryAction::none) {
            emit(options_.log, LogLevel::warning, "recovering: " + verdict.reason);
            begin_recovery(verdict.reason);
            entered_recovery = true;
        }
    }
    if (!fault.empty()) {
        mailbox_.report_fault(Status{Errc::protocol, fault});  // "dish reported: AZ MOTOR STALLED"
    }
    publish(outcome.status, outcome.talked);
    return next_period(entered_recovery);
}

// The mail in the order the client meant it: a stop posted before a target clears the old pass
// first, so `S` then `P` (however quickly) ends up doing what `P` says; likewise `R` then `P`
// homes first and then goes to the target.
ServiceWorker::Outcome ServiceWorker::work_on(const ServiceMail& mail) {
    Outcome out;
    if (mail.stop) {
        controller_->cancel_pending();
        forget_the_pass();
    }
    if (mail.home) {
        // The home runs inside controller_->service() a short slice per step, so the mailbox keeps
        // being read while it runs: `p` answers, `P` and `S` are taken.
        forget_the_pass();
        out.status = controller_->start_home();
        mailbox_.home_started();
    }
    for (const ServiceMail::Answered& answered : mail.answered) {
        predictor_.note_reported(answered.at, answered.position);
    }
    if (mail.target) {
        // A target beside a home was posted after it (post_home() drops the ones before): it is
        // taken once the home has started, so its legs wait for the home's end.
        const Status accepted = accept_target(*mail.target, mail.target_posted_at, mail.reported_before_target);
        out.status = out.status ? accepted : out.status;
    }
    // A receiver job waits for the leg in flight; legs still queued wait for the job.
    bool ran_job = false;
    if (out.status && mail.job && !mail.home && !controller_->leg_in_flight() && mailbox_.job_started(mail.job)) {
        ran_job = true;
        leg_overhead_.interrupt();
        out.status = mail.job->work(*controller_);
        mailbox_.job_finished(*mail.job, out.status);
    }
    if (out.status && !mail.target && !mail.home) {
        out.status = steer();
    }
    out.talked = mail.target || mail.home || mail.stop || ran_job || !controller_->idle();
    if (out.status) {
        out.status = controller_->service();
    }
    const auto now = options_.clock.now();
    if (!controller_->idle()) {
        // Read the position again shortly after the last leg ends (ServiceTiming).
        last_poll_ = now - timing_.idle_poll_period + timing_.settle_polls_after_move * timing_.busy_period;
        return out;
    }
    if (leg_overhead_.timing()) {
        leg_overhead_.finished(now);
        char text[96];
        std::snprintf(text, sizeof text, "steering: leg overhead now %.3f s (smoothed)",
                      leg_overhead_.overhead_s().value_or(0.0));
        emit(options_.log, LogLevel::verbose, text);
    }
    if (out.status && now - last_poll_ >= timing_.idle_poll_period) {
        out.talked = true;
        out.status = controller_->poll_at_rest();
        last_poll_ = now;
    }
    return out;
}

void ServiceWorker::begin_recovery(const std::string& reason) {
    attempts_ = 0;
    backoff_ = std::chrono::milliseconds{0};
    reinitialised_ = false;
    recovery_started_ = options_.clock.now();
    published_.recovering = true;
    published_.recovery_reason = reason;
    published_.recovering_since = Clock::now();
}

ServiceWorker::Outcome ServiceWorker::recover(const ServiceMail& mail) {
    if (mail.stop) {
        // `S` while the dish cannot be asked: nothing is resumed (the mailbox dropped the target)
        // and the pass is forgotten, as it would have been at once.
        controller_->cancel_pending();
        forget_the_pass();
    }
    if (mail.target) {
        // The client tracks on while the dish cannot be asked: its targets still teach the
        // satellite's motion, the orbit and the client's habits, so steering resumes from an
        // estimate that ran through the outage instead of one started afresh. The dish's position
        // is no measure of the client's lead meanwhile.
        predictor_.observe(std::min(mail.target_posted_at, options_.clock.now()), *mail.target, std::nullopt);
        previous_client_target_ = std::exchange(client_target_, *mail.target);
    }
    const Status attempt = recover_once();
    if (!attempt) {
        const RetryVerdict retry =
            classify_failed_attempt(attempt, backoff_, timing_.recovery_backoff_min, timing_.recovery_backoff_max);
        link_down_ = link_down_ || retry.reopen;
        backoff_ = retry.backoff;
        published_.recovery_reason = attempt.message;
        return {attempt, true};
    }
    consecutive_failures_ = 0;
    published_.recovering = false;
    published_.last_answer_at = Clock::now();  // recover_once() has just read the position
    mailbox_.dish_rebooted();
    const bool first = std::exchange(published_.initialising, false);
    if (!first) {
        ++published_.recoveries;
    }
    emit(options_.log, LogLevel::warning,
         std::string(first ? "initialised" : "recovered") + " after " + std::to_string(attempts_) + " attempt(s)" +
             (mail.latest_target ? "; resuming the last target" : ""));
    // Targets posted meanwhile were kept by the mailbox (its latest target); a stop cleared it.
    return {mail.latest_target ? resume(*mail.latest_target) : Status::ok(), true};
}

// One bounded recovery attempt: reopen the device if it hung up, re-initialise the dish (boot wait
// bounded by the slice, search stop, motor menu), then read its position afresh. An attempt that
// fails after the re-initialisation only reads again next time, unless the dish needs more.
Status ServiceWorker::recover_once() {
    ++attempts_;
    if (link_down_) {
        if (!reopen_) {
            return {Errc::disconnected, "the serial port hung up and cannot be reopened"};
        }
        auto reopened = reopen_();
        if (!reopened) {
            return {Errc::disconnected, "the serial port hung up; reopening it (attempt " + std::to_string(attempts_) +
                                            "): " + reopened.status.message};
        }
        // A new controller over the new transport: the old one holds a reference to the old one.
        auto reopened_controller = std::make_unique<Controller>(*reopened.value, options_);
        reopened_controller->carry_over(*controller_);
        controller_ = std::move(reopened_controller);
        transport_ = std::move(reopened.value);
        link_down_ = false;
        reinitialised_ = false;
        emit(options_.log, LogLevel::warning, "serial port reopened; re-initialising the dish");
    }
    if (!reinitialised_ || controller_->needs_reinit()) {
        const Status st = controller_->reinitialize(timing_.recovery_boot_slice);
        if (!st) {
            return {st.code, "re-initialising the dish (attempt " + std::to_string(attempts_) + "): " + st.message};
        }
        reinitialised_ = true;
    }
    return read_position_afresh();
}

// The first position given after a recovery is one read after it began: the dish may have moved
// meanwhile (a reboot homes or calibrates the axes), so the reading from before says nothing of
// where it is now. Until then position() keeps giving that earlier reading as the last one read.
Status ServiceWorker::read_position_afresh() {
    const auto read_after_start = [this] {
        const auto at = controller_->last_position_at();
        return at && *at > recovery_started_;
    };
    // Nothing to read on a dish that cannot report its position at rest, nor once the
    // re-initialisation has read it.
    if (profile_->position_query.empty() || read_after_start()) {
        return Status::ok();
    }
    const Result<AzEl> fresh = controller_->query_position();
    // An unhomed dish answers with its sentinel: it is reachable, and position() reports why it
    // has no position (the client homes it with R 1).
    if (read_after_start() || fresh.status.code == Errc::not_homed) {
        return Status::ok();
    }
    if (controller_->needs_reinit()) {
        reinitialised_ = false;
    }
    return {fresh.status ? Errc::protocol : fresh.status.code,
            "reading the position after re-initialising (attempt " + std::to_string(attempts_) +
                "): " + (fresh.status ? std::string("the reading was refused") : fresh.status.message)};
}

Status ServiceWorker::resume(AzEl target) {
    aim_.reset();  // the moves in flight were lost: steer again from the estimate
    aims_ahead_ = {};
    leg_overhead_.interrupt();
    // A target posted while the worker was stuck in the failing step or recovering never reached
    // the estimator: take it as new, or the dish would return to the one before it.
    const bool unseen = !client_target_ || client_target_->az != target.az || client_target_->el != target.el;
    if (unseen) {
        return accept_target(target, options_.clock.now());
    }
    const auto now = options_.clock.now();
    const std::optional<Prediction> prediction = predictor_.predict(now);
    if (steering_predictively() && prediction) {
        return steer();
    }
    return aim(target,
               azimuth_direction_hint(prediction, sky_position(), previous_client_target_, target,
                                      sky_limits_at(target.az).min),
               now, prediction);
}

// Predictive steering aims ahead of the satellite and moves in small steps; a dish that needs a
// second or more for one only trails each aim, and the client's corrections then fight it
// (docs/tracking.md §4). Which kind of dish this is, is a fact about its motors, not its firmware:
// the same HAL 2.05 console drives fast and slow mounts.
void ServiceWorker::choose_mode_from_dish() {
    if (!mode_from_dish_) {
        return;
    }
    const auto az = controller_->learnt_step_seconds(Axis::azimuth);
    const auto el = controller_->learnt_step_seconds(Axis::elevation);
    if (!az || !el) {
        return;
    }
    const double step_s = std::max(*az, *el);
    const PointingMode chosen = step_s <= fast_step_s ? PointingMode::predictive : PointingMode::none;
    if (chosen != pointing_.mode) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "pointing: a small step (0.4-2 deg) takes this dish %.2f s from command to arrival: %s "
                      "from now on (set -C pointing=... to choose)",
                      step_s, chosen == PointingMode::predictive ? "predictive" : "none");
        emit(options_.log, LogLevel::verbose, text);
        pointing_.mode = chosen;
        aim_.reset();
        leg_overhead_.interrupt();
    }
}

// A dish too slow for small steps trails each aim of the local estimate, and the client's
// corrections fight it; a trusted orbit instead knows where the satellite will be when even a slow
// move ends (the benchmark's Trav'ler at 0.5 deg: closer to the oracle on 7 of 9 passes than with
// the client's own targets). So where the dish chose `none`, the orbit's trust switches to
// predictive steering and its loss back.
bool ServiceWorker::steering_predictively() const {
    return pointing_.mode == PointingMode::predictive || (mode_from_dish_ && predictor_.pass_model_in_use());
}

Status ServiceWorker::accept_target(AzEl target, Clock::time_point sent_at, std::optional<AzEl> reported) {
    const auto now = options_.clock.now();
    choose_mode_from_dish();
    // Every mode feeds the estimator: its azimuth rate tells the controller which way a pass
    // turns, so it can choose a cable-wrap branch with room for the whole pass.
    // The client's lead shows in the gap between its target and the dish it compared the satellite
    // with: the position it last read back, not the dish now. A client that re-sends before it has
    // read the dish's move towards its previous target (Gpredict's timer ticks between its I/O
    // loops) would otherwise show a gap of nearly nothing, and whether such a re-send came within
    // a fixed time of the previous target depended on the I/O's real timing: at k = 1 the G2 learnt
    // a lead of 0.09 deg in one run of two and started its motors 528 times on iss-45 at 5 deg,
    // against 140 (docs/benchmarks.md).
    const auto fit_started = Clock::now();
    predictor_.observe(std::min(sent_at, now), target, reported ? reported : sky_position());
    // The fit runs on this thread, between the dish's legs: on a loaded machine it can hold them up.
    const auto fit_ms = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - fit_started).count();
    if (fit_ms >= slow_fit_ms) {
        emit(options_.log, LogLevel::verbose,
             "estimate: fitting the target took " + std::to_string(fit_ms) + " ms (real time)");
    }
    previous_client_target_ = std::exchange(client_target_, target);
    const bool predictive = steering_predictively();
    const bool switched =
        predictive != std::exchange(steered_predictively_, predictive) && pointing_.mode != PointingMode::predictive;
    if (switched) {
        emit(options_.log, LogLevel::verbose,
             predictive ? "pointing: the orbit is trusted: predictive steering while it holds"
                        : "pointing: the orbit is no longer trusted: the client's targets as sent");
        aims_ahead_ = predictive || !aim_ ? AimsAhead{} : AimsAhead{aim_->az, aim_->el};
        aim_.reset();
        leg_overhead_.interrupt();
    }
    if (!predictive) {
        leg_overhead_.interrupt();
        const std::optional<Prediction> estimate = predictor_.predict(now);
        const bool held_before = aims_ahead_.any();
        const AzEl wanted = hold_aims_ahead(aims_ahead_, target, estimate);
        if (switched && aims_ahead_.any()) {
            emit(options_.log, LogLevel::verbose,
                 "pointing: the last aim " + format_degrees(wanted.az) + " " + format_degrees(wanted.el) +
                     " lies ahead of the client's target along the pass: held until the targets reach it");
        } else if (held_before && !switched && !aims_ahead_.any()) {
            emit(options_.log, LogLevel::verbose,
                 "pointing: the aims left ahead are let go: the client's targets as sent");
        }
        return aim(wanted,
                   azimuth_direction_hint(estimate, sky_position(), previous_client_target_, target,
                                          sky_limits_at(target.az).min),
                   now, estimate);
    }
    emit(options_.log, LogLevel::verbose, "predictive: " + predictor_.describe());
    // On a track the aim is kept, and steering moves it only when the satellite is a deadband
    // past it or the estimate jumped: a client that sends every cycle (its limits wider than the
    // dish's, the dish waiting at its floor) would otherwise start a motor every second.
    if (!predictor_.predict(now).value_or(Prediction{}).moving) {
        aim_.reset();
    }
    return steer();
}

// Predictive mode (steering.hpp): hands the controller the next aim, if any.
Status ServiceWorker::steer() {
    if (!steering_predictively()) {
        return Status::ok();
    }
    const auto now = options_.clock.now();
    const std::optional<AzEl> dish = sky_position();
    const std::optional<Prediction> estimate = predictor_.predict(now);
    // The limits where the satellite is (its estimate), else where the client last aimed.
    auto limits_azimuth = [&] {
        if (mount_.identity()) {
            return 0.0;  // any: the limits are the same all round
        }
        return estimate ? estimate->position.az : client_target_ ? client_target_->az : dish.value_or(AzEl{}).az;
    };
    const ElLimits limits = sky_limits_at(limits_azimuth());
    const SteeringInput input{now,
                              predictor_,
                              *profile_,
                              limits.min,
                              limits.max,
                              pointing_,
                              leg_overhead_.overhead_s().value_or(0.0),
                              aim_,
                              client_target_,
                              dish,
                              controller_->learnt_motor()};
    const std::optional<SteeringDecision> decision = next_aim(input);
    if (!decision) {
        return Status::ok();
    }
    // Time this step: what a leg costs beyond its motion (exchange, polling) is measured, not
    // assumed. A re-aim while the dish still runs the last one ends that measurement unmeasured.
    if (!decision->holding && controller_->idle() && aim_) {
        leg_overhead_.start(now, decision->legs, decision->motion_s);
    } else {
        leg_overhead_.interrupt();
    }
    aim_ = decision->aim;
    const double az_rate = decision->az_rate != 0.0 ? decision->az_rate
                           : client_target_
                               ? azimuth_direction_hint(estimate, dish, previous_client_target_, *client_target_,
                                                        sky_limits_at(client_target_->az).min)
                               : 0.0;
    return aim(decision->aim, az_rate, now, estimate);
}

Status ServiceWorker::aim(AzEl sky_target, double sky_az_rate, Clock::time_point now,
                          const std::optional<Prediction>& estimate) {
    std::optional<wrap::PassAhead> ahead = predictor_.pass_ahead(now);
    if (mount_.identity()) {
        return controller_->set_target(sky_target, sky_az_rate, ahead);
    }
    const double el_rate = estimate ? estimate->el_rate : 0.0;
    const double dish_az_rate = dish_azimuth_rate(mount_, sky_target, sky_az_rate, el_rate);
    if (ahead) {
        // The pass rises at the floor the estimator was given (the controller's, as the client
        // clamps at it): its rise and set azimuths, on the dish's axes, bound the travel it needs.
        const double floor = controller_->el_min();
        const double rise = ahead->from_az, set = ahead->from_az + ahead->sweep_deg;
        const double rise_dish = sky_to_dish(mount_, {rise, floor}).az;
        const double set_dish = sky_to_dish(mount_, {set, floor}).az;
        ahead->from_az = normalize_azimuth(rise_dish);
        ahead->sweep_deg += (set_dish - set) - (rise_dish - rise);
    }
    return controller_->set_target(sky_to_dish(mount_, sky_target), dish_az_rate, ahead);
}

AzEl ServiceWorker::in_the_sky(AzEl dish_axes) const {
    if (mount_.identity()) {
        return dish_axes;
    }
    const AzEl sky = dish_to_sky(mount_, dish_axes);
    return {normalize_azimuth(sky.az), sky.el};
}

std::optional<AzEl> ServiceWorker::sky_position() const {
    const std::optional<AzEl> dish = controller_->last_position();
    return dish ? std::optional<AzEl>(in_the_sky(*dish)) : std::nullopt;
}

ServiceWorker::ElLimits ServiceWorker::sky_limits_at(double sky_az) const {
    const double el_min = controller_->el_min(), el_max = controller_->el_max();
    if (mount_.identity()) {
        return {el_min, el_max};
    }
    // The dish's azimuth that looks toward sky_az at that elevation, to first order in the tilt.
    auto sky_el = [&](double dish_el) {
        const double dish_az = sky_to_dish(mount_, {sky_az, std::min(dish_el + mount_.el_index, 90.0)}).az;
        return dish_to_sky(mount_, {dish_az, dish_el}).el;
    };
    return {sky_el(el_min), sky_el(el_max)};
}

void ServiceWorker::forget_the_pass() {
    predictor_.reset();
    aim_.reset();
    aims_ahead_ = {};
    client_target_.reset();
    previous_client_target_.reset();
    leg_overhead_.interrupt();
}

Clock::duration ServiceWorker::next_period(bool entered_recovery) const {
    if (published_.recovering) {
        return entered_recovery ? Clock::duration::zero() : Clock::duration(backoff_);
    }
    const auto now = options_.clock.now();
    const bool steering = steering_predictively() && predictor_.predict(now).value_or(Prediction{}).moving;
    if (controller_->idle() && !steering) {
        const Clock::duration until_poll = last_poll_ + timing_.idle_poll_period - now;
        return std::clamp<Clock::duration>(until_poll, timing_.busy_period, timing_.idle_poll_period);
    }
    return timing_.busy_period;
}

void ServiceWorker::publish(const Status& step, bool talked) {
    if (auto position = controller_->last_position()) {
        published_.position = position;
    }
    published_.moving_axes = controller_->moving_axes();
    published_.dish_idle = controller_->idle();
    published_.homing = controller_->homing();
    published_.unhomed = controller_->unhomed();
    if (talked) {
        published_.last_error = step;
        if (step) {
            published_.last_answer_at = Clock::now();
        }
    }
    published_.description = controller_->describe() + "; " + controller_->describe_wrap() + "; pointing " +
                             std::string(pointing_mode_name(pointing_.mode.value_or(PointingMode::none)));
    if (pointing_.mode != PointingMode::predictive && steering_predictively()) {
        published_.description += ", predictive while the orbit holds";
    }
    if (steering_predictively()) {
        published_.description += " (" + predictor_.describe() + ")";
    }
    if (!mount_.identity()) {
        // The controller's words are the dish's axes; a client reading the target it took (the
        // MCP server, after az_min/az_max) needs it on the sky.
        char text[200];
        std::snprintf(text, sizeof text, "; mount az_index %.2f el_index %.2f tilt_north %.2f tilt_east %.2f",
                      mount_.az_index, mount_.el_index, mount_.tilt_north, mount_.tilt_east);
        published_.description += text;
        if (const std::optional<AzEl> target = controller_->current_target()) {
            const AzEl sky = in_the_sky(*target);
            std::snprintf(text, sizeof text, "; sky target az %.2f el %.2f", sky.az, sky.el);
            published_.description += text;
        }
    }
    mailbox_.publish(published_);
}

}  // namespace birdcage
