// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The only state the rotator service's two sides share: what callers post (targets, stop, home,
// receiver jobs, shutdown) and the snapshot the worker publishes (position, motion, errors,
// recovery). One mutex, held only to copy mail in or a snapshot out; nobody talks to the dish
// under it, so `p`, `P` and `S` never wait for the dish (rotctld runs every client's command under
// one global lock: docs/tracking.md §1.3).
#pragma once

#include "base/azel.hpp"
#include "base/errors.hpp"
#include "base/plain_types.hpp"

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace birdcage {

class Controller;

// Console work that must run between legs (the receiver: receiver.hpp), and its result.
struct ServiceJob {
    std::function<Status(Controller&)> work;
    Status result;
    bool started = false;
    bool done = false;
};

// What the worker takes from the mailbox at one step.
struct ServiceMail {
    bool stop = false;                     // a stop posted since the last step; acted on before `target`
    std::optional<AzEl> target;            // the newest target posted since the last step (sky)
    Clock::time_point target_posted_at{};  // when it was posted (dish time)
    // The position `p` last answered before the target was posted: what the client compared the
    // satellite with when it decided to send (a tracking client sends when the dish it read back is
    // off). None: nothing asked yet.
    std::optional<AzEl> reported_before_target;
    // Every position `p` answered since the last step, oldest first, with when (dish time): which
    // one a client compared the satellite with depends on its I/O timing (docs/tracking.md §6).
    struct Answered {
        Clock::time_point at{};
        AzEl position;
    };
    std::vector<Answered> answered;
    bool home = false;                  // a home requested and not yet started
    std::optional<AzEl> latest_target;  // the client's last target (resumed after a recovery)
    std::shared_ptr<ServiceJob> job;    // a receiver job waiting for the dish, if any
};

// The worker's view of the dish, as last published.
struct ServiceSnapshot {
    std::optional<AzEl> position;  // the last position read (or known) from the dish, in its axes
    MovingAxes moving_axes;        // the legs that may be moving, for the position model
    bool dish_idle = true;         // the controller has nothing in flight or queued
    bool homing = false;           // the firmware's home is running
    bool unhomed = false;          // the dish reports its axes unhomed
    Status last_error;             // the last step that talked to the dish
    std::string description;
    // The worker cannot ask the dish (rebooting, re-initialising, adapter unplugged, out of sync):
    // `position` stays the last reading until the recovery has read a fresh one.
    bool recovering = false;
    // The recovery is the dish's first initialisation: it was still booting when the service
    // started (ServiceWorker::start()), and nothing has been read from it yet.
    bool initialising = false;
    std::string recovery_reason;
    Clock::time_point recovering_since{};  // steady (real) time, like last_answer_at
    unsigned recoveries = 0;
    // The last step that talked and succeeded. Steady (real) time: how long the line has been
    // silent is a matter of the serial link, like every I/O deadline (clock.hpp).
    Clock::time_point last_answer_at{};
};

// What callers see: the snapshot plus the mailbox's own view of mail not yet taken.
struct ServiceView {
    ServiceSnapshot dish;
    bool idle = true;     // no motion, nothing queued, nothing posted and not yet taken
    bool homing = false;  // homing, or a home requested and not yet started
    Status fault;         // the last motor fault, until the next target
    // Read from the dish at open, set since, or the boot default after a reboot; empty: unknown
    // (the read failed and nothing was set), never assumed.
    std::optional<LnbSupply> lnb_supply;
};

class ServiceMailbox {
public:
    // --- callers (any thread) ---
    // Mail is accepted between open() (the worker is running) and close().
    void open();
    bool is_open() const;
    // Posts the newest target; replaces one not yet taken. A stop posted before it stays posted:
    // the worker takes the stop first, so `S` then `P` does what `P` says however quickly they come.
    // `posted_at` (dish time) is when the client sent it: the estimator dates the target by it,
    // not by when the worker got to it, so the worker's wake-up latency never reads as lag.
    // A position answered to a caller (`p`) at `at` (dish time), remembered for the next target
    // (ServiceMail).
    void note_reported(AzEl position, Clock::time_point at);
    Status post_target(AzEl target, Clock::time_point posted_at);
    // Drops any target not yet taken and asks the worker to drop the legs not yet sent.
    void post_stop();
    Status post_home();
    // Runs `work` on the worker's thread between legs and waits for its result. `wait_for_leg`
    // bounds the wait for the dish to become free; the work itself is bounded by its own timeouts.
    Status run_job(std::function<Status(Controller&)> work, std::chrono::milliseconds wait_for_leg);
    ServiceView view() const;
    // A motor fault is reported once by the next position read (then kept in view().fault).
    std::optional<Status> take_fault_report();
    void set_lnb_supply(LnbSupply supply);
    // Stops accepting mail, wakes the worker and fails a job still waiting with `why`.
    void close(const Status& why);

    // --- the worker ---
    ServiceMail take();
    void home_started();
    // False when the caller has given up on `job` meanwhile (it must not run: its caller is gone).
    bool job_started(const std::shared_ptr<ServiceJob>& job);
    void job_finished(ServiceJob& job, const Status& result);
    void publish(const ServiceSnapshot& snapshot);
    void report_fault(const Status& fault);
    // A reboot restored the dish's boot defaults.
    void dish_rebooted();
    // Sleeps up to `real_period`, or until mail the worker must act on arrives (none while it
    // recovers: the mail waits for a dish that answers). False once closed.
    bool wait(Clock::duration real_period, bool recovering);

private:
    bool has_urgent_mail_locked() const;

    mutable std::mutex mutex_;
    std::condition_variable wake_worker_;
    std::condition_variable job_done_;
    bool open_ = false;
    // Inbox.
    std::optional<AzEl> posted_target_;
    Clock::time_point posted_at_{};
    std::optional<AzEl> reported_, reported_before_target_;
    std::vector<ServiceMail::Answered> answered_;
    bool stop_posted_ = false;
    bool home_posted_ = false;
    std::optional<AzEl> latest_target_;
    std::shared_ptr<ServiceJob> job_;  // one at a time; rotctld serialises its clients anyway
    // Outbox.
    ServiceSnapshot snapshot_;
    Status fault_;
    std::optional<Status> fault_unreported_;
    std::optional<LnbSupply> lnb_supply_;
};

}  // namespace birdcage
