// A Controller driven by its own worker thread, so that callers never wait for the dish.
//
// Why a thread: rotctld runs every client's command under one global mutex, and the dish moves one
// axis at a time, so a set_position that waited for motion would stall every client's `p` for
// seconds (notes/tracking.md §1.3). Here set_target() only posts the latest target, position()
// answers from the last position the worker read, and the worker sends each axis leg when the
// dish is free, polling the position while it moves.
#pragma once

#include "birdcage/controller.hpp"
#include "birdcage/detect.hpp"
#include "birdcage/errors.hpp"
#include "birdcage/transport.hpp"

#include <chrono>
#include <condition_variable>
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
};

class RotatorService {
public:
    RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options,
                   ServiceTiming timing = {});
    ~RotatorService();
    RotatorService(const RotatorService&) = delete;
    RotatorService& operator=(const RotatorService&) = delete;

    // Initialises the dish (blocking: boot wait, search stop, motor menu), reads the position
    // once, then starts the worker. Fails without starting anything if the dish cannot be reached.
    Status start();
    // Stops the worker; the controller is left as it is (a leg in flight finishes on its own).
    void shutdown();

    // Posts a new target. Returns at once; an invalid target is refused here.
    Status set_target(AzEl target);
    // The last position read from the dish (or, on variants that cannot report it at rest, the
    // controller's best knowledge). Never talks to the dish.
    Result<AzEl> position() const;
    // Drops every leg not yet sent to the dish (and aborts a running `g` where input aborts it).
    Status stop();
    // Moves to the variant's safe park position with ordinary moves (never `stow`).
    Status park();
    // Homes the axes (G2: h 1, h 0) in the worker; Errc::unsupported where the firmware cannot.
    Status reset();

    bool idle() const;
    // The worker's last error (ok if the last service step succeeded).
    Status last_error() const;
    std::string describe() const;
    const FirmwareProfile& profile() const;

private:
    void run();
    void publish_locked(const Controller& controller, const Status& step);
    Status detect();

    std::unique_ptr<Transport> transport_;
    ControllerOptions options_;
    std::unique_ptr<Controller> controller_;   // built at start() once the variant is known
    ServiceTiming timing_;

    mutable std::mutex mutex_;
    std::condition_variable wake_;
    // Mailbox from callers to the worker.
    std::optional<AzEl> posted_target_;
    bool cancel_requested_ = false;
    bool home_requested_ = false;
    bool unhomed_ = false;
    bool shutdown_requested_ = false;
    // Snapshot from the worker to callers.
    std::optional<AzEl> position_;
    bool idle_ = true;
    Status last_error_;
    std::string description_;

    std::thread worker_;
};

} // namespace birdcage
