// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The rotator service's worker: the one owner of the Controller (and through it the serial line)
// once the service has started. Each step takes the mail (service_mailbox.hpp), acts on it in the
// order the client meant (stop, target, home, receiver job), steers (steering.hpp), services the
// move in flight, classifies the outcome (recovery.hpp) and publishes a snapshot. step() is the
// whole of one pass, so tests drive it by hand with a deterministic schedule; run() loops it on
// the service's thread.
#pragma once

#include "base/errors.hpp"
#include "console/transport.hpp"
#include "dish/controller.hpp"
#include "service/service_mailbox.hpp"
#include "tracking/mount_model.hpp"
#include "tracking/pointing.hpp"
#include "tracking/steering.hpp"

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace birdcage {

// The worker's periods are dish time (clock.hpp): against an emulator run k times faster they
// shrink k times through ControllerOptions::clock, and the worker converts them only where it
// sleeps. The link's timeouts (boot slice, position age) are real time, like every I/O deadline:
// the serial line does not run faster with the dish.
struct ServiceTiming {
    // How often the worker services the controller while a leg is in flight.
    std::chrono::milliseconds busy_period{50};
    // How often the position is refreshed while the dish is idle.
    std::chrono::milliseconds idle_poll_period{1000};
    // Once the last leg ends, the position is read again after this many busy periods: the dish
    // may still have been finishing the move when the leg counted as arrived.
    int settle_polls_after_move = 4;
    // Consecutive failed steps (timeouts, unusable replies) after which the console is considered
    // out of sync and the worker re-synchronises and re-initialises it.
    int failures_before_recovery = 2;
    // Backoff between recovery attempts (reopen, re-initialise), doubling from min up to max.
    std::chrono::milliseconds recovery_backoff_min{100};
    std::chrono::milliseconds recovery_backoff_max{2000};
    // Longest single wait for a booting dish inside one recovery attempt (the attempts repeat
    // until the dish answers; the slice keeps stop/shutdown responsive).
    std::chrono::milliseconds recovery_boot_slice{5000};
    // After this long without an answer (real time) the dish counts as not answering even before
    // the worker has started to recover it: position() gives the last reading as read, without
    // running the move in flight on (position_model.hpp), and the rotator reports itself busy.
    std::chrono::milliseconds max_position_age{5000};
};

// Opens the device again after a hang-up (the glue opens the same path with FdTransport::open).
using TransportFactory = std::function<Result<std::unique_ptr<Transport>>()>;

class ServiceWorker {
public:
    ServiceWorker(ServiceMailbox& mailbox, std::unique_ptr<Transport> transport, ControllerOptions options,
                  ServiceTiming timing, TransportFactory reopen);

    // Before start(): how targets become moves (unset mode: the variant's default).
    void set_pointing(PointingOptions pointing);
    // Before start(): how the dish's axes sit against the sky (docs/sky.md §1). The client's
    // targets, the estimator and steering are in the sky; the Controller (limits, cable wrap,
    // console) in the dish's axes; aim() and sky_position() are the one seam between them.
    void set_mount(MountModel mount) { mount_ = mount; }
    // Where the beam points with the dish's axes at `dish_axes`, as the client reads it (azimuth
    // in [0, 360)).
    AzEl in_the_sky(AzEl dish_axes) const;

    // Before the worker runs, on the caller's thread: identifies the variant if asked, initialises
    // the dish (boot wait, search stop, motor menu), reads the position once and publishes it.
    // Bounded by ControllerOptions::boot_timeout: a console still silent then fails the start
    // without side effects on the mailbox; one heard booting (a known variant) is left to the
    // worker, which initialises it as it recovers a rebooted dish (initialising in the snapshot).
    Status start();
    // One pass over the mail and the dish. Returns how long to wait (dish time) before the next
    // pass unless mail arrives.
    Clock::duration step();
    // step() until the mailbox closes; the waits are converted to real time here.
    void run();

    const FirmwareProfile& profile() const { return *profile_; }
    // What was learnt about the dish and the client, for tests and diagnostics: it survives a
    // reboot of the dish and an unplugged adapter.
    std::optional<double> learnt_step_seconds(Axis axis) const {
        return controller_ ? controller_->learnt_step_seconds(axis) : std::nullopt;
    }
    std::optional<PointingMode> pointing_mode() const { return pointing_.mode; }
    const TargetPredictor& predictor() const { return predictor_; }
    const DishClock& clock() const { return options_.clock; }

private:
    Status detect();
    void read_lnb_supply_at_open();
    struct Outcome {
        Status status = Status::ok();
        bool talked = false;  // false: an idle step that sent nothing (proves nothing about the dish)
    };
    Outcome work_on(const ServiceMail& mail);
    Outcome recover(const ServiceMail& mail);
    void begin_recovery(const std::string& reason);
    Status recover_once();
    Status read_position_afresh();
    Status resume(AzEl target);
    // `reported`: the position the client last read back (ServiceMail), if known.
    Status accept_target(AzEl target, Clock::time_point sent_at, std::optional<AzEl> reported = std::nullopt);
    Status steer();
    // The seam: a sky target (with its sky azimuth rate, for the cable-wrap branch) handed to the
    // controller in the dish's axes, with the pass ahead likewise; and the dish's last reading in
    // the sky.
    Status aim(AzEl sky_target, double sky_az_rate, Clock::time_point now, const std::optional<Prediction>& estimate);
    std::optional<AzEl> sky_position() const;
    // The controller's elevation limits (dish axes) as sky elevations near sky azimuth `sky_az`:
    // a tilted base reaches lower on one side than on the other.
    struct ElLimits {
        double min, max;
    };
    ElLimits sky_limits_at(double sky_az) const;
    void forget_the_pass();
    Clock::duration next_period(bool entered_recovery) const;
    void publish(const Status& step, bool talked);

    ServiceMailbox& mailbox_;
    std::unique_ptr<Transport> transport_;
    ControllerOptions options_;
    std::unique_ptr<Controller> controller_;  // built at start() once the variant is known
    const FirmwareProfile* profile_;
    ServiceTiming timing_;
    TransportFactory reopen_;
    PointingOptions pointing_;
    MountModel mount_;
    // The pointing mode was not set: the variant's default is a first guess, and the dish's own
    // timing of a small step decides (choose_mode_from_dish()).
    bool mode_from_dish_ = false;
    void choose_mode_from_dish();
    bool steering_predictively() const;
    bool steered_predictively_ = false;  // what the last target was steered by (to log a switch)

    // Steering: the estimator and what was last handed to the controller.
    TargetPredictor predictor_;
    std::optional<AzEl> aim_;
    AimsAhead aims_ahead_;                        // held after predictive steering handed back to the client's targets
    std::optional<AzEl> client_target_;           // the last target the client sent, as sent
    std::optional<AzEl> previous_client_target_;  // the one before it (the client's last step)
    LegOverheadMeter leg_overhead_;

    // Polling and recovery.
    Clock::time_point last_poll_{};
    bool link_down_ = false;  // the transport hung up; reopen before anything else
    int consecutive_failures_ = 0;
    std::chrono::milliseconds backoff_{0};
    unsigned attempts_ = 0;
    Clock::time_point recovery_started_{};  // dish clock: a position read after it is fresh
    bool reinitialised_ = false;            // this recovery has re-initialised the dish

    ServiceSnapshot published_;  // the worker's own copy of what it last published
};

}  // namespace birdcage
