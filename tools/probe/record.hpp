// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe record: a pass-through terminal that tees the session into a transcript
// (docs/transcripts.md), each typed line judged by the hazard rule before it goes out.
#pragma once

#include <optional>
#include <string>

#include "firmware/variants.hpp"

namespace probe {

int run_record(const std::string& path, int baud, const birdcage::FirmwareProfile& profile,
               std::optional<birdcage::VariantId> rule_variant, bool force_fd, bool force, const std::string& output,
               const std::string& source);

}  // namespace probe
