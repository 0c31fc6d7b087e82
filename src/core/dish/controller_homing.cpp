// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The Controller's homing (Hamlib reset): the variant's home commands one at a time, a slice of
// console reading per service() call, so the caller's loop keeps answering while the axes home.
#include "dish/controller.hpp"

#include <string>

namespace birdcage {
namespace {

using namespace std::chrono_literals;

// `h <id>` blocks the shell until the axis is homed. Homing is motion, so the bound is dish time
// (clock.hpp): the emulator's time scale shortens it as it shortens the homing.
constexpr auto home_timeout = 180000ms;
// While homing, one service() call reads the console this long (real time) for the prompt: short
// enough that the caller's loop stays responsive, long enough not to spin.
constexpr auto home_listen_slice = 100ms;

}  // namespace

void Controller::warn_if_unhomed() const {
    if (profile_.has(quirk_requires_homing) && state_.unhomed) {
        emit(options_.log, LogLevel::error,
             "the dish's axes are not homed (it reports INT_MAX); moves are refused until it is homed: "
             "use reset (rotctl R 1), which runs h 1 and h 0");
    }
}

Status Controller::start_home() {
    if (profile_.home_commands.empty()) {
        return Status{Errc::unsupported,
                      std::string(profile_.display_name) + " has no homing command (it calibrates at power-up only)"};
    }
    if (!initialised_) {
        return Status{Errc::not_initialised, "initialize() has not succeeded"};
    }
    // Whatever was queued or in flight is void: homing recalibrates both axes.
    driver_->reset();
    forget_target();
    wrap_.forget_position();
    start_rest_.reset();  // homing moves the dish and reads it at the end
    homing_ = HomingRun{};
    return Status::ok();
}

Status Controller::home() {
    if (Status started = start_home(); !started) {
        return started;
    }
    while (homing_) {
        if (Status step = service(); !step) {
            return step;
        }
    }
    return Status::ok();
}

Status Controller::service_homing() {
    HomingRun& run = *homing_;
    if (run.next >= profile_.home_commands.size()) {
        return finish_homing();
    }
    const std::string command(profile_.home_commands[run.next]);
    const auto failed = [&](const Status& why) {
        homing_.reset();
        return Status{why.code, "homing (" + command + "): " + why.message};
    };
    Result<Reply> heard;
    if (!run.awaiting_prompt) {
        emit(options_.log, LogLevel::verbose, "homing: " + command);
        heard = session_.transact(command, home_listen_slice);
        run.sent_at = now();
        run.awaiting_prompt = true;
        if (!heard && heard.status.code != Errc::timeout) {
            return failed(heard.status);
        }
    } else {
        heard = session_.listen(home_listen_slice);
        if (!heard) {
            return failed(heard.status);
        }
    }
    if (!heard.value.prompt.empty()) {
        run.awaiting_prompt = false;
        ++run.next;
        return service_homing();  // the next command at once, or the end
    }
    if (now() - run.sent_at > home_timeout) {
        return failed(Status{Errc::timeout, "no prompt within " + std::to_string(home_timeout.count()) + " ms"});
    }
    return Status::ok();
}

Status Controller::finish_homing() {
    homing_.reset();
    state_.unhomed = false;
    session_.set_axes_unhomed(false);
    const auto position = reader_.ask(query_timeout);
    if (!position) {
        return Status{position.status.code, "after homing: " + position.status.message};
    }
    emit(options_.log, LogLevel::verbose, "homed: " + describe());
    return Status::ok();
}

}  // namespace birdcage
