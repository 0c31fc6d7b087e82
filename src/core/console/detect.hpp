// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Firmware auto-detection at open: identifies the variant from any evidence the console offers
// (boot and version lines, prompt shapes, `?` listings in any layout), ranks it per candidate, and
// never sends a documented hazard: no moves, no NVS access, and `q` only where a submenu was
// positively recognised (see detect.cpp). What the evidence says is read in console/evidence.hpp.
#pragma once

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "base/log.hpp"
#include "console/evidence.hpp"
#include "console/transport.hpp"
#include "firmware/variants.hpp"

namespace birdcage {

struct Detection {
    VariantId variant{};
    std::string evidence;  // what identified it, for get_info and the debug log
    // The console looked like the root of `variant`, which this other variant's inner console also
    // looks like (FirmwareProfile::also_shown_inside: a Trav'ler Pro left inside its ODU console):
    // the caller should keep within that variant's limits too.
    std::optional<VariantId> maybe_inside;
};

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout);

}  // namespace birdcage
