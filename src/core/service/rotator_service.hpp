// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A Controller driven by its own worker thread, so that callers never wait for the dish.
//
// Why a thread: rotctld runs every client's command under one global mutex, and the dish moves one
// axis at a time, so a set_position that waited for motion would stall every client's `p` for
// seconds (docs/tracking.md §1.3). Here set_target() only posts the latest target, position()
// answers from the last position the worker read, and the worker sends each axis leg when the
// dish is free, polling the position while it moves.
//
// Three parts: the mailbox (service_mailbox.hpp, the only state both threads touch), the worker
// (service_worker.hpp, the only code that talks to the dish) and this facade, which owns the
// thread and turns the worker's snapshot into answers (position model, staleness, faults).
#pragma once

#include "base/errors.hpp"
#include "console/transport.hpp"
#include "dish/controller.hpp"
#include "dish/receiver.hpp"
#include "service/service_mailbox.hpp"
#include "service/service_worker.hpp"
#include "tracking/mount_model.hpp"
#include "tracking/pointing.hpp"
#include "tracking/steering.hpp"

#include <memory>
#include <string>
#include <thread>

namespace birdcage {

class RotatorService {
public:
    RotatorService(std::unique_ptr<Transport> transport, ControllerOptions options, ServiceTiming timing = {},
                   TransportFactory reopen = {});
    ~RotatorService();
    RotatorService(const RotatorService&) = delete;
    RotatorService& operator=(const RotatorService&) = delete;

    // Before start(): how targets become moves (default: the variant's).
    void set_pointing(PointingOptions pointing);
    // Before start(): how the dish's axes sit against the sky (docs/sky.md §1; default: aligned).
    // Targets and position() are then in the sky; limits and cable wrap stay in the dish's axes.
    void set_mount(MountModel mount);
    // Initialises the dish (blocking, at most ControllerOptions::boot_timeout: boot wait, search
    // stop, motor menu), reads the position once, then starts the worker. Fails without starting
    // anything if the dish cannot be reached; a dish heard booting is left to the worker
    // (initialising()), and the calls meanwhile answer as while it recovers.
    Status start();
    // Stops the worker; the controller is left as it is (a leg in flight finishes on its own).
    void shutdown();

    // Posts a new target (sky). Returns at once; an invalid target is refused here.
    Status set_target(AzEl target);
    // Where the dish points in the sky: the last position read from the dish, advanced along the
    // move in flight (position_model.hpp) in its axes, then mapped by the mount model
    // — or, on variants that cannot report it at rest, the controller's best knowledge. Never
    // talks to the dish. While the dish cannot be asked (the worker recovers it: rebooting,
    // re-initialising, unplugged, out of sync; or it has not answered for
    // ServiceTiming::max_position_age), the last reading as read, not advanced: answering() is
    // false and describe() says why. After a recovery, the first position is a fresh reading.
    // Errors instead of a position:
    //  - Errc::timeout while recovering before any position was ever read;
    //  - Errc::protocol once after the dish reported a motor fault (`AZ MOTOR STALLED`);
    //  - Errc::not_homed while the dish reports its axes unhomed.
    Result<AzEl> position();
    // Drops every leg not yet sent to the dish (and aborts a running `g` where input aborts it).
    Status stop();
    // Moves to the variant's safe park position (dish axes) with ordinary moves (never `stow`).
    Status park();
    // Starts homing the axes (G2: h 1, h 0) in the worker and returns; homing() tells when it
    // ends. Errc::unsupported where the firmware cannot home.
    Status reset();

    // Receiver (receiver.hpp): taken by the worker between legs, so position() keeps answering
    // from the position model and queued legs wait; the caller blocks until the reading is done.
    // Errc::unsupported on variants without a tuner.
    Result<RssiReading> read_signal(int samples);
    Status set_lnb_supply(LnbSupply supply);
    // The supply last set (the boot default until then, and again after the dish rebooted).
    // Empty while unknown: not read at open (no `dis` answer) and not set since (docs/receiver.md).
    std::optional<LnbSupply> lnb_supply() const;

    bool idle() const;
    // True from reset() until the home has run. position() keeps answering meanwhile.
    bool homing() const;
    // True while the worker re-initialises the dish (after a reboot, hang-up or lost sync, or at
    // open: initialising()).
    bool recovering() const;
    // True while the dish, still booting when start() returned, has not been initialised yet.
    bool initialising() const;
    // False while the dish cannot be asked: recovering, or silent for ServiceTiming::max_position_age.
    bool answering() const;
    // How many times the worker has recovered the dish (re-initialised it) since start().
    unsigned recoveries() const;
    // The worker's last error (ok if the last service step succeeded); a motor fault stays here
    // until the next target is posted.
    Status last_error() const;
    std::string describe() const;
    // The variant's table row (the probe row until start() has identified the dish).
    const FirmwareProfile& profile() const;

private:
    Status unsupported_without_tuner() const;
    bool not_answering(const ServiceSnapshot& dish) const;

    ServiceTiming timing_;
    ServiceMailbox mailbox_;
    ServiceWorker worker_;
    std::thread thread_;
};

}  // namespace birdcage
