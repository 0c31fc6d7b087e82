// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Pure protocol: command builders, reply parsers and the hazard guard's rules. No I/O, no clock.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "base/azel.hpp"
#include "base/errors.hpp"
#include "base/plain_types.hpp"
#include "base/span.hpp"
#include "firmware/hazards.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

// ---- number formatting -------------------------------------------------------------------------

// Fixed two decimals ("180.00"): never exponent form, never "-0.00". Requires a finite value.
std::string format_degrees(double degrees);

// ---- command builders --------------------------------------------------------------------------

std::string build_axis_move(Axis axis, double degrees);  // "a 0 180.00"
std::string build_combined_move(AzEl target);            // "g 180.00 45.00"
std::string build_nvs_dump(int index);                   // "d 20"  (G2 NVS>)
std::string build_rssi(int samples);                     // "rssi 10" (G2 DVB>)

// ---- reply parsers -----------------------------------------------------------------------------
// Each parser takes the reply lines (echo and prompt already removed). A reply that does not
// contain every required field is an error: garbage never produces a position.

// Trav'ler: `AZ = <f>` and `EL = <f>` (SK optional), optional sign, any whitespace or line layout.
Result<AzEl> parse_travler_position(Span<const std::string> lines);

// G2: `Angle[0] = <f>` and `Angle[1] = <f>`. The INT_MAX sentinel of unhomed axes -> Errc::not_homed.
Result<AzEl> parse_g2_position(Span<const std::string> lines);

// G2 move acknowledgement `Angle = <f>`.
Result<double> parse_g2_move_ack(Span<const std::string> lines);

// Carryout 2003 live output while `g` runs: `... <azcdeg>   el = <elcdeg>` (docs/firmware.md 8.4).
// Returns the last complete sample among the lines.
Result<AzEl> parse_carryout_live(Span<const std::string> lines);

// Dispatches on profile.position_format.
Result<AzEl> parse_position(const FirmwareProfile& profile, Span<const std::string> lines);

struct NvsEntry {
    int index = -1;
    std::string name;
    std::string current, saved, default_value;
};
// One G2 `d <idx>` table line: ` 20) Disable Tracker Proc?            FALSE       FALSE       FALSE`.
std::optional<NvsEntry> parse_g2_nvs_line(std::string_view line);

struct RssiReading {
    int reads = 0;
    int average = 0;
    int current = 0;
};
// G2 `rssi <n>` body: `iterations:<n>  interval(msec):20` / ` Reads:<n>  RSSI[avg: <v>  cur: <v>]`.
Result<RssiReading> parse_g2_rssi(Span<const std::string> lines);

// The LNB supply in a G2 DVB `dis` table (a one-shot listing of the channel parameters): its row
// `5    LNB Polarity         ODU:13V                  ---` (the real console, firmware 02.02.48),
// 13 V or 18 V in the row's current value. Errc::protocol when no such row names either.
Result<LnbSupply> parse_g2_lnb_polarity(Span<const std::string> lines);

// ---- hazard guard rules ------------------------------------------------------------------------

// What the session knows when it decides whether a command may be sent.
struct HazardContext {
    std::string_view menu;  // "root", "mot", "nvs", ... ; empty = unknown
    bool allow_nvs_write = false;
    bool axes_unhomed = false;  // a position reply showed the INT_MAX sentinel
    // What the caller asks for (hazards.hpp): nothing by default, so a caller that forgets to say
    // gets a console it cannot move.
    HazardRequests requests = request_nothing;
};

// Ok, or Errc::hazard / Errc::not_homed naming the hazard. The rule is hazards.hpp's
// (docs/firmware.md §15), judged for the profile's variant (every variant's rules while it is the
// auto-detect profile) with `context.requests`, plus request_nvs_write where allow_nvs_write says
// so. A move the caller asked for is still refused (Errc::not_homed) while the axes are unhomed.
Status hazard_check(const FirmwareProfile& profile, std::string_view command, const HazardContext& context);

// The menu a prompt stands for: the profile's root prompt -> "root", `EE>` -> "eeprom",
// otherwise the lower-cased word ("MOT>" -> "mot"). Empty for an empty prompt.
std::string menu_for_prompt(const FirmwareProfile& profile, std::string_view prompt);

}  // namespace birdcage
