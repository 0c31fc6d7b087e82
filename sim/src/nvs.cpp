// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "nvs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace birdcage::sim {

NvsEntry* NvsTable::find(int index) {
    for (auto& entry : entries_)
        if (entry.index == index)
            return &entry;
    return nullptr;
}

const NvsEntry* NvsTable::find(int index) const {
    for (const auto& entry : entries_)
        if (entry.index == index)
            return &entry;
    return nullptr;
}

const NvsEntry* NvsTable::next_after(int index) const {
    for (const auto& entry : entries_)
        if (entry.index > index)
            return &entry;
    return entries_.empty() ? nullptr : &entries_.front();
}

void NvsTable::load_saved() {
    for (auto& entry : entries_)
        entry.current = entry.saved;
}

void NvsTable::save_all() {
    for (auto& entry : entries_)
        entry.saved = entry.current;
}

std::string NvsTable::format_value(const NvsEntry& entry, double value) {
    char text[48];
    switch (entry.kind) {
        case NvsEntry::Kind::boolean:
            return value != 0.0 ? "TRUE" : "FALSE";
        case NvsEntry::Kind::integer:
            std::snprintf(text, sizeof text, "%ld", std::lround(value));
            break;
        case NvsEntry::Kind::signed_integer:
            std::snprintf(text, sizeof text, "%+ld", std::lround(value));
            break;
        case NvsEntry::Kind::hex:
            std::snprintf(text, sizeof text, "0x%08lx", static_cast<unsigned long>(std::lround(value)));
            break;
        case NvsEntry::Kind::real:
            std::snprintf(text, sizeof text, "%.2f", value);
            break;
        case NvsEntry::Kind::real_mph:
            std::snprintf(text, sizeof text, "%.2f MPH", value);
            break;
    }
    return text;
}

std::optional<double> NvsTable::parse_value(const NvsEntry& entry, std::string_view text) {
    const std::string owned(text);
    if (entry.kind == NvsEntry::Kind::boolean) {
        if (owned == "TRUE" || owned == "true")
            return 1.0;
        if (owned == "FALSE" || owned == "false")
            return 0.0;
    }
    char* end = nullptr;
    const bool is_hex = owned.size() > 2 && owned[0] == '0' && (owned[1] == 'x' || owned[1] == 'X');
    const double value =
        is_hex ? static_cast<double>(std::strtoul(owned.c_str(), &end, 16)) : std::strtod(owned.c_str(), &end);
    if (owned.empty() || end == nullptr || *end != '\0')
        return std::nullopt;
    if (entry.kind == NvsEntry::Kind::boolean)
        return value != 0.0 ? 1.0 : 0.0;
    return value;
}

std::string NvsTable::header() {
    return "Num  Name                         Current      Saved      Default";
}

std::string NvsTable::rule() {
    return "---- --------------------------  ----------  ----------  ----------";
}

// The columns end at fixed places: a name longer than its 26 characters eats into the first
// value's field instead of pushing the row right (the captured dump's row 71, §6.3 / Appendix A).
std::string NvsTable::row(const NvsEntry& entry) {
    constexpr int first_value_end = 5 + 26 + 12;
    char text[160];
    const int name_end = std::snprintf(text, sizeof text, "%3d) %-26s", entry.index, entry.name.c_str());
    const std::string current = format_value(entry, entry.current);
    const int width = std::max(first_value_end - name_end, static_cast<int>(current.size()) + 1);
    std::snprintf(text + name_end, sizeof text - static_cast<std::size_t>(name_end), "%*s%12s%12s", width,
                  current.c_str(), format_value(entry, entry.saved).c_str(),
                  format_value(entry, entry.default_value).c_str());
    return text;
}

std::string NvsTable::edit_row(const NvsEntry& entry, double old_value) {
    char text[160];
    std::snprintf(text, sizeof text, "%3d) %-26s%11s .%11s", entry.index, entry.name.c_str(),
                  format_value(entry, old_value).c_str(), format_value(entry, entry.current).c_str());
    return text;
}

namespace {

NvsEntry same(int index, const char* name, NvsEntry::Kind kind, double value) {
    return {index, name, kind, value, value, value};
}

}  // namespace

// Appendix A: the captured dump of a 02.02.48 unit (sim/transcripts/captured/), which
// agrees with the predecessor's demo table except for the names of 75-77.
std::vector<NvsEntry> g2_nvs_table() {
    using K = NvsEntry::Kind;
    return {
        same(0, "Log ID's", K::hex, 7),
        same(1, "Log Device", K::hex, 1),
        same(2, "Debug 2nd Console Port", K::integer, 0),
        same(3, "Debug 2nd Packet Port", K::integer, 0),
        same(4, "Debug Port Connection", K::integer, 0),
        same(16, "Pitch Deadband", K::real, 0),
        same(17, "Roll Deadband", K::real, 0),
        same(18, "Yaw Deadband", K::real, 0),
        {20, "Disable Tracker Proc?", K::boolean, 1, 1, 0},
        same(21, "Tracker Proc Run Mode", K::integer, 0),
        same(22, "Conical Alpha Az", K::integer, 200),
        same(23, "Conical Alpha El", K::integer, 200),
        same(24, "Conical Radius", K::real, 1),
        same(25, "Conical Count Max", K::integer, 20),
        same(26, "Conical Test Drift", K::signed_integer, 0),
        same(27, "Circle RPM", K::integer, 120),
        same(28, "Circle Pts/Rev", K::integer, 6),
        same(32, "Conical Az Clamp", K::real, 8),
        same(33, "Conical El Clamp", K::real, 8),
        same(35, "Motor Pts/Rev", K::integer, 72),
        same(36, "Circle Az Radius", K::real, 1),
        same(37, "Circle El Radius", K::real, 1),
        same(38, "Sleep Mode Timer Secs", K::integer, 420),
        same(40, "Motor Type", K::integer, 0),
        same(41, "Satellite Scan Velocity", K::real, 55),
        same(48, "Motor Spiral Velocity", K::real, 55),
        same(49, "Motor Gear Ratio", K::hex, 0),
        same(63, "GPS Heading Threshold", K::real, 1),
        same(64, "GPS Moving Threshold", K::real_mph, 5),
        same(66, "Spiral Signal In A Row Min", K::signed_integer, 3),
        same(67, "Spiral Signal In A Row Max", K::signed_integer, 20),
        same(68, "Signal Odd to Even Offset", K::signed_integer, 0),
        same(69, "Signal Offset", K::integer, 80),
        same(70, "Signal Baseline Angle", K::real, 65),
        same(71, "Signal Re-Peak Degrade Percent", K::integer, 25),
        same(72, "Gyro Sensitivity", K::signed_integer, 1110),
        same(73, "Gyro Filter Size", K::signed_integer, 1),
        same(74, "Gyro Calib Readings", K::integer, 100),
        same(75, "Gyro Mount Type", K::integer, 1),
        same(76, "Gyro Velocity Offset", K::integer, 4),
        same(77, "Gyro Max Accel", K::integer, 600),
        same(80, "AZ Max Vel", K::real, 65),
        same(81, "AZ Max Accel", K::real, 400),
        same(82, "AZ Home Velocity", K::real, 55),
        same(83, "AZ Steps/Rev", K::integer, 40000),
        same(84, "AZ Direction", K::signed_integer, 1),
        same(85, "EL Max Vel", K::real, 45),
        same(86, "EL Max Accel", K::real, 400),
        same(87, "EL Home Velocity", K::real, 45),
        same(88, "EL Steps/Rev", K::integer, 24960),
        same(89, "EL Direction", K::signed_integer, 1),
        same(95, "AZ Low current limit", K::hex, 0xff0c),
        same(96, "AZ High current limit", K::hex, 0xff30),
        same(97, "EL Low current limit", K::hex, 0xff0c),
        same(98, "EL High current limit", K::hex, 0xff40),
        same(101, "Minimum Elevation Angle", K::real, 18),
        same(102, "Maximum Elevation Angle", K::real, 65),
        same(103, "Elevation Home Angle", K::real, 65),
        same(106, "Az Stall Detect", K::integer, 78),
        same(107, "El Stall Detect", K::integer, 75),
        same(108, "Az Stall Samples", K::integer, 100),
        same(109, "El Stall Samples", K::integer, 100),
        same(110, "EL Home Current Limit", K::hex, 0xff28),
        same(111, "AZ Home Current Limit", K::hex, 0xff40),
        same(112, "Disable Dipswitch?", K::boolean, 0),
        same(113, "Dipswitch Value", K::integer, 101),
        same(114, "Dipswitch Front/Rear Mount", K::integer, 0),
        same(115, "Mount Offset Angle", K::signed_integer, 0),
        same(118, "Signal Use LNB Clamp", K::boolean, 0),
        same(128, "AZ PID Kp", K::signed_integer, 600),
        same(129, "AZ PID Kv", K::signed_integer, 60),
        same(130, "AZ PID Ki", K::signed_integer, 1),
        same(131, "EL PID Kp", K::signed_integer, 250),
        same(132, "EL PID Kv", K::signed_integer, 50),
        same(133, "EL PID Ki", K::signed_integer, 1),
        same(136, "AZ PWM Stall Cnt", K::integer, 6),
        same(137, "EL PWM Stall Cnt", K::integer, 5),
        same(143, "Tracking Number", K::integer, 0),
    };
}

// §3.3: only the indices are known (125 search minimum EL, 127 safe minimum EL); names and
// the 15 deg default (§3.4 "doesn't like to go below 15") are INVENTED.
std::vector<NvsEntry> travler_nvs_table() {
    using K = NvsEntry::Kind;
    return {same(125, "Search Minimum Elevation", K::real, 15), same(127, "Safe Minimum Elevation", K::real, 15)};
}

// §5.3/§5.4: the Pro's indices are unknown (§14 Pro.4); the Trav'ler's are reused with the
// Pro's 12 deg floor. INVENTED.
std::vector<NvsEntry> travler_pro_nvs_table() {
    using K = NvsEntry::Kind;
    return {same(125, "Search Minimum Elevation", K::real, 12), same(127, "Safe Minimum Elevation", K::real, 12)};
}

// §8.3: NVS 102 = maximum elevation, default 73. Name INVENTED (taken from the G2's row).
std::vector<NvsEntry> carryout2003_nvs_table() {
    using K = NvsEntry::Kind;
    return {same(102, "Maximum Elevation Angle", K::real, 73)};
}

}  // namespace birdcage::sim
