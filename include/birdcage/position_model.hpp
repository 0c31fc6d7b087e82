// Where the dish is between polls, pure: a move in flight runs its axis from the last reading to
// the leg's target over the variant's estimated move time (variants.hpp) with a symmetric
// accelerate/brake profile, so `p` follows a moving dish instead of repeating the last poll.
#pragma once

#include <optional>

#include "birdcage/azel.hpp"
#include "birdcage/move_driver.hpp"
#include "birdcage/variants.hpp"

namespace birdcage {

// `last`: the last reading; `leg`: the move in flight (none: the dish is at `last`); `now`: dish time.
AzEl modelled_position(const FirmwareProfile& dish, AzEl last, const std::optional<LegMotion>& leg,
                       Clock::time_point now);

}  // namespace birdcage
