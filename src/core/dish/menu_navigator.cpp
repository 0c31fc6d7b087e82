// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "dish/menu_navigator.hpp"

#include <array>
#include <string>

#include "console/synchroniser.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto menu_step_timeout = 3000ms;  // one menu command and its reply
// Re-synchronising on a console that is up, only its menu unknown (as auto-detection does after a `q`).
constexpr auto menu_sync_budget = 5000ms;
// Known prompts: `q` at most this often on the way to the root (the deepest nesting is 3 levels,
// Pro IDU > ODU > mot, plus one for a menu learnt late).
constexpr int max_menu_levels = 4;

}  // namespace

MenuNavigator::MenuNavigator(ConsoleSession& session, const FirmwareProfile& profile, LogSink log)
    : session_(session), profile_(profile), log_(std::move(log)) {}

Status MenuNavigator::run_steps(Span<const ConsoleStep> steps, std::string_view purpose) {
    for (const auto& step : steps) {
        const auto reply = session_.transact(step.command, menu_step_timeout);
        if (!reply) {
            return Status{reply.status.code, std::string(purpose) + ": " + reply.status.message};
        }
        if (step.settle.count() > 0) {
            if (const auto heard = session_.listen(step.settle); !heard) {
                return heard.status;
            }
        }
    }
    return Status::ok();
}

Status MenuNavigator::leave_submenus() {
    if (!profile_.prompt_known()) {
        // The clients' idiom (docs/firmware.md 2): `q` leaves a submenu, a bare line clears the input.
        static constexpr std::array<ConsoleStep, 2> back_to_root{{{"q", 0ms}, {"", 0ms}}};
        return run_steps(back_to_root, "leaving submenus");
    }
    for (int level = 0; level < max_menu_levels; ++level) {
        if (session_.menu().empty()) {
            // The one way to learn where an unknown console is: the synchroniser (never one line).
            const auto synced = session_.synchronise(console_sync_settings(profile_, menu_sync_budget));
            if (!synced) {
                return synced.status;
            }
        }
        if (session_.menu() == "root") {
            return Status::ok();
        }
        if (const auto left = session_.transact("q", menu_step_timeout); !left) {
            return left.status;
        }
    }
    return Status{Errc::protocol, "could not reach the root menu (last prompt " + session_.last_prompt() + ")"};
}

Status MenuNavigator::visit(std::string_view menu, const std::function<Status(ConsoleSession&)>& work) {
    if (Status left = leave_submenus(); !left) {
        return left;
    }
    Status worked = Status::ok();
    if (const auto entered = session_.transact(menu, menu_step_timeout); !entered) {
        worked = entered.status;
    } else {
        worked = work(session_);
    }
    // Back to the motor menu even when the work failed: the next leg must find it open.
    Status back = leave_submenus();
    if (back) {
        back = enter_motor_menu("returning to the motor menu");
    }
    if (!back) {
        emit(log_, LogLevel::warning,
             "could not return to the motor menu from " + std::string(menu) + ": " + back.message);
        return back;
    }
    return worked;
}

Result<std::optional<NvsEntry>> MenuNavigator::read_nvs(int index) {
    if (Status left = leave_submenus(); !left) {
        return {std::nullopt, left};
    }
    const std::array<std::string, 2> steps{"nvs", build_nvs_dump(index)};
    std::optional<NvsEntry> entry;
    for (const auto& step : steps) {
        const auto reply = session_.transact(step, menu_step_timeout);
        if (!reply) {
            emit(log_, LogLevel::warning, "could not read NVS " + std::to_string(index) + ": " + reply.status.message);
            break;
        }
        for (const auto& line : reply.value.lines) {
            if (auto parsed = parse_g2_nvs_line(line); parsed && parsed->index == index) {
                entry = parsed;
            }
        }
    }
    if (session_.menu() == "nvs") {
        if (const auto left = session_.transact("q", menu_step_timeout); !left) {
            return {std::nullopt, left.status};
        }
    }
    if (Status back = enter_motor_menu("re-entering the motor menu"); !back) {
        return {std::nullopt, back};
    }
    return {entry, Status::ok()};
}

}  // namespace birdcage
