// The rotator service's worker and mailbox (rotator_service.hpp). Over 500 lines because the
// callers' side (the public methods), the worker loop and the position model share one state under
// one mutex; the pure decisions are already apart and unit tested: steering (steering.cpp),
// recovery (recovery.cpp), the estimator (pointing.cpp). Separating the mailbox from the worker
// loop is the remaining step of that split.
#include "birdcage/rotator_service.hpp"
#include "birdcage/recovery.hpp"
#include "birdcage/wrap.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace birdcage {
namespace {

// How long a receiver request may wait for the leg in flight: a full G2 azimuth slew (~40 s).
constexpr std::chrono::milliseconds receiver_wait_for_leg{45000};

} // namespace

RotatorService::RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options,
                               ServiceTiming timing, TransportFactory reopen)
    : transport_(std::move(transport)), options_(std::move(options)),
      controller_(options_.detect ? nullptr : std::make_unique<Controller>(*transport_, options_)),
      timing_(timing), reopen_(std::move(reopen)) {}

Status RotatorService::detect() {
    const auto found = detect_variant(*transport_, options_.log, options_.boot_timeout);
    if (!found) {
        return found.status;
    }
    options_.variant = found.value.variant;
    options_.detection_note = found.value.evidence;
    if (found.value.maybe_pro_odu) {
        const double pro_cap = birdcage::profile(VariantId::travler_pro).el_max;
        options_.el_max = std::min(options_.el_max.value_or(pro_cap), pro_cap);
    }
    controller_ = std::make_unique<Controller>(*transport_, options_);
    return Status::ok();
}

RotatorService::~RotatorService() { shutdown(); }

Status RotatorService::start() {
    if (worker_.joinable()) {
        return Status::ok();
    }
    if (!controller_) {
        if (Status st = detect(); !st) {
            return st;
        }
    }
    if (!pointing_.mode) {
        pointing_.mode = controller_->profile().predictive_by_default ? PointingMode::predictive : PointingMode::none;
    }
    if (Status st = controller_->initialize(); !st) {
        return st;
    }
    Result<AzEl> first = controller_->query_position();
    {
        std::lock_guard lock(mutex_);
        publish_locked(*controller_, first.status);
        last_ok_at_ = Clock::now();
        shutdown_requested_ = false;
    }
    // A dish that answers its menus but not a position query is still usable for moves; the error
    // is kept and reported by position() until a poll succeeds.
    worker_ = std::thread([this] { run(); });
    return Status::ok();
}

void RotatorService::shutdown() {
    {
        std::lock_guard lock(mutex_);
        shutdown_requested_ = true;
    }
    wake_.notify_all();
    if (worker_.joinable()) {
        worker_.join();
    }
    {
        std::lock_guard lock(mutex_);
        if (receiver_job_) {
            receiver_job_->result = Status{Errc::not_initialised, "the rotator was closed"};
            receiver_job_->done = true;
            receiver_job_.reset();
        }
    }
    receiver_done_.notify_all();
}

Status RotatorService::run_between_legs(std::function<Status(Controller&)> work, std::chrono::milliseconds timeout) {
    auto job = std::make_shared<ReceiverJob>();
    job->work = std::move(work);
    std::unique_lock lock(mutex_);
    if (!controller_ || !worker_.joinable()) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    if (controller_->profile().receiver_menu.empty()) {
        // Answered here: no need to wait for the dish to learn it has no tuner.
        return {Errc::unsupported, std::string(controller_->profile().display_name) + " has no satellite tuner"};
    }
    if (receiver_job_) {
        return {Errc::busy, "another receiver request is in progress"};
    }
    receiver_job_ = job;
    wake_.notify_all();
    // The leg in flight ends first (a long slew takes tens of seconds); then the job itself.
    if (!receiver_done_.wait_for(lock, timeout, [&] { return job->done; })) {
        if (!job->started) {
            receiver_job_.reset();
            return {Errc::busy, "the dish did not finish its move in time for the receiver request"};
        }
        receiver_done_.wait(lock, [&] { return job->done; });   // the work is bounded by its own timeouts
    }
    return job->result;
}

Result<RssiReading> RotatorService::read_signal(int samples) {
    Result<RssiReading> reading{{}, Status{Errc::protocol, "no reading"}};
    const Status done = run_between_legs(
        [&reading, samples](Controller& controller) {
            reading = birdcage::read_signal(controller, samples);
            return reading.status;
        },
        receiver_wait_for_leg + rssi_timeout(samples));
    if (!done) {
        return {{}, done};
    }
    return reading;
}

Status RotatorService::set_lnb_supply(LnbSupply supply) {
    const Status done =
        run_between_legs([supply](Controller& controller) { return apply_lnb_supply(controller, supply); },
                         receiver_wait_for_leg + rssi_timeout(1));
    if (done) {
        std::lock_guard lock(mutex_);
        lnb_supply_ = supply;
    }
    return done;
}

LnbSupply RotatorService::lnb_supply() const {
    std::lock_guard lock(mutex_);
    return lnb_supply_;
}

Status RotatorService::set_target(AzEl target) {
    if (!std::isfinite(target.az) || !std::isfinite(target.el)) {
        return {Errc::invalid_argument, "target azimuth/elevation must be finite numbers"};
    }
    {
        std::lock_guard lock(mutex_);
        if (!worker_.joinable()) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        if (unhomed_ && !homing_) {
            return {Errc::not_homed, "the dish's axes are not homed (it reports INT_MAX); home them first with "
                                     "reset (rotctl: R 1)"};
        }
        // A stop posted before this target stays requested: the worker takes the stop first
        // (dropping the old legs and the estimator's history), then this target, so `S` then `P`
        // does what `P` says from a clean start however quickly they come.
        posted_target_ = target;
        latest_target_ = target;
        idle_ = false;
        fault_ = Status::ok();   // a new target is the client's answer to a fault (p still reports it once)
    }
    wake_.notify_all();
    return Status::ok();
}

Result<AzEl> RotatorService::position() {
    std::lock_guard lock(mutex_);
    if (recovering_) {
        return {AzEl{}, Status{Errc::timeout, recovery_reason_}};
    }
    if (fault_unreported_) {
        fault_unreported_ = false;
        return {AzEl{}, fault_report_};
    }
    if (unhomed_) {
        return {AzEl{}, Status{Errc::not_homed, "the dish's axes are not homed; reset (R 1) homes them"}};
    }
    if (position_ && Clock::now() - last_ok_at_ > timing_.max_position_age) {
        return {AzEl{}, Status{Errc::timeout, "the dish has not answered for " +
                                                  std::to_string(std::chrono::duration_cast<std::chrono::milliseconds>(
                                                                     Clock::now() - last_ok_at_)
                                                                     .count() /
                                                                 1000) +
                                                  " s (" + last_error_.message + ")"}};
    }
    if (!position_) {
        Status why = last_error_ ? Status{Errc::not_initialised, "no position read from the dish yet"}
                                 : last_error_;
        return {AzEl{}, why};
    }
    return {modelled_position_locked(), Status::ok()};
}

// Between polls the dish is where the move in flight has taken it: the axis runs from its last
// reading to the leg's target over the variant's estimated move time, with a symmetric
// accelerate/brake profile, so `p` tracks a moving dish instead of repeating the last poll.
AzEl RotatorService::modelled_position_locked() const {
    AzEl at = *position_;
    if (!leg_motion_ || !controller_) {
        return at;
    }
    const Controller::LegMotion& leg = *leg_motion_;
    const bool azimuth = leg.axis == Axis::azimuth;
    const double distance = azimuth ? azimuth_difference(leg.from, leg.to) : leg.to - leg.from;
    const double move_s =
        std::chrono::duration<double>(estimated_move_time(controller_->profile(), leg.axis, distance)).count();
    const auto now = controller_now();
    const auto started = std::max(leg.from_at, leg.sent_at);
    const double elapsed = std::chrono::duration<double>(now - started).count();
    if (move_s <= 0.0 || elapsed <= 0.0) {
        return at;
    }
    // From the last reading: a reading taken mid-move leaves the remaining distance to cover.
    const double u = std::clamp(elapsed / move_s, 0.0, 1.0);
    const double travelled = distance * u * u * (3.0 - 2.0 * u);
    if (azimuth) {
        at.az = normalize_azimuth(leg.from + travelled);
    } else {
        at.el = leg.from + travelled;
    }
    return at;
}

Status RotatorService::stop() {
    {
        std::lock_guard lock(mutex_);
        posted_target_.reset();
        latest_target_.reset();
        cancel_requested_ = true;
    }
    wake_.notify_all();
    return Status::ok();
}

Status RotatorService::park() {
    AzEl park_at;
    {
        std::lock_guard lock(mutex_);
        if (!controller_) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        park_at = controller_->park_position();
    }
    return set_target(park_at);
}

Status RotatorService::reset() {
    {
        std::lock_guard lock(mutex_);
        if (!controller_) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        if (controller_->profile().home_commands.empty()) {
            return {Errc::unsupported, std::string(controller_->profile().display_name) +
                                           " has no homing command (it calibrates at power-up only)"};
        }
        if (!worker_.joinable()) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        posted_target_.reset();
        home_requested_ = true;
        homing_ = true;
        idle_ = false;
    }
    wake_.notify_all();
    return Status::ok();
}

bool RotatorService::idle() const {
    std::lock_guard lock(mutex_);
    return idle_;
}

bool RotatorService::homing() const {
    std::lock_guard lock(mutex_);
    return homing_;
}

bool RotatorService::recovering() const {
    std::lock_guard lock(mutex_);
    return recovering_;
}

unsigned RotatorService::recoveries() const {
    std::lock_guard lock(mutex_);
    return recoveries_;
}

Status RotatorService::last_error() const {
    std::lock_guard lock(mutex_);
    if (!fault_ && last_error_) {
        return fault_;
    }
    return last_error_;
}

std::string RotatorService::describe() const {
    std::lock_guard lock(mutex_);
    std::string text = description_;
    if (recovering_) {
        text += "; RECOVERING: " + recovery_reason_;
    }
    if (!fault_) {
        text += "; last fault: " + fault_.message;
    }
    if (recoveries_ > 0) {
        text += "; recovered " + std::to_string(recoveries_) + " time(s)";
    }
    return text;
}

const FirmwareProfile& RotatorService::profile() const {
    return controller_ ? controller_->profile() : probe_profile();
}

void RotatorService::publish_locked(const Controller& controller, const Status& step) {
    if (auto pos = controller.last_position()) {
        position_ = pos;
    }
    leg_motion_ = controller.leg_motion();
    // A target posted while the worker was busy keeps the service non-idle until it is taken.
    idle_ = controller.idle() && !posted_target_ && !home_requested_;
    homing_ = controller.homing() || home_requested_;
    unhomed_ = controller.unhomed();
    last_error_ = step;
    description_ = controller.describe() + "; " + controller.describe_wrap() + "; pointing " +
                   std::string(pointing_mode_name(pointing_.mode.value_or(PointingMode::none)));
    if (pointing_.mode == PointingMode::predictive) {
        description_ += " (" + predictor_.describe() + ")";
    }
}

void RotatorService::enter_recovery_locked(std::string reason) {
    if (!recovering_) {
        emit(options_.log, LogLevel::warning, "recovering: " + reason);
        attempts_ = 0;
        backoff_ = std::chrono::milliseconds{0};
    }
    recovering_ = true;
    recovery_reason_ = std::move(reason);
    idle_ = false;
}

// One bounded recovery attempt: reopen the device if it hung up, then re-initialise the dish
// (boot wait bounded by the slice, search stop, motor menu). Worker thread only.
Status RotatorService::recover_once() {
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
        auto controller = std::make_unique<Controller>(*reopened.value, options_);
        std::lock_guard swap(mutex_);
        controller_ = std::move(controller);
        transport_ = std::move(reopened.value);
        link_down_ = false;
        emit(options_.log, LogLevel::warning, "serial port reopened; re-initialising the dish");
    }
    Status st = controller_->reinitialize(timing_.recovery_boot_slice);
    if (!st) {
        if (st.code == Errc::disconnected || st.code == Errc::io) {
            link_down_ = true;
        }
        return {st.code, "re-initialising the dish (attempt " + std::to_string(attempts_) + "): " + st.message};
    }
    if (!controller_->last_position()) {
        (void)controller_->query_position();
    }
    return Status::ok();
}

Clock::time_point RotatorService::controller_now() const {
    return options_.clock.now();
}

// The azimuth direction a pass is taking, for the controller's cable-wrap choice: the estimated
// rate once two targets are known. Before that, one case is already clear: a client following a
// satellite that is still below or near the dish's lowest elevation moves the dish, waiting there,
// a small step along the satellite's azimuth track, as Gpredict does from the AOS point; the
// direction of that step is the pass's, and knowing it now lets the one unwind a pass may need
// happen while the satellite is still out of reach rather than as it rises into the beam.
double RotatorService::azimuth_direction_hint(AzEl target) const {
    if (const auto motion = predictor_.predict(controller_now()); motion && motion->az_rate != 0.0) {
        return motion->az_rate;
    }
    // The dish waits at the lowest elevation (where Gpredict parks it before AOS) and the target
    // is still low: Gpredict's first target may lie up to one threshold ahead of the satellite.
    const auto dish = controller_->last_position();
    if (!dish || dish->el > controller_->el_min() + 1.0 || target.el > controller_->el_min() + wrap::pass_start_band_deg) {
        return 0.0;
    }
    const double step = azimuth_difference(dish->az, target.az);
    // Degrees: a client's step along the track (Gpredict's default 5 deg threshold, its lead of up
    // to one more threshold, and the satellite's motion since), not a new pointing.
    constexpr double tracking_step_max = 20.0;
    constexpr double tiny_rate = 1e-3;          // a direction, not a speed
    return std::fabs(step) > same_angle_degrees && std::fabs(step) <= tracking_step_max ? std::copysign(tiny_rate, step) : 0.0;
}

Status RotatorService::accept_target(AzEl target) {
    // Every mode feeds the estimator: its azimuth rate tells the controller which way a pass
    // turns, so it can choose a cable-wrap branch with room for the whole pass.
    predictor_.observe(controller_now(), target, controller_->last_position());
    client_target_ = target;
    if (pointing_.mode != PointingMode::predictive) {
        return controller_->set_target(target, azimuth_direction_hint(target));
    }
    emit(options_.log, LogLevel::verbose, "predictive: " + predictor_.describe());
    aim_.reset();
    return steer();
}

// Predictive mode (steering.hpp): hands the controller the next aim, if any. Worker thread only.
Status RotatorService::steer() {
    if (pointing_.mode != PointingMode::predictive) {
        return Status::ok();
    }
    const auto now = controller_now();
    const SteeringInput input{now,
                              predictor_,
                              controller_->profile(),
                              controller_->el_min(),
                              controller_->el_max(),
                              pointing_,
                              measured_overhead_s_.value_or(0.0),
                              aim_,
                              client_target_,
                              controller_->last_position()};
    const std::optional<SteeringDecision> decision = next_aim(input);
    if (!decision) {
        return Status::ok();
    }
    if (!decision->holding && controller_->idle() && aim_) {
        // Time this step: what a leg costs beyond its motion (exchange, polling) is measured, not assumed.
        timed_step_ = TimedStep{now, decision->legs, decision->motion_s};
    }
    aim_ = decision->aim;
    const double az_rate = decision->az_rate != 0.0 ? decision->az_rate : azimuth_direction_hint(decision->aim);
    return controller_->set_target(decision->aim, az_rate);
}

void RotatorService::note_step_finished() {
    if (!timed_step_ || !controller_->idle()) {
        return;
    }
    const TimedStep step = *std::exchange(timed_step_, std::nullopt);
    if (step.legs == 0) {
        return;
    }
    const double busy = std::chrono::duration<double>(controller_now() - step.started).count();
    const double overhead = std::max(0.0, (busy - step.motion_s) / step.legs);
    measured_overhead_s_ = measured_overhead_s_ ? 0.8 * *measured_overhead_s_ + 0.2 * overhead : overhead;
}

void RotatorService::run() {
    auto last_poll = Clock::now();
    std::unique_lock lock(mutex_);
    while (!shutdown_requested_) {
        std::optional<AzEl> target = std::exchange(posted_target_, std::nullopt);
        bool cancel = std::exchange(cancel_requested_, false);
        const bool home = home_requested_;
        const bool recovering = recovering_;
        const std::optional<AzEl> resume = latest_target_;
        const std::shared_ptr<ReceiverJob> job = receiver_job_;
        lock.unlock();

        // Only this thread touches the controller (and through it the transport) after start().
        Status step = Status::ok();
        bool recovered = false;
        bool talked = true;   // false: an idle step that sent nothing (proves nothing about the dish)
        if (recovering) {
            // Targets posted meanwhile are kept in latest_target_ and resumed below.
            step = recover_once();
            if (step) {
                recovered = true;
                consecutive_failures_ = 0;
                emit(options_.log, LogLevel::warning,
                     "recovered after " + std::to_string(attempts_) + " attempt(s)" +
                         (resume ? "; resuming the last target" : ""));
                if (resume) {
                    aim_.reset();   // the moves in flight were lost: steer again from the estimate
                    // A target posted while the worker was stuck in the failing step or recovering
                    // never reached the estimator: take it as new, or the dish would return to
                    // the one before it.
                    const bool unseen = !client_target_ || client_target_->az != resume->az ||
                                        client_target_->el != resume->el;
                    if (unseen) {
                        step = accept_target(*resume);
                    } else {
                        step = pointing_.mode == PointingMode::predictive && predictor_.predict(controller_now())
                                   ? steer()
                                   : controller_->set_target(*resume);
                    }
                }
            }
        } else {
            if (cancel) {
                controller_->cancel_pending();
                predictor_.reset();
                aim_.reset();
                client_target_.reset();
            }
            if (target) {
                step = accept_target(*target);
            }
            if (home) {
                // The home runs inside controller_->service() a short slice per step, so the
                // mailbox keeps being read: `p` answers, `P` and `S` are taken, while it runs.
                predictor_.reset();
                aim_.reset();
                client_target_.reset();
                step = controller_->start_home();
                std::lock_guard done(mutex_);
                home_requested_ = false;
            }
            // A receiver job waits for the leg in flight; legs still queued wait for the job.
            const bool run_job = step && job && !home && !controller_->leg_in_flight();
            if (run_job) {
                {
                    std::lock_guard started(mutex_);
                    job->started = true;
                }
                step = job->work(*controller_);
                {
                    std::lock_guard done(mutex_);
                    job->result = step;
                    job->done = true;
                    receiver_job_.reset();
                }
                receiver_done_.notify_all();
            }
            if (step && !target && !home) {
                step = steer();
            }
            talked = target || home || cancel || run_job || !controller_->idle();
            if (step) {
                step = controller_->service();
            }
            note_step_finished();
            const bool idle_now = controller_->idle();
            if (step && idle_now && Clock::now() - last_poll >= timing_.idle_poll_period) {
                talked = true;
                step = controller_->query_position().status;
                last_poll = Clock::now();
            } else if (!idle_now) {
                // Read the position once more shortly after the last leg ends: the dish may still
                // have been finishing the move when the leg counted as arrived.
                last_poll = Clock::now() - timing_.idle_poll_period + 4 * timing_.busy_period;
            }
        }
        std::string fault = controller_->take_fault();

        // Classify the step (recovery.hpp): what needs recovering, what is only reported.
        std::optional<std::string> recover_because;
        if (!recovering) {
            const RecoveryVerdict verdict = classify_step(
                StepOutcome{step, talked, controller_->needs_reinit(), !fault.empty()}, consecutive_failures_,
                timing_.failures_before_recovery);
            consecutive_failures_ = verdict.consecutive_failures;
            if (verdict.action == RecoveryAction::reopen) {
                link_down_ = true;
            }
            if (verdict.action != RecoveryAction::none) {
                recover_because = verdict.reason;
            }
        } else if (!step) {
            if (step.code == Errc::disconnected) {
                link_down_ = true;
            }
            backoff_ = std::clamp(backoff_ * 2, timing_.recovery_backoff_min, timing_.recovery_backoff_max);
        }

        lock.lock();
        if (!fault.empty()) {
            fault_ = Status{Errc::protocol, fault};   // "dish reported: AZ MOTOR STALLED"
            fault_report_ = fault_;
            fault_unreported_ = true;
        }
        if (step && talked) {
            last_ok_at_ = Clock::now();
        }
        if (recovered) {
            recovering_ = false;
            lnb_supply_ = lnb_boot_default;   // a reboot restores the boot default
            ++recoveries_;
        } else if (recovering && !step) {
            recovery_reason_ = step.message;
        }
        if (recover_because) {
            enter_recovery_locked(*recover_because);
        }
        publish_locked(*controller_, talked ? step : last_error_);
        if (recovering_) {
            idle_ = false;
        }
        if (shutdown_requested_) {
            break;
        }
        std::chrono::milliseconds period = timing_.busy_period;
        const bool steering = pointing_.mode == PointingMode::predictive && !recovering_ &&
                              predictor_.predict(controller_now()).value_or(Prediction{}).moving;
        if (controller_->idle() && !steering) {
            const auto until_poll =
                std::chrono::duration_cast<std::chrono::milliseconds>(last_poll + timing_.idle_poll_period - Clock::now());
            period = std::clamp(until_poll, timing_.busy_period, timing_.idle_poll_period);
        }
        if (recovering_) {
            period = recover_because ? std::chrono::milliseconds{0} : backoff_;
        }
        wake_.wait_for(lock, period, [this] {
            return shutdown_requested_ ||
                   ((posted_target_.has_value() || cancel_requested_ || home_requested_ ||
                     (receiver_job_ && !receiver_job_->started)) &&
                    !recovering_);
        });
    }
}

} // namespace birdcage
