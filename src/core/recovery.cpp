#include "birdcage/recovery.hpp"

namespace birdcage {

RecoveryVerdict classify_step(const StepOutcome& outcome, int failures_so_far, int failures_before_recovery) {
    const Status& step = outcome.status;
    if (step.code == Errc::disconnected || step.code == Errc::io) {
        return {RecoveryAction::reopen, failures_so_far, "the serial port hung up (" + step.message + "); reopening it"};
    }
    if (outcome.needs_reinit) {
        return {RecoveryAction::reinitialise, failures_so_far,
                "the dish rebooted; waiting for it to boot and re-initialising it"};
    }
    if (!outcome.talked) {
        return {RecoveryAction::none, failures_so_far, {}};   // nothing asked: neither success nor failure
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

}  // namespace birdcage
