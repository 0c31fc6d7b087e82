// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "dish/move_driver.hpp"

#include <memory>

#include "dish/move_drivers.hpp"

namespace birdcage {

std::unique_ptr<MoveDriver> make_move_driver(const MoveContext& context) {
    switch (context.profile.move_style) {
        case MoveStyle::per_axis_a:
            return std::make_unique<AxisLegDriver>(context);
        case MoveStyle::combined_g:
            return std::make_unique<CombinedMoveDriver>(context);
    }
    return std::make_unique<AxisLegDriver>(context);
}

}  // namespace birdcage
