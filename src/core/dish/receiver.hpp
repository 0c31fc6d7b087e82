// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The dish as a receiver: signal strength and LNB supply from the satellite tuner's menu
// (G2 `DVB>`, docs/firmware.md 6.3). Variants without a tuner (FirmwareProfile::receiver_menu empty)
// answer Errc::unsupported.
//
// Only single-shot commands are ever sent here: `rssi <n>`, `lnbdc odu|stb` and `dis`. The tuner's
// streaming commands (`agc`, `lnbv`, `snr`, `nid`) and the ADC menu's `m` and argument-less `scan`
// never end or deadlock the console (docs/firmware.md 6.5), so no function builds them.
#pragma once

#include <chrono>
#include <string>

#include "base/errors.hpp"
#include "base/plain_types.hpp"
#include "dish/controller.hpp"
#include "firmware/protocol.hpp"

namespace birdcage {

inline constexpr int rssi_default_samples = 10;  // what the upstream scanners send (docs/firmware.md 6.6)
// At 20 ms a sample the reading blocks the console for samples x 20 ms; 100 keeps it at 2 s, well
// inside the position's freshness limit (ServiceTiming::max_position_age).
inline constexpr int rssi_max_samples = 100;

std::string build_lnb_supply(LnbSupply supply);  // "lnbdc odu" / "lnbdc stb"
int lnb_volts(LnbSupply supply);                 // 13 / 18
// 13 and 18 (and the values in between rounded to the nearer); anything else is invalid.
Result<LnbSupply> lnb_supply_from_volts(double volts);

// How long a `rssi <samples>` reply may take: the samples at 20 ms each, plus the console's margin.
std::chrono::milliseconds rssi_timeout(int samples);

// Both run on the controller's thread between legs (RotatorService does the scheduling): they
// leave the motor menu for the tuner's menu and return to it, whatever the outcome.
Result<RssiReading> read_signal(Controller& controller, int samples);
Status apply_lnb_supply(Controller& controller, LnbSupply supply);
// Reads the LNB supply the tuner is set to from its one-shot `dis` listing (parse_g2_lnb_polarity),
// so that what the backend reports after open is the dish's, not an assumption.
Result<LnbSupply> read_lnb_supply(Controller& controller);

}  // namespace birdcage
