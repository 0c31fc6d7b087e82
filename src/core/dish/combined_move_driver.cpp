// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <algorithm>
#include <cmath>
#include <utility>

#include "dish/move_drivers.hpp"
#include "firmware/protocol.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto listen_slice = 100ms;        // one service() call listens this long for live output
constexpr auto leg_margin = 3000ms;         // added to 2 x the estimated move time
constexpr auto menu_step_timeout = 3000ms;  // the line ending that aborts a `g`, and its reply
// `g` with prompts unknown: its reply is the quiet gap after the first live output, or this.
constexpr auto send_timeout = 1000ms;
// The 2003 Carryout prints a live position line within this long after `g` starts a move: the
// upstream client reads 1 s after writing `g` and parses one (docs/firmware.md 8.4). A `g` that needed
// a move and printed none in this window did not run as a move (the console is not in `target`).
constexpr auto first_live_line_window = 1000ms;
// Without a position reading the distance of a move is unknown: assume the longest (a half turn).
constexpr double unknown_distance_degrees = 180.0;

std::string degrees_text(double value) {
    return format_degrees(value);
}

}  // namespace

void CombinedMoveDriver::plan(AzEl, AzEl command, const std::optional<AzEl>&, double,
                              const std::optional<wrap::PassAhead>&) {
    // `g az el` takes 0..360 only (the 2003 Carryout's travel is 0..360): no branch to choose.
    pending_ = Move{command};
}

void CombinedMoveDriver::reset() {
    pending_.reset();
    in_flight_.reset();
    sync_lost_ = false;
}

bool CombinedMoveDriver::at_target(const AzEl& position) const {
    const AzEl& target = in_flight_->target;
    return std::fabs(azimuth_difference(position.az, target.az)) <= c_.profile.arrival_tolerance &&
           std::fabs(position.el - target.el) <= c_.profile.arrival_tolerance;
}

Status CombinedMoveDriver::service() {
    if (in_flight_) {
        const Status status = follow();
        if (in_flight_ || !status) {
            return status;
        }
    }
    if (!pending_) {
        return Status::ok();
    }
    return send(*std::exchange(pending_, std::nullopt));
}

Status CombinedMoveDriver::send(Move move) {
    const auto& last = c_.state.last_position;
    const double distance =
        last ? std::max(std::fabs(azimuth_difference(last->az, move.target.az)), std::fabs(move.target.el - last->el))
             : unknown_distance_degrees;
    const auto estimate = std::max(estimated_move_time(c_.profile, Axis::azimuth, distance),
                                   estimated_move_time(c_.profile, Axis::elevation, distance));
    move.budget = estimate * 2 + leg_margin;
    move.needs_motion = distance > c_.profile.arrival_tolerance;
    const std::string command = build_combined_move(move.target);
    const auto reply = c_.session.transact(command, send_timeout);
    if (!reply && reply.status.code != Errc::timeout) {
        return reply.status;
    }
    if (!reply) {
        // Expected: the live output runs until the move ends.
        emit(c_.log, LogLevel::verbose, "no prompt after " + command + "; assuming the move runs");
    }
    // Live output that arrived with the reply is the first position sample.
    move.live_seen = static_cast<bool>(c_.reader.note_live_output(reply.value.lines));
    live_output_proven_ = live_output_proven_ || move.live_seen;
    move.sent_at = c_.now();
    last_poll_ = move.sent_at;
    emit(c_.log, LogLevel::verbose, "sent " + command + " (estimated " + std::to_string(estimate.count()) + " ms)");
    in_flight_ = move;
    // A prompt with no live line for a move that needed one proves nothing yet: the shell may run
    // `g` in the background, or not be in `target` at all (follow() decides).
    if (reply && !reply.value.prompt.empty() && (move.live_seen || !move.needs_motion || !live_output_proven_)) {
        end_without_readback("ended (prompt after the move)");
    }
    return Status::ok();
}

Status CombinedMoveDriver::follow() {
    Move& move = *in_flight_;
    const auto t = c_.now();
    if (t - last_poll_ < listen_slice) {
        return Status::ok();
    }
    last_poll_ = t;
    // Sending anything during `g` may abort it (docs/firmware.md 2, 3.5; 8.5 leaves it open for the
    // 2003 Carryout): listen instead.
    const auto heard = c_.session.listen(listen_slice);
    if (!heard) {
        finish("abandoned: " + heard.status.message);
        return heard.status;
    }
    const Result<AzEl> sample = c_.reader.note_live_output(heard.value.lines);
    if (sample) {
        move.live_seen = true;
        live_output_proven_ = true;
        if (at_target(sample.value)) {
            finish("arrived");
            return Status::ok();
        }
    }
    // A prompt after live output ends the move; one before any (the shell may run `g` in the
    // background) ends it only where nothing else can (no move needed, no live output known).
    if (!heard.value.prompt.empty() && (move.live_seen || !move.needs_motion || !live_output_proven_)) {
        end_without_readback("ended (prompt after the move)");
        return Status::ok();
    }
    // A silent reboot leaves the 2003 Carryout at its root, booting, with no boot line (8.1, 8.2),
    // and a bare `>` prompt may look the same in every menu. What gives it away on any reading of
    // the firmware: this console has printed live positions during `g` before, and now a `g` that
    // needed a move printed none in the window the upstream client relies on, or its live output
    // stopped short of the target with no prompt after it. Either way the console is not where the
    // backend left it: re-initialise (Controller::needs_reinit()), which waits out a boot.
    if (live_output_proven_ && move.needs_motion && !move.live_seen && t - move.sent_at >= first_live_line_window) {
        return lose_sync("the dish printed no live position within " + std::to_string(first_live_line_window.count()) +
                         " ms of " + build_combined_move(move.target) + ": it did not run the move");
    }
    if (t - move.sent_at > move.budget) {
        if (move.live_seen) {
            const AzEl& last = *c_.state.last_position;
            return lose_sync("the live position stopped at az " + degrees_text(last.az) + " el " +
                             degrees_text(last.el) + ", short of the target, and no prompt followed");
        }
        c_.state.record(move.target, t, true);
        finish("assumed complete (estimated move time elapsed)");
    }
    return Status::ok();
}

// The move is over with no live sample at its end: the commanded position is all that is known
// (and describe() says so).
void CombinedMoveDriver::end_without_readback(std::string_view how) {
    if (!c_.state.last_position || c_.state.position_estimated) {
        c_.state.record(in_flight_->target, c_.now(), true);
    }
    finish(how);
}

void CombinedMoveDriver::finish(std::string_view how) {
    if (!in_flight_) {
        return;
    }
    emit(c_.log, LogLevel::verbose, "leg " + std::string(how));
    in_flight_.reset();
}

Status CombinedMoveDriver::lose_sync(const std::string& why) {
    emit(c_.log, LogLevel::warning, why + "; the console is not where it was left (a silent reboot?): re-initialising");
    finish("abandoned");
    pending_.reset();
    sync_lost_ = true;
    return Status{Errc::not_initialised, why};
}

// A bare line ending is the documented way to stop a running `g` (docs/firmware.md 2, 3.5); where the
// firmware reads it only once the move is over (8.5), it ends the move at its target instead.
void CombinedMoveDriver::cancel() {
    pending_.reset();
    if (!in_flight_) {
        return;
    }
    if (const auto heard = c_.session.listen(0ms); heard) {
        c_.reader.note_live_output(heard.value.lines);
    }
    const auto reply = c_.session.transact("", menu_step_timeout);
    c_.reader.note_live_output(reply.value.lines);
    if (reply.value.prompt.empty()) {
        return;
    }
    // A prompt after a live line at the target is an arrival, not an abort.
    const auto& last = c_.state.last_position;
    const bool arrived = last && at_target(*last);
    emit(c_.log, LogLevel::verbose,
         arrived ? "stop: the running g had reached its target; the line ending did not abort it"
                 : "stop: sent a line ending to abort the running g");
    finish(arrived ? "arrived" : "aborted by stop");
}

}  // namespace birdcage
