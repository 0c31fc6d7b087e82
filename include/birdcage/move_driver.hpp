// A move driver turns a target into console commands and follows them until the dish gets there:
// one per move style of the variant table (MoveStyle), chosen by make_move_driver(). The
// controller owns the state they share (MoveContext) and composes one driver with the wrap
// tracker, the position reader and the console setup.
#pragma once

#include <functional>
#include <memory>
#include <optional>

#include "birdcage/azel.hpp"
#include "birdcage/clock.hpp"
#include "birdcage/dish_state.hpp"
#include "birdcage/errors.hpp"
#include "birdcage/log.hpp"
#include "birdcage/session.hpp"
#include "birdcage/variants.hpp"
#include "birdcage/wrap_tracker.hpp"

namespace birdcage {

// One axis reading taken during a leg (display degrees, dish time).
struct AxisReading {
    double value = 0.0;
    Clock::time_point at{};
};

// A single-axis leg whose axis may still be moving, for a position model between polls: sent at
// `sent_at` from `start` towards `to` (display degrees). `latest` is the axis' last reading;
// `previous` the one before it and `first_moving` the first that showed the axis under way, both
// taken during this leg (add_reading()).
struct LegMotion {
    Axis axis = Axis::azimuth;
    double start = 0.0, to = 0.0;
    Clock::time_point sent_at{};
    AxisReading latest;
    std::optional<AxisReading> previous, first_moving;
    double pace = 1.0;   // until its readings time it: the axis' pace on legs this long (AxisPaces)
    // The axis' start-up delay (seconds from the command to the first motion; StartupDelays): 0 for
    // a leg sent while the axis was still moving (a running motor takes a new target at once).
    double startup_s = 0.0;
};

// At most one leg per axis: the one in flight, and the one before it on the other axis while it may
// still be covering the last of its arrival tolerance.
struct MovingAxes {
    std::optional<LegMotion> azimuth, elevation;
    bool empty() const { return !azimuth && !elevation; }
};

struct MoveContext {
    ConsoleSession& session;
    const FirmwareProfile& profile;
    DishState& state;
    WrapTracker& wrap;
    PositionReader& reader;
    LogSink log;
    std::function<Clock::time_point()> now;   // dish time (clock.hpp)
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
    // (wanted plus any leapfrog lead). `previous`: the target before; `az_rate_dps`: see
    // Controller::set_target(). Replaces whatever was queued. No I/O.
    virtual void plan(AzEl wanted, AzEl command, const std::optional<AzEl>& previous, double az_rate_dps) = 0;
    // One pump step: follows the leg in flight, sends the next one.
    virtual Status service() = 0;
    // Drops what is not sent yet; stops the leg in flight where the firmware lets input stop it.
    virtual void cancel() = 0;
    // Forgets every leg and what was commanded (initialisation, homing).
    virtual void reset() = 0;
    virtual bool idle() const = 0;
    virtual bool leg_in_flight() const = 0;
    virtual MovingAxes moving_axes() const = 0;
    // The console showed it is not where the controller left it: initialise again.
    virtual bool sync_lost() const = 0;
};

std::unique_ptr<MoveDriver> make_move_driver(const MoveContext& context);

}  // namespace birdcage
