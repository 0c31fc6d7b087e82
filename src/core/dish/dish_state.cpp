// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "dish/dish_state.hpp"

#include "firmware/protocol.hpp"

namespace birdcage {

void DishState::record(AzEl position, Clock::time_point at, bool estimated) {
    last_position = position;
    last_position_at = at;
    position_estimated = estimated;
}

PositionReader::PositionReader(ConsoleSession& session, const FirmwareProfile& profile, WrapTracker& wrap,
                               DishState& state, std::function<Clock::time_point()> now)
    : session_(session), profile_(profile), wrap_(wrap), state_(state), now_(std::move(now)) {}

void PositionReader::record_reading(AzEl& reading) {
    const auto t = now_();
    wrap_.note_reading(reading.az, t);
    reading.az = normalize_azimuth(reading.az);
    state_.record(reading, t, false);
}

Result<AzEl> PositionReader::ask(std::chrono::milliseconds timeout) {
    const auto complete = [this](Span<const std::string> lines) {
        return parse_position(profile_, lines).status.code != Errc::protocol;
    };
    const std::string command(profile_.position_query);
    const auto reply = session_.transact(command, timeout, complete);
    state_.fault_reported = reply.status.code == Errc::protocol;  // the session's only protocol error: a fault line
    if (state_.fault_reported) {
        state_.fault = reply.status.message;
    }
    if (!reply && reply.status.code != Errc::protocol) {
        return {{}, reply.status};
    }
    auto position = parse_position(profile_, reply.value.lines);
    if (position.status.code == Errc::not_homed) {
        state_.unhomed = true;
        session_.set_axes_unhomed(true);
        session_.report(ConsoleEvent::reply_to(ConsoleEvent::Kind::unhomed, command));
        return position;
    }
    if (!position) {
        // A reply that was only a fault line is reported as that (by the session).
        if (!state_.fault_reported || !reply.value.lines.empty()) {
            const std::string first_line = reply.value.lines.empty() ? std::string() : reply.value.lines.front();
            session_.report(ConsoleEvent::reply_to(ConsoleEvent::Kind::unrecognised, command, first_line));
        }
        return position;
    }
    state_.unhomed = false;
    session_.set_axes_unhomed(false);
    record_reading(position.value);
    session_.report(ConsoleEvent::read_position(ConsoleEvent::Kind::position, position.value));
    if (!reply) {
        position.status = reply.status;  // a valid position, but the dish also reported a fault
    }
    return position;
}

Result<AzEl> PositionReader::note_live_output(Span<const std::string> lines) {
    // Every live line is an event, not only the newest: how many lines one read brings is timing.
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (auto sample = parse_carryout_live(lines.subspan(i, 1))) {
            sample.value.az = normalize_azimuth(sample.value.az);
            session_.report(ConsoleEvent::read_position(ConsoleEvent::Kind::live_position, sample.value));
        }
    }
    auto sample = parse_carryout_live(lines);
    if (sample) {
        record_reading(sample.value);
    }
    return sample;
}

}  // namespace birdcage
