// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "service/rotator_service.hpp"

#include "tracking/position_model.hpp"

#include <chrono>
#include <cmath>
#include <exception>
#include <string>
#include <utility>

namespace birdcage {
namespace {

// How long a receiver request may wait for the leg in flight before it is refused as busy. rotctld
// answers one client's command at a time, so the wait holds every client's `p`: a tracking leg
// ends within it, a slew (a G2's full turn takes ~40 s) does not, and the client asks again.
constexpr std::chrono::milliseconds receiver_wait_for_leg{3000};

}  // namespace

RotatorService::RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options, ServiceTiming timing,
                               TransportFactory reopen)
    : timing_(timing), worker_(mailbox_, std::move(transport), std::move(options), timing, std::move(reopen)) {}

RotatorService::~RotatorService() {
    shutdown();
}

void RotatorService::set_pointing(PointingOptions pointing) {
    worker_.set_pointing(std::move(pointing));
}

void RotatorService::set_mount(MountModel mount) {
    worker_.set_mount(mount);
}

Status RotatorService::start() {
    if (thread_.joinable()) {
        return Status::ok();
    }
    if (Status st = worker_.start(); !st) {
        return st;
    }
    mailbox_.open();
    thread_ = std::thread([this] {
        // Nothing may leave the thread (std::terminate would end the host process): the service
        // closes, reports the dish as not answering and says why, and refuses new mail.
        const auto stopped = [this](const std::string& why) {
            ServiceSnapshot dish = mailbox_.view().dish;
            dish.recovering = true;
            dish.recovery_reason = why;
            mailbox_.publish(dish);
            mailbox_.close(Status{Errc::io, why});
        };
        try {
            worker_.run();
        } catch (const std::exception& e) {
            stopped(std::string("the service stopped on an internal error: ") + e.what());
        } catch (...) {
            stopped("the service stopped on an internal error");
        }
    });
    return Status::ok();
}

void RotatorService::shutdown() {
    mailbox_.close(Status{Errc::not_initialised, "the rotator was closed"});
    if (thread_.joinable()) {
        thread_.join();
    }
}

Status RotatorService::set_target(AzEl target) {
    if (!std::isfinite(target.az) || !std::isfinite(target.el)) {
        return {Errc::invalid_argument, "target azimuth/elevation must be finite numbers"};
    }
    return mailbox_.post_target(target, worker_.clock().now());
}

namespace {

long whole_seconds_since(Clock::time_point then) {
    return static_cast<long>(std::chrono::duration_cast<std::chrono::seconds>(Clock::now() - then).count());
}

}  // namespace

bool RotatorService::not_answering(const ServiceSnapshot& dish) const {
    return dish.recovering || Clock::now() - dish.last_answer_at > timing_.max_position_age;
}

Result<AzEl> RotatorService::position() {
    const ServiceView view = mailbox_.view();
    const ServiceSnapshot& dish = view.dish;
    // While the dish cannot be asked, the last reading is the truth as far as anyone knows, and an
    // error would not be: Gpredict gives up for good after a few erroring polls, and the pass is
    // lost although the dish comes back. get_status() and describe() tell that it is not answering.
    // The move in flight is not run on: the dish may not be making it (a reboot stops it dead).
    if (not_answering(dish) && dish.position) {
        const AzEl last = worker_.in_the_sky(*dish.position);
        mailbox_.note_reported(last, worker_.clock().now());
        return {last, Status::ok()};
    }
    if (dish.recovering) {
        return {AzEl{}, Status{Errc::timeout, "no position read from the dish yet; " + dish.recovery_reason}};
    }
    if (std::optional<Status> fault = mailbox_.take_fault_report()) {
        return {AzEl{}, *fault};
    }
    if (dish.unhomed) {
        return {AzEl{}, Status{Errc::not_homed, "the dish's axes are not homed; reset (R 1) homes them"}};
    }
    if (!dish.position) {
        // A console that answers without reporting its position at rest has none until a move.
        const Status none = worker_.profile().position_query.empty()
                                ? Status{Errc::unsupported,
                                         "this dish cannot report its position at rest and none has been commanded yet"}
                                : Status{Errc::not_initialised, "no position read from the dish yet"};
        return {AzEl{}, dish.last_error ? none : dish.last_error};
    }
    // One instant for the position modelled and the time it is noted at (the predictor compares
    // the satellite with it at that time).
    const Clock::time_point now = worker_.clock().now();
    // The model runs the legs in flight in the dish's axes, where they move.
    const AzEl reported =
        worker_.in_the_sky(modelled_position(worker_.profile(), *dish.position, dish.moving_axes, now));
    mailbox_.note_reported(reported, now);
    return {reported, Status::ok()};
}

Status RotatorService::stop() {
    mailbox_.post_stop();
    return Status::ok();
}

Status RotatorService::park() {
    if (!mailbox_.is_open()) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    // The park position is a pose of the mechanism: the target whose dish axes are exactly it.
    const FirmwareProfile& dish = worker_.profile();
    return set_target(worker_.in_the_sky(AzEl{dish.park_az, dish.park_el}));
}

Status RotatorService::reset() {
    if (!mailbox_.is_open()) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    if (worker_.profile().home_commands.empty()) {
        return {Errc::unsupported, std::string(worker_.profile().display_name) +
                                       " has no homing command (it calibrates at power-up only)"};
    }
    return mailbox_.post_home();
}

Status RotatorService::unsupported_without_tuner() const {
    // Answered here: no need to wait for the dish to learn it has no tuner.
    return {Errc::unsupported, std::string(worker_.profile().display_name) + " has no satellite tuner"};
}

Result<RssiReading> RotatorService::read_signal(int samples) {
    if (mailbox_.is_open() && worker_.profile().receiver_menu.empty()) {
        return {{}, unsupported_without_tuner()};
    }
    Result<RssiReading> reading{{}, Status{Errc::protocol, "no reading"}};
    const Status done = mailbox_.run_job(
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
    if (mailbox_.is_open() && worker_.profile().receiver_menu.empty()) {
        return unsupported_without_tuner();
    }
    const Status done =
        mailbox_.run_job([supply](Controller& controller) { return apply_lnb_supply(controller, supply); },
                         receiver_wait_for_leg + rssi_timeout(1));
    if (done) {
        mailbox_.set_lnb_supply(supply);
    }
    return done;
}

std::optional<LnbSupply> RotatorService::lnb_supply() const {
    return mailbox_.view().lnb_supply;
}

bool RotatorService::idle() const {
    return mailbox_.view().idle;
}

bool RotatorService::homing() const {
    return mailbox_.view().homing;
}

bool RotatorService::recovering() const {
    return mailbox_.view().dish.recovering;
}

bool RotatorService::initialising() const {
    return mailbox_.view().dish.initialising;
}

bool RotatorService::answering() const {
    return !not_answering(mailbox_.view().dish);
}

unsigned RotatorService::recoveries() const {
    return mailbox_.view().dish.recoveries;
}

Status RotatorService::last_error() const {
    const ServiceView view = mailbox_.view();
    if (!view.fault && view.dish.last_error) {
        return view.fault;
    }
    return view.dish.last_error;
}

std::string RotatorService::describe() const {
    const ServiceView view = mailbox_.view();
    const ServiceSnapshot& dish = view.dish;
    std::string text = dish.description;
    if (dish.recovering) {
        text += std::string(dish.initialising ? "; INITIALISING for " : "; RECOVERING for ") +
                std::to_string(whole_seconds_since(dish.recovering_since)) + " s: " + dish.recovery_reason;
    } else if (not_answering(dish)) {
        text += "; NOT ANSWERING for " + std::to_string(whole_seconds_since(dish.last_answer_at)) + " s (" +
                dish.last_error.message + ")";
    }
    if (not_answering(dish) && dish.position) {
        text += "; p gives the last position read, " + std::to_string(whole_seconds_since(dish.last_answer_at)) +
                " s ago; P is kept for when the dish answers";
    }
    if (!view.fault) {
        text += "; last fault: " + view.fault.message;
    }
    if (view.dish.recoveries > 0) {
        text += "; recovered " + std::to_string(view.dish.recoveries) + " time(s)";
    }
    return text;
}

const FirmwareProfile& RotatorService::profile() const {
    return worker_.profile();
}

}  // namespace birdcage
