// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The recovery classifier (recovery.hpp): step outcomes in, verdicts out.
#include <catch2/catch.hpp>

#include "service/recovery.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

TEST_CASE("recovery: a hang-up reopens the port at once, a reboot re-initialises at once") {
    const auto hung = classify_step({Status{Errc::disconnected, "EOF"}, true, false, false}, 0, 2);
    CHECK(hung.action == RecoveryAction::reopen);
    CHECK(hung.reason.find("hung up") != std::string::npos);
    const auto rebooted = classify_step({Status::ok(), true, true, false}, 0, 2);
    CHECK(rebooted.action == RecoveryAction::reinitialise);
}

TEST_CASE("recovery: timeouts re-synchronise only after the configured run, any answer resets the count") {
    const StepOutcome timeout{Status{Errc::timeout, "no prompt"}, true, false, false};
    const auto first = classify_step(timeout, 0, 2);
    CHECK(first.action == RecoveryAction::none);
    CHECK(first.consecutive_failures == 1);
    const auto second = classify_step(timeout, first.consecutive_failures, 2);
    CHECK(second.action == RecoveryAction::resynchronise);
    CHECK(second.reason.find("no prompt") != std::string::npos);
    // Refusals and fault lines are answers: the console is in step.
    for (const Errc refusal : {Errc::not_homed, Errc::hazard, Errc::invalid_argument, Errc::unsupported}) {
        CHECK(classify_step({Status{refusal, "refused"}, true, false, false}, 1, 2).consecutive_failures == 0);
    }
    CHECK(classify_step({Status{Errc::protocol, "stall"}, true, false, true}, 1, 2).action == RecoveryAction::none);
}

TEST_CASE("recovery: a step that asked nothing proves nothing") {
    const auto idle = classify_step({Status{Errc::timeout, "x"}, false, false, false}, 1, 2);
    CHECK(idle.action == RecoveryAction::none);
    CHECK(idle.consecutive_failures == 1);
}

TEST_CASE("recovery: a failed attempt backs off doubling within bounds, a lost link is reopened first") {
    const auto first = classify_failed_attempt(Status{Errc::protocol, "unexpected prompt"}, 0ms, 100ms, 2000ms);
    CHECK_FALSE(first.reopen);
    CHECK(first.backoff == 100ms);
    const auto later = classify_failed_attempt(Status{Errc::protocol, "unexpected prompt"}, 1500ms, 100ms, 2000ms);
    CHECK(later.backoff == 2000ms);
    // A timed-out attempt listened for its whole slice: the next listens after the shortest pause,
    // so the ready line of a booting dish is read when it comes, not seconds later.
    const auto booting = classify_failed_attempt(Status{Errc::timeout, "still booting"}, 1500ms, 100ms, 2000ms);
    CHECK_FALSE(booting.reopen);
    CHECK(booting.backoff == 100ms);
    CHECK(classify_failed_attempt(Status{Errc::disconnected, "EOF"}, 100ms, 100ms, 2000ms).reopen);
    CHECK(classify_failed_attempt(Status{Errc::io, "EIO"}, 100ms, 100ms, 2000ms).reopen);
}
