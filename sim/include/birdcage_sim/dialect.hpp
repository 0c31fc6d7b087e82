// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The dialect generator: from a seed, a plausible console for a variant in every respect
// docs/firmware.md leaves open (§14), with what the notes document held fixed. The grammar is
// described in sim/README.md, "Dialects". A seed reproduces a console byte for byte.
#pragma once

#include <cstdint>
#include <string>

#include "birdcage_sim/emulator.hpp"

namespace birdcage::sim {

struct Dialect {
    Options options;          // variant, seed and every drawn switch; the rest at their defaults
    std::string description;  // what was drawn, one `name: value` per line
};

// Pure: the same (variant, seed) gives the same Dialect. Options::seed is set to `seed` too.
Dialect draw_dialect(Variant variant, std::uint32_t seed);

// The description plus the console it makes: the boot log with simulated timestamps and the
// root `?` listing, as the dish would print them (escaped like --trace).
std::string describe_console(const Dialect& dialect);

}  // namespace birdcage::sim
