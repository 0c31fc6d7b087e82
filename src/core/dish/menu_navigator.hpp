// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Menu navigation on the dish console: from whatever menu the console is in to the root, into the
// motor menu (the variant's motor_menu_entry), and through the root into another submenu and back.
// `q` is sent only from a submenu whose prompt was seen (the session's hazard guard refuses the
// rest); where prompts are unknown, the upstream clients' idiom (`q`, a bare line ending) is used.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <string_view>

#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/span.hpp"
#include "console/session.hpp"
#include "firmware/protocol.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

class MenuNavigator {
public:
    MenuNavigator(ConsoleSession& session, const FirmwareProfile& profile, LogSink log);

    // Each step's command, then its settle time listening (pacing some firmware needs).
    Status run_steps(Span<const ConsoleStep> steps, std::string_view purpose);
    Status leave_submenus();
    Status enter_motor_menu(std::string_view purpose) { return run_steps(profile_.motor_menu_entry, purpose); }
    // Root, `menu`, `work` there, then back into the motor menu whatever `work` returned.
    Status visit(std::string_view menu, const std::function<Status(ConsoleSession&)>& work);
    // One NVS entry, read (never written) from the root's `nvs` menu; back in the motor menu after.
    // nullopt when the console did not show it.
    Result<std::optional<NvsEntry>> read_nvs(int index);

private:
    ConsoleSession& session_;
    const FirmwareProfile& profile_;
    LogSink log_;
};

}  // namespace birdcage
