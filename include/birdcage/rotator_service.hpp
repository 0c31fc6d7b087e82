// A Controller driven by its own worker thread, so that callers never wait for the dish.
//
// Why a thread: rotctld runs every client's command under one global mutex, and the dish moves one
// axis at a time, so a set_position that waited for motion would stall every client's `p` for
// seconds (docs/tracking.md §1.3). Here set_target() only posts the latest target, position()
// answers from the last position the worker read, and the worker sends each axis leg when the
// dish is free, polling the position while it moves.
#pragma once

#include "birdcage/controller.hpp"
#include "birdcage/detect.hpp"
#include "birdcage/errors.hpp"
#include "birdcage/pointing.hpp"
#include "birdcage/receiver.hpp"
#include "birdcage/steering.hpp"
#include "birdcage/transport.hpp"

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace birdcage {

struct ServiceTiming {
    // How often the worker services the controller while a leg is in flight.
    std::chrono::milliseconds busy_period{50};
    // How often the position is refreshed while the dish is idle.
    std::chrono::milliseconds idle_poll_period{1000};
    // Consecutive failed steps (timeouts, unusable replies) after which the console is considered
    // out of sync and the worker re-synchronises and re-initialises it.
    int failures_before_recovery = 2;
    // Backoff between recovery attempts (reopen, re-initialise), doubling from min up to max.
    std::chrono::milliseconds recovery_backoff_min{100};
    std::chrono::milliseconds recovery_backoff_max{2000};
    // Longest single wait for a booting dish inside one recovery attempt (the attempts repeat
    // until the dish answers; the slice keeps stop/shutdown responsive).
    std::chrono::milliseconds recovery_boot_slice{5000};
    // position() refuses (Errc::timeout) a position older than this: the dish has not answered
    // since, so the client is told instead of being handed a stale value.
    std::chrono::milliseconds max_position_age{5000};
};


// Opens the device again after a hang-up (the glue opens the same path with FdTransport::open).
using TransportFactory = std::function<Result<std::unique_ptr<Transport>>()>;

class RotatorService {
public:
    RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options,
                   ServiceTiming timing = {}, TransportFactory reopen = {});
    ~RotatorService();
    RotatorService(const RotatorService&) = delete;
    RotatorService& operator=(const RotatorService&) = delete;

    // Initialises the dish (blocking: boot wait, search stop, motor menu), reads the position
    // once, then starts the worker. Fails without starting anything if the dish cannot be reached.
    Status start();
    // Before start(): how targets become moves (default: as sent).
    void set_pointing(PointingOptions pointing) {
        pointing_ = pointing;
        predictor_ = TargetPredictor(pointing.predictor);
    }
    // Stops the worker; the controller is left as it is (a leg in flight finishes on its own).
    void shutdown();

    // Posts a new target. Returns at once; an invalid target is refused here.
    Status set_target(AzEl target);
    // The last position read from the dish (or, on variants that cannot report it at rest, the
    // controller's best knowledge). Never talks to the dish. Errors instead of a position:
    //  - Errc::timeout while the worker recovers (dish rebooting, unplugged, out of sync): the
    //    last position is stale, so none is reported;
    //  - Errc::protocol once after the dish reported a motor fault (`AZ MOTOR STALLED`).
    Result<AzEl> position();
    // Drops every leg not yet sent to the dish (and aborts a running `g` where input aborts it).
    Status stop();
    // Moves to the variant's safe park position with ordinary moves (never `stow`).
    Status park();
    // Homes the axes (G2: h 1, h 0) in the worker; Errc::unsupported where the firmware cannot.
    Status reset();

    // Receiver (receiver.hpp): taken by the worker between legs, so position() keeps answering from
    // the position model and queued legs wait; the caller blocks until the reading is done.
    // Errc::unsupported on variants without a tuner.
    Result<RssiReading> read_signal(int samples);
    Status set_lnb_supply(LnbSupply supply);
    // The supply last set (the boot default until then, and again after the dish rebooted).
    LnbSupply lnb_supply() const;

    bool idle() const;
    // True from reset() until the home has run: the console is held by the firmware's home
    // command, so position() repeats the last reading taken before it (the dish cannot be asked)
    // and targets posted meanwhile are moved to once the axes are homed.
    bool homing() const;
    // True while the worker re-initialises the dish (after a reboot, hang-up or lost sync).
    bool recovering() const;
    // How many times the worker has recovered the dish (re-initialised it) since start().
    unsigned recoveries() const;
    // The worker's last error (ok if the last service step succeeded); a motor fault stays here
    // until the next target is posted.
    Status last_error() const;
    std::string describe() const;
    const FirmwareProfile& profile() const;

private:
    void run();
    Status run_between_legs(std::function<Status(Controller&)> work, std::chrono::milliseconds timeout);
    void run_receiver_job();
    void publish_locked(const Controller& controller, const Status& step);
    Status detect();
    void enter_recovery_locked(std::string reason);
    Status recover_once();
    Clock::time_point controller_now() const;
    Status accept_target(AzEl target);
    double azimuth_direction_hint(AzEl target) const;
    Status steer();
    void note_step_finished();
    AzEl modelled_position_locked() const;

    std::unique_ptr<Transport> transport_;
    ControllerOptions options_;
    std::unique_ptr<Controller> controller_;   // built at start() once the variant is known
    ServiceTiming timing_;
    TransportFactory reopen_;
    PointingOptions pointing_;
    // Worker-only predictive state: the estimator and what was last handed to the controller.
    TargetPredictor predictor_;
    std::optional<AzEl> aim_;
    std::optional<AzEl> client_target_;   // the last target the client sent, as sent
    struct TimedStep {
        Clock::time_point started;
        int legs = 0;
        double motion_s = 0.0;   // estimated motor time of those legs
    };
    std::optional<TimedStep> timed_step_;
    std::optional<double> measured_overhead_s_;   // per leg, beyond the motion (EMA)
    // Worker-only recovery state.
    bool link_down_ = false;               // the transport hung up; reopen before anything else
    int consecutive_failures_ = 0;
    std::chrono::milliseconds backoff_{0};
    unsigned attempts_ = 0;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    // Mailbox from callers to the worker.
    std::optional<AzEl> posted_target_;
    bool cancel_requested_ = false;
    bool home_requested_ = false;
    bool unhomed_ = false;
    bool shutdown_requested_ = false;
    std::optional<AzEl> latest_target_;   // the client's last target (resumed after a recovery)
    struct ReceiverJob {
        std::function<Status(Controller&)> work;
        Status result;
        bool started = false, done = false;
    };
    std::shared_ptr<ReceiverJob> receiver_job_;   // one at a time; rotctld serialises its clients
    std::condition_variable receiver_done_;
    LnbSupply lnb_supply_ = lnb_boot_default;
    // Snapshot from the worker to callers.
    std::optional<AzEl> position_;
    std::optional<Controller::LegMotion> leg_motion_;   // the move in flight (position model)
    bool idle_ = true;
    bool homing_ = false;
    Status last_error_;
    std::string description_;
    bool recovering_ = false;
    Clock::time_point last_ok_at_{};     // the last service step that succeeded
    std::string recovery_reason_;
    unsigned recoveries_ = 0;
    Status fault_;                 // the last motor fault, until the next target
    Status fault_report_;          // what the next position() reports once
    bool fault_unreported_ = false;

    std::thread worker_;
};

} // namespace birdcage
