// Where the dish is between polls, pure. A leg in flight runs its axis from where it stood when the
// leg was sent to the leg's target along the variant's motion model (variants.hpp:
// travelled_after). The latest reading places the axis on that curve (how far along it is) and,
// with the reading before it in the same leg, times it (how fast the real axis goes through the
// curve), so the model follows the dish's pace rather than the table's guess of it: the Trav'lers
// publish no speed or acceleration (docs/firmware.md 3.4).
#pragma once

#include <optional>

#include "birdcage/azel.hpp"
#include "birdcage/move_driver.hpp"
#include "birdcage/variants.hpp"

namespace birdcage {

// `last`: the last reading; `moving`: the legs whose axes may still be moving (none: the dish is at
// `last`); `now`: dish time.
AzEl modelled_position(const FirmwareProfile& dish, AzEl last, const MovingAxes& moving, Clock::time_point now);

// One axis of that: where the leg's axis is at `now`.
double modelled_axis(const FirmwareProfile& dish, const LegMotion& leg, Clock::time_point now);

}  // namespace birdcage
