#include "birdcage/rotator_service.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace birdcage {

RotatorService::RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options,
                               ServiceTiming timing)
    : transport_(std::move(transport)), options_(std::move(options)),
      controller_(options_.detect ? nullptr : std::make_unique<Controller>(*transport_, options_)),
      timing_(timing) {}

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
    if (Status st = controller_->initialize(); !st) {
        return st;
    }
    Result<AzEl> first = controller_->query_position();
    {
        std::lock_guard lock(mutex_);
        publish_locked(*controller_, first.status);
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
        if (unhomed_ && !home_requested_) {
            return {Errc::not_homed, "the dish's axes are not homed (it reports INT_MAX); home them first with "
                                     "reset (rotctl: R 1)"};
        }
        posted_target_ = target;
        cancel_requested_ = false;
        idle_ = false;
    }
    wake_.notify_all();
    return Status::ok();
}

Result<AzEl> RotatorService::position() const {
    std::lock_guard lock(mutex_);
    if (unhomed_) {
        return {AzEl{}, Status{Errc::not_homed, "the dish's axes are not homed; reset (R 1) homes them"}};
    }
    if (!position_) {
        Status why = last_error_ ? Status{Errc::not_initialised, "no position read from the dish yet"}
                                 : last_error_;
        return {AzEl{}, why};
    }
    return {*position_, Status::ok()};
}

Status RotatorService::stop() {
    {
        std::lock_guard lock(mutex_);
        posted_target_.reset();
        cancel_requested_ = true;
    }
    wake_.notify_all();
    return Status::ok();
}

Status RotatorService::park() {
    if (!controller_) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    return set_target(controller_->park_position());
}

Status RotatorService::reset() {
    if (!controller_) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    if (controller_->profile().home_commands.empty()) {
        return {Errc::unsupported, std::string(controller_->profile().display_name) +
                                       " has no homing command (it calibrates at power-up only)"};
    }
    {
        std::lock_guard lock(mutex_);
        if (!worker_.joinable()) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        posted_target_.reset();
        home_requested_ = true;
        idle_ = false;
    }
    wake_.notify_all();
    return Status::ok();
}

bool RotatorService::idle() const {
    std::lock_guard lock(mutex_);
    return idle_;
}

Status RotatorService::last_error() const {
    std::lock_guard lock(mutex_);
    return last_error_;
}

std::string RotatorService::describe() const {
    std::lock_guard lock(mutex_);
    return description_;
}

const FirmwareProfile& RotatorService::profile() const {
    return controller_ ? controller_->profile() : probe_profile();
}

void RotatorService::publish_locked(const Controller& controller, const Status& step) {
    if (auto pos = controller.last_position()) {
        position_ = pos;
    }
    // A target posted while the worker was busy keeps the service non-idle until it is taken.
    idle_ = controller.idle() && !posted_target_ && !home_requested_;
    unhomed_ = controller.unhomed();
    last_error_ = step;
    description_ = controller.describe();
}

void RotatorService::run() {
    auto last_poll = Clock::now();
    std::unique_lock lock(mutex_);
    while (!shutdown_requested_) {
        std::optional<AzEl> target = std::exchange(posted_target_, std::nullopt);
        bool cancel = std::exchange(cancel_requested_, false);
        const bool home = home_requested_;
        lock.unlock();

        // Only this thread touches the controller (and through it the transport) after start().
        Status step = Status::ok();
        if (cancel) {
            controller_->cancel_pending();
        }
        if (target) {
            step = controller_->set_target(*target);
        }
        if (home) {
            step = controller_->home();
            std::lock_guard done(mutex_);
            home_requested_ = false;
        }
        if (step) {
            step = controller_->service();
        }
        const bool idle_now = controller_->idle();
        if (step && idle_now && Clock::now() - last_poll >= timing_.idle_poll_period) {
            step = controller_->query_position().status;
            last_poll = Clock::now();
        } else if (!idle_now) {
            last_poll = Clock::now();
        }

        lock.lock();
        publish_locked(*controller_, step);
        if (shutdown_requested_) {
            break;
        }
        const auto period = idle_now ? timing_.idle_poll_period : timing_.busy_period;
        wake_.wait_for(lock, period, [this] {
            return shutdown_requested_ || posted_target_.has_value() || cancel_requested_ || home_requested_;
        });
    }
}

} // namespace birdcage
