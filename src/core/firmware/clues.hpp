// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What identifies each variant on its console, for auto-detection (console/detect.hpp): the clues
// its output may show and the harmless probes that tell apart the variants the clues do not.
#pragma once

#include <string_view>

#include "base/span.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

// Auto-detection evidence: each clue, when seen, adds `weight` to one variant's score
// (console/evidence.cpp ranks the scores). Text is matched case-insensitively: a boot line
// containing it, a prompt equal to it, or a command word a `?` listing shows (full weight where the
// listing puts it in a command's place, a third of it where it only appears in a description).
enum class ClueSource { boot_line, prompt, help_command };
struct DetectionClue {
    ClueSource source;
    std::string_view text;
    VariantId variant;
    int weight;
};
Span<const DetectionClue> detection_clues();

// Auto-detection probes, tried in table order where the evidence above does not decide
// (console/detect.cpp): enter a motor menu some variant has, then ask the position. Both commands are harmless on every
// variant (an unknown command at worst; the query has no arguments, so it never moves), and the
// variants answer them differently. After a probe that entered a menu, `q` leaves it (docs/firmware.md 2).
enum class ProbeAnswer {
    any,               // not documented: the answer rules nothing in or out
    nothing,           // no position (an unknown command at this variant's root)
    travler_position,  // `AZ = <f> EL = <f> ...` (docs/firmware.md 3.3)
    g2_position,       // `Angle[0] = <f>` (docs/firmware.md 6.3)
};
struct ProbeExpectation {
    VariantId variant;
    ProbeAnswer answer;  // from this variant's root
};
struct DetectionProbe {
    std::string_view enter;  // a menu command
    std::string_view query;  // asked inside it
    Span<const ProbeExpectation> expected;
};
Span<const DetectionProbe> detection_probes();

}  // namespace birdcage
