// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The recovery classifier, pure: what one worker step's outcome means for the link to the dish —
// carry on, count a failure, or recover (reopen the port, wait for a rebooted dish, re-synchronise
// a console that stopped answering). RotatorService acts on the verdict; tests feed outcomes.
#pragma once

#include <chrono>
#include <string>

#include "base/errors.hpp"

namespace birdcage {

struct StepOutcome {
    Status status;                // the step's result
    bool talked = true;           // the step exchanged something with the dish
    bool needs_reinit = false;    // the controller saw boot output or a foreign menu
    bool fault_reported = false;  // the dish printed a fault line (a stall): it answers
};

enum class RecoveryAction { none, reopen, reinitialise, resynchronise };

struct RecoveryVerdict {
    RecoveryAction action = RecoveryAction::none;
    int consecutive_failures = 0;  // the count after this step
    std::string reason;            // for the log and for position()'s error while recovering
};

// `failures_so_far`: consecutive failed steps before this one; `failures_before_recovery`: how
// many in a row mean the console is out of sync (a single timeout is not).
RecoveryVerdict classify_step(const StepOutcome& outcome, int failures_so_far, int failures_before_recovery);

// A recovery attempt failed: whether the port must be reopened before the next one, and how long
// to wait for it. An attempt that timed out has spent its time listening to the line (the
// synchroniser paces its own pokes): the next one follows after `min` only, since a longer pause
// would leave unread the ready line a booting Trav'ler prints before its TV search swings the
// dish. Any other failure waits, doubling from `min` up to `max`, so a port that reopens later is
// found quickly without a busy loop.
struct RetryVerdict {
    bool reopen = false;
    std::chrono::milliseconds backoff{0};
};
RetryVerdict classify_failed_attempt(const Status& attempt, std::chrono::milliseconds previous_backoff,
                                     std::chrono::milliseconds min, std::chrono::milliseconds max);

}  // namespace birdcage
