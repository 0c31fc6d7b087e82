// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A move driver turns a target into console commands and follows them until the dish gets there:
// one per move style of the variant table (MoveStyle), chosen by make_move_driver(). The
// controller owns the state they share (MoveContext) and composes one driver with the wrap
// tracker, the position reader and the console setup.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <optional>

#include "base/azel.hpp"
#include "base/clock.hpp"
#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/plain_types.hpp"
#include "console/session.hpp"
#include "dish/dish_state.hpp"
#include "firmware/variants.hpp"
#include "tracking/position_model.hpp"
#include "tracking/wrap_tracker.hpp"

namespace birdcage {

struct MoveContext {
    ConsoleSession& session;
    const FirmwareProfile& profile;
    DishState& state;
    WrapTracker& wrap;
    PositionReader& reader;
    LogSink log;
    std::function<Clock::time_point()> now;  // dish time (clock.hpp)
    double el_min, el_max;

    // The target is void (the firmware dropped its moves): the same target sent again is a new move.
    void forget_target() const {
        state.target.reset();
        wrap.forget_target();
    }
};

class MoveDriver {
public:
    virtual ~MoveDriver() = default;
    // Queues what takes the dish to `wanted` (clamped; DishState::target), commanding `command`
    // (wanted plus any leapfrog lead). `previous`: the target before; `az_rate_dps`, `ahead`: see
    // Controller::set_target(). Replaces whatever was queued. No I/O.
    virtual void plan(AzEl wanted, AzEl command, const std::optional<AzEl>& previous, double az_rate_dps,
                      const std::optional<wrap::PassAhead>& ahead) = 0;
    // One pump step: follows the leg in flight, sends the next one.
    virtual Status service() = 0;
    // Drops what is not sent yet; stops the leg in flight where the firmware lets input stop it.
    virtual void cancel() = 0;
    // Forgets every leg and what was commanded (initialisation, homing).
    virtual void reset() = 0;
    virtual bool idle() const = 0;
    virtual bool leg_in_flight() const = 0;
    virtual MovingAxes moving_axes() const = 0;
    // Where the azimuth leg in flight ends (display degrees) when that is a waypoint of a longer
    // move (wrap::next_waypoint()) rather than the target: a stop ends the move there.
    virtual std::optional<double> azimuth_waypoint() const { return std::nullopt; }
    // The console showed it is not where the controller left it: initialise again.
    virtual bool sync_lost() const = 0;
    // How long a small step (0.4 to 2 degrees) on `axis` takes this dish, from the command to the
    // reading that shows it there, once its own legs have timed it; nullopt before (or where the
    // driver cannot time legs).
    virtual std::optional<double> learnt_step_seconds(Axis) const { return std::nullopt; }
    // The motors' start-up delays and paces as the legs' readings showed them (default: nothing
    // learnt, the variant's motion curve).
    virtual MotorTiming learnt_motor() const { return {}; }
    // Takes over what `before` (the driver of the controller this one replaces, over a reopened
    // port) learnt of the motors: facts about the dish, which an unplugged adapter does not change.
    virtual void take_learning_from(const MoveDriver& before) { (void)before; }
    // The dish was re-initialised after a reboot or an unplug: wherever its firmware left it, the
    // next move should bring it back onto the target as fast as the motors allow.
    virtual void recovered() {}
    // How long an axis may stand still after a command before it moves (its start-up delay as
    // learnt, with a margin, or the allowance while none is): between two moves its firmware has
    // queued, a dish stands still this long.
    virtual std::chrono::milliseconds startup_allowance() const { return std::chrono::milliseconds{0}; }
    // While watched (from initialisation until a leg arrives), a leg that sees the dish move on its
    // own (away from the leg's end, or on the other axis) drops its legs and says so once through
    // took_motion_of_its_own(): the firmware still runs something else (a calibration, a braking
    // search) and runs the leg after it, so what the leg would judge from that motion (a stop
    // short, a start-up delay, the mapping) is wrong.
    virtual void watch_motion_of_its_own(bool watch) { (void)watch; }
    virtual bool took_motion_of_its_own() { return false; }
};

std::unique_ptr<MoveDriver> make_move_driver(const MoveContext& context);

}  // namespace birdcage
