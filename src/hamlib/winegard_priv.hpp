// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What the two C++ halves of the backend share: the per-rotator state Hamlib keeps in
// rot_state->priv, and the error and log mapping onto Hamlib's. winegard_ops.cpp holds the
// operations, winegard_conf.cpp the conf parameters and the ext-level table.
#pragma once

#include "hamlib_compat.h"

#include "base/errors.hpp"
#include "dish/controller.hpp"
#include "dish/receiver.hpp"
#include "firmware/variants.hpp"
#include "service/rotator_service.hpp"
#include "tracking/mount_model.hpp"
#include "tracking/steering.hpp"

#include <array>
#include <memory>
#include <string>

namespace birdcage::hamlib {

struct WinegardPriv {
    ControllerOptions options;
    PointingOptions pointing;                 // mode unset: the variant's default
    MountModel mount;                         // aligned until the conf says otherwise
    double time_scale = 1.0;                  // emulator runs only: the backend's clock runs this many times faster
    int rssi_samples = rssi_default_samples;  // ext level RSSI_SAMPLES
    std::unique_ptr<RotatorService> service;
    std::string info;
};

// The variants registered as Hamlib models, besides the auto-detecting one (probe_profile()).
inline constexpr std::array registered_variants = {
    VariantId::travler_hal000, VariantId::travler_hal205, VariantId::travler_pro,
    VariantId::carryout2003,   VariantId::carryout_g2,
};

inline WinegardPriv* priv_of(ROT* rot) {
    return static_cast<WinegardPriv*>(WG_ROTSTATE(rot)->priv);
}

// The extension levels' tokens (winegard_ext_levels).
enum ExtLevelToken : int { tok_rssi = 101, tok_rssi_samples = 102, tok_lnb_volts = 103 };

// A line for Hamlib's debug log, also on stderr when it is a warning or an error that Hamlib's
// level would hide.
void say(rig_debug_level_e level, const std::string& text);

// Logs a failed status with where it failed and returns the Hamlib error for it.
int report(const char* where, const Status& status);

// The profile of the variant a Winegard model number stands for; nullptr if none.
const FirmwareProfile* profile_for_model(rot_model_t model);

// A note logged at open, set by the preload build when the running Hamlib is another release of
// the build's ABI; empty in a Hamlib tree.
std::string& load_note();

}  // namespace birdcage::hamlib
