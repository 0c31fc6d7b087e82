// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "service/service_mailbox.hpp"

#include <utility>

namespace birdcage {

void ServiceMailbox::open() {
    std::lock_guard lock(mutex_);
    open_ = true;
}

bool ServiceMailbox::is_open() const {
    std::lock_guard lock(mutex_);
    return open_;
}

void ServiceMailbox::note_reported(AzEl position, Clock::time_point at) {
    // Bounded for a worker that is not taking mail (a recovery): the newest positions are the ones
    // a target may have been compared with.
    constexpr std::size_t answered_kept = 32;
    std::lock_guard lock(mutex_);
    reported_ = position;
    if (answered_.size() >= answered_kept) {
        answered_.erase(answered_.begin());
    }
    answered_.push_back({at, position});
}

Status ServiceMailbox::post_target(AzEl target, Clock::time_point posted_at) {
    {
        std::lock_guard lock(mutex_);
        if (!open_) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        if (snapshot_.unhomed && !snapshot_.homing && !home_posted_) {
            return {Errc::not_homed,
                    "the dish's axes are not homed (it reports INT_MAX); home them first with "
                    "reset (rotctl: R 1)"};
        }
        posted_target_ = target;
        posted_at_ = posted_at;
        reported_before_target_ = reported_;
        latest_target_ = target;
        fault_ = Status::ok();  // a new target is the client's answer to a fault (p still reports it once)
    }
    wake_worker_.notify_all();
    return Status::ok();
}

void ServiceMailbox::post_stop() {
    {
        std::lock_guard lock(mutex_);
        posted_target_.reset();
        latest_target_.reset();
        stop_posted_ = true;
    }
    wake_worker_.notify_all();
}

Status ServiceMailbox::post_home() {
    {
        std::lock_guard lock(mutex_);
        if (!open_) {
            return {Errc::not_initialised, "rotator is not open"};
        }
        // A home replaces the pending target: where the dish goes next is the home position.
        posted_target_.reset();
        home_posted_ = true;
    }
    wake_worker_.notify_all();
    return Status::ok();
}

Status ServiceMailbox::run_job(std::function<Status(Controller&)> work, std::chrono::milliseconds wait_for_leg) {
    auto job = std::make_shared<ServiceJob>();
    job->work = std::move(work);
    std::unique_lock lock(mutex_);
    if (!open_) {
        return {Errc::not_initialised, "rotator is not open"};
    }
    if (job_) {
        return {Errc::busy, "another receiver request is in progress"};
    }
    job_ = job;
    wake_worker_.notify_all();
    if (!job_done_.wait_for(lock, wait_for_leg, [&] { return job->done; })) {
        if (!job->started) {
            job_.reset();
            return {Errc::busy, "the dish did not finish its move in time for the receiver request"};
        }
        job_done_.wait(lock, [&] { return job->done; });
    }
    return job->result;
}

ServiceView ServiceMailbox::view() const {
    std::lock_guard lock(mutex_);
    ServiceView view;
    view.dish = snapshot_;
    view.idle = snapshot_.dish_idle && !posted_target_ && !home_posted_ && !snapshot_.recovering;
    view.homing = snapshot_.homing || home_posted_;
    view.fault = fault_;
    view.lnb_supply = lnb_supply_;
    return view;
}

std::optional<Status> ServiceMailbox::take_fault_report() {
    std::lock_guard lock(mutex_);
    return std::exchange(fault_unreported_, std::nullopt);
}

void ServiceMailbox::set_lnb_supply(LnbSupply supply) {
    std::lock_guard lock(mutex_);
    lnb_supply_ = supply;
}

void ServiceMailbox::close(const Status& why) {
    {
        std::lock_guard lock(mutex_);
        open_ = false;
        if (job_) {
            job_->result = why;
            job_->done = true;
            job_.reset();
        }
    }
    wake_worker_.notify_all();
    job_done_.notify_all();
}

ServiceMail ServiceMailbox::take() {
    std::lock_guard lock(mutex_);
    ServiceMail mail;
    mail.stop = std::exchange(stop_posted_, false);
    mail.target = std::exchange(posted_target_, std::nullopt);
    mail.target_posted_at = posted_at_;
    mail.reported_before_target = reported_before_target_;
    mail.answered = std::exchange(answered_, {});
    mail.home = home_posted_;
    mail.latest_target = latest_target_;
    mail.job = job_;
    if (mail.target || mail.home) {
        // Until the worker publishes what the controller made of it, the dish counts as busy:
        // `s` must not read idle between the take and the first publish.
        snapshot_.dish_idle = false;
    }
    return mail;
}

void ServiceMailbox::home_started() {
    std::lock_guard lock(mutex_);
    home_posted_ = false;
    snapshot_.homing = true;  // until the worker publishes the controller's own view
}

bool ServiceMailbox::job_started(const std::shared_ptr<ServiceJob>& job) {
    std::lock_guard lock(mutex_);
    if (job_ != job) {
        return false;
    }
    job->started = true;
    return true;
}

void ServiceMailbox::job_finished(ServiceJob& job, const Status& result) {
    {
        std::lock_guard lock(mutex_);
        job.result = result;
        job.done = true;
        if (job_.get() == &job) {
            job_.reset();
        }
    }
    job_done_.notify_all();
}

void ServiceMailbox::publish(const ServiceSnapshot& snapshot) {
    std::lock_guard lock(mutex_);
    snapshot_ = snapshot;
}

void ServiceMailbox::report_fault(const Status& fault) {
    std::lock_guard lock(mutex_);
    fault_ = fault;
    fault_unreported_ = fault;
}

void ServiceMailbox::dish_rebooted() {
    std::lock_guard lock(mutex_);
    lnb_supply_ = lnb_boot_default;
}

bool ServiceMailbox::has_urgent_mail_locked() const {
    return posted_target_.has_value() || stop_posted_ || home_posted_ || (job_ && !job_->started);
}

bool ServiceMailbox::wait(Clock::duration real_period, bool recovering) {
    std::unique_lock lock(mutex_);
    wake_worker_.wait_for(lock, real_period, [&] { return !open_ || (!recovering && has_urgent_mail_locked()); });
    return open_;
}

}  // namespace birdcage
