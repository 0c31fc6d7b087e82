// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What the backend knows of the dish between commands (position, homing, the last fault), and the
// one place a position reply or a live position line becomes that knowledge. Shared by the
// controller and its move driver.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "base/azel.hpp"
#include "base/clock.hpp"
#include "base/errors.hpp"
#include "base/span.hpp"
#include "console/session.hpp"
#include "firmware/variants.hpp"
#include "tracking/wrap_tracker.hpp"

namespace birdcage {

struct DishState {
    std::optional<AzEl> last_position;  // az in [0, 360)
    std::optional<Clock::time_point> last_position_at;
    bool position_estimated = false;  // last_position comes from commands, not a readback
    bool unhomed = false;
    bool fault_reported = false;  // the last position reply carried a fault line (stall)
    std::string fault;            // that fault, until Controller::take_fault()
    std::optional<AzEl> target;   // the client's target as accepted (clamped), display degrees

    // A position the dish reported (estimated = false) or the backend inferred (true).
    void record(AzEl position, Clock::time_point at, bool estimated);
};

class PositionReader {
public:
    PositionReader(ConsoleSession& session, const FirmwareProfile& profile, WrapTracker& wrap, DishState& state,
                   std::function<Clock::time_point()> now);

    // Asks the dish (the variant's position query) and records the answer; a fault line in the
    // reply is kept in DishState::fault and returned as Errc::protocol with the position.
    Result<AzEl> ask(std::chrono::milliseconds timeout);
    // The newest live position line among `lines` (2003 Carryout `g`, docs/firmware.md 8.4), recorded.
    Result<AzEl> note_live_output(Span<const std::string> lines);

private:
    void record_reading(AzEl& reading);

    ConsoleSession& session_;
    const FirmwareProfile& profile_;
    WrapTracker& wrap_;
    DishState& state_;
    std::function<Clock::time_point()> now_;
};

}  // namespace birdcage
