// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The clue and probe tables. Each fact cites a section (n.n) of the compiled docs/firmware.md.
#include "firmware/clues.hpp"

#include <array>

namespace birdcage {
namespace {

// Weights: a command found on one variant's root only, or a boot line only one firmware prints, is
// decisive (>= 4, winning_score in console/evidence.hpp); shapes other firmware may share (the
// `TRK>` prompt, `mot`/`os` at a root, `NoGPS` on both Trav'ler HALs) only tip the balance.
using V = VariantId;
using S = ClueSource;
constexpr std::array<DetectionClue, 37> clues{{
    // Boot lines (3.2, 4.2, 6.2).
    {S::boot_line, "Bootloader v", V::carryout_g2, 4},
    {S::boot_line, "Ant ID -", V::carryout_g2, 4},
    {S::boot_line, "12-IN G2", V::carryout_g2, 4},
    {S::boot_line, "Motor init:", V::carryout_g2, 3},
    {S::boot_line, "Antenna Facing", V::carryout_g2, 3},
    {S::boot_line, "Boot Complete", V::carryout_g2, 3},
    {S::boot_line, "Loc Startup:", V::carryout_g2, 3},
    {S::boot_line, "EXTENDED_DVB_DEBUG", V::carryout_g2, 3},
    {S::boot_line, "BCM4515", V::carryout_g2, 3},
    {S::boot_line, "No LNB Voltage", V::travler_hal205, 4},
    {S::boot_line, "NoGPS", V::travler_hal000, 1},
    {S::boot_line, "NoGPS", V::travler_hal205, 1},
    // Prompts (6.3): the G2's submenu prompts are documented; its root shape may be shared.
    {S::prompt, "TRK>", V::carryout_g2, 1},
    {S::prompt, "A3981>", V::carryout_g2, 4},
    {S::prompt, "EE>", V::carryout_g2, 4},
    {S::prompt, "DIPSWITCH>", V::carryout_g2, 4},
    {S::prompt, "LATLON>", V::carryout_g2, 4},
    {S::prompt, "GPIO>", V::carryout_g2, 4},
    {S::prompt, "PEAK>", V::carryout_g2, 3},
    {S::prompt, "STEP>", V::carryout_g2, 3},
    {S::prompt, "ADC>", V::carryout_g2, 3},
    // Root listings (3.3, 4.3, 5.3, 6.3, 8.3).
    {S::help_command, "a3981", V::carryout_g2, 5},
    {S::help_command, "dipswitch", V::carryout_g2, 3},
    {S::help_command, "latlon", V::carryout_g2, 3},
    {S::help_command, "adc", V::carryout_g2, 2},
    {S::help_command, "eeprom", V::carryout_g2, 2},
    {S::help_command, "gpio", V::carryout_g2, 2},
    {S::help_command, "peak", V::carryout_g2, 2},
    {S::help_command, "step", V::carryout_g2, 2},
    {S::help_command, "odu", V::travler_pro, 6},
    {S::help_command, "target", V::carryout2003, 6},
    {S::help_command, "ngsearch", V::travler_hal205, 6},
    {S::help_command, "motor", V::travler_hal205, 3},  // its motor menu (4.3); HAL 2.05 may list mot too
    {S::help_command, "mot", V::travler_hal000, 2},
    {S::help_command, "os", V::travler_hal000, 1},
    {S::help_command, "nvs", V::travler_hal000, 1},
    {S::help_command, "stow", V::travler_hal000, 1},
}};

// Probes, most telling first: `motor` alone separates the two Trav'ler HALs, which share `NoGPS`.
// What a variant answers from its root: 3.3/4.3 (Trav'ler motor menus), 5.3 (the Pro's IDU has
// only `odu`; behind it the HAL 0.0.00 root), 6.3 (the G2 has no `motor`), 8.3 (the 2003 Carryout's
// `motor` menu exists but its commands are unknown). Unknown answers are `any`, never a guess.
using A = ProbeAnswer;
constexpr std::array<ProbeExpectation, 5> motor_probe{{{V::travler_hal000, A::nothing},
                                                       {V::travler_hal205, A::travler_position},
                                                       {V::travler_pro, A::nothing},
                                                       {V::carryout2003, A::any},
                                                       {V::carryout_g2, A::nothing}}};
constexpr std::array<ProbeExpectation, 5> mot_probe{{{V::travler_hal000, A::travler_position},
                                                     {V::travler_hal205, A::any},  // 14 HAL2.05.4
                                                     {V::travler_pro, A::any},     // IDU or ODU root
                                                     {V::carryout2003, A::nothing},
                                                     {V::carryout_g2, A::g2_position}}};
constexpr std::array<DetectionProbe, 2> probes{{{"motor", "a", motor_probe}, {"mot", "a", mot_probe}}};

}  // namespace

Span<const DetectionClue> detection_clues() {
    return clues;
}

Span<const DetectionProbe> detection_probes() {
    return probes;
}

}  // namespace birdcage
