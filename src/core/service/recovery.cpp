// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "service/recovery.hpp"

#include <algorithm>

namespace birdcage {

namespace {

bool link_lost(const Status& status) {
    return status.code == Errc::disconnected || status.code == Errc::io;
}

}  // namespace

RecoveryVerdict classify_step(const StepOutcome& outcome, int failures_so_far, int failures_before_recovery) {
    const Status& step = outcome.status;
    if (link_lost(step)) {
        return {RecoveryAction::reopen, failures_so_far,
                "the serial port hung up (" + step.message + "); reopening it"};
    }
    if (outcome.needs_reinit) {
        return {RecoveryAction::reinitialise, failures_so_far,
                "the dish rebooted; waiting for it to boot and re-initialising it"};
    }
    if (!outcome.talked) {
        return {RecoveryAction::none, failures_so_far, {}};  // nothing asked: neither success nor failure
    }
    // Answers that prove the console is alive and in step, even when they refuse something.
    const bool console_answered = step || outcome.fault_reported || step.code == Errc::not_homed ||
                                  step.code == Errc::hazard || step.code == Errc::invalid_argument ||
                                  step.code == Errc::unsupported;
    if (console_answered) {
        return {RecoveryAction::none, 0, {}};
    }
    const int failures = failures_so_far + 1;
    if (failures >= failures_before_recovery) {
        return {RecoveryAction::resynchronise, failures,
                "the dish stopped answering (" + step.message + "); re-synchronising"};
    }
    return {RecoveryAction::none, failures, {}};
}

RetryVerdict classify_failed_attempt(const Status& attempt, std::chrono::milliseconds previous_backoff,
                                     std::chrono::milliseconds min, std::chrono::milliseconds max) {
    if (attempt.code == Errc::timeout) {
        return {false, min};
    }
    return {link_lost(attempt), std::clamp(previous_backoff * 2, min, max)};
}

}  // namespace birdcage
