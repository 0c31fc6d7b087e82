// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "dish/receiver.hpp"

#include <cmath>

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto receiver_command_timeout = 2000ms;

Status require_receiver(const Controller& controller) {
    if (controller.profile().receiver_menu.empty()) {
        return {Errc::unsupported, std::string(controller.profile().display_name) + " has no satellite tuner"};
    }
    return Status::ok();
}

}  // namespace

std::string build_lnb_supply(LnbSupply supply) {
    return supply == LnbSupply::odu_13v ? "lnbdc odu" : "lnbdc stb";
}

int lnb_volts(LnbSupply supply) {
    return supply == LnbSupply::odu_13v ? 13 : 18;
}

Result<LnbSupply> lnb_supply_from_volts(double volts) {
    if (!std::isfinite(volts) || volts < 13.0 || volts > 18.0) {
        return {{}, Status{Errc::invalid_argument, "the LNB supply is 13 or 18 V"}};
    }
    return {volts < 15.5 ? LnbSupply::odu_13v : LnbSupply::stb_18v, Status::ok()};
}

std::chrono::milliseconds rssi_timeout(int samples) {
    return samples * 20ms + receiver_command_timeout;
}

Result<RssiReading> read_signal(Controller& controller, int samples) {
    if (Status usable = require_receiver(controller); !usable) {
        return {{}, usable};
    }
    if (samples < 1 || samples > rssi_max_samples) {
        return {{}, Status{Errc::invalid_argument, "RSSI samples must be 1.." + std::to_string(rssi_max_samples)}};
    }
    Result<RssiReading> reading{{}, Status{Errc::protocol, "no reading"}};
    const Status done = controller.in_submenu(controller.profile().receiver_menu, [&](ConsoleSession& session) {
        const auto reply = session.transact(build_rssi(samples), rssi_timeout(samples));
        if (!reply) {
            return reply.status;
        }
        reading = parse_g2_rssi(reply.value.lines);
        return reading.status;
    });
    if (!done) {
        return {{}, done};
    }
    return reading;
}

Status apply_lnb_supply(Controller& controller, LnbSupply supply) {
    if (Status usable = require_receiver(controller); !usable) {
        return usable;
    }
    return controller.in_submenu(controller.profile().receiver_menu, [&](ConsoleSession& session) {
        // The firmware prints nothing we could check (docs/firmware.md 14, question 9): the prompt is the answer.
        return session.transact(build_lnb_supply(supply), receiver_command_timeout).status;
    });
}

Result<LnbSupply> read_lnb_supply(Controller& controller) {
    if (Status usable = require_receiver(controller); !usable) {
        return {{}, usable};
    }
    Result<LnbSupply> supply{{}, Status{Errc::protocol, "no reading"}};
    const Status done = controller.in_submenu(controller.profile().receiver_menu, [&](ConsoleSession& session) {
        const auto reply = session.transact("dis", receiver_command_timeout);
        if (!reply) {
            return reply.status;
        }
        supply = parse_g2_lnb_polarity(reply.value.lines);
        return supply.status;
    });
    if (!done) {
        return {{}, done};
    }
    return supply;
}

}  // namespace birdcage
