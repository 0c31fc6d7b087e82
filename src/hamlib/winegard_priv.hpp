// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// What the C++ halves of the backend share: the per-rotator state Hamlib keeps in
// rot_state->priv, the guard every C entry point runs in, the error and log mapping onto Hamlib's,
// and the port link (intree/hamlib_port.cpp in a Hamlib tree, preload/fd_port.cpp in the preload
// build). winegard_ops.cpp holds the operations, winegard_conf.cpp the conf parameters and the
// ext-level table.
#pragma once

#if __cplusplus < 201703L
#error "the Winegard backend is C++17 (configure --with-winegard checks for it)"
#endif

#include "winegard.h"

#include "base/errors.hpp"
#include "console/transport.hpp"
#include "dish/controller.hpp"
#include "dish/receiver.hpp"
#include "firmware/variants.hpp"
#include "service/rotator_service.hpp"
#include "service/service_worker.hpp"
#include "tracking/mount_model.hpp"
#include "tracking/steering.hpp"

#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>

namespace birdcage::hamlib {

struct WinegardPriv {
    ControllerOptions options;
    PointingOptions pointing;  // mode unset: the variant's default
    MountModel mount;          // aligned until the conf says otherwise
#if defined(BIRDCAGE_PRELOAD)
    double time_scale = 1.0;  // emulator runs only: the backend's clock runs this many times faster
#endif
    int rssi_samples = rssi_default_samples;  // ext level RSSI_SAMPLES
    std::unique_ptr<RotatorService> service;
    std::string info;
};

// Hamlib's state of a rotator (nullptr where master has not allocated it).
inline struct rot_state* state_of(ROT* rot) {
    return ROTSTATE(rot);
}

// The backend's state of an initialised rotator. Throws (the guard turns it into -RIG_EINVAL) for a
// rotator rot_init did not set up.
inline WinegardPriv& priv_of(ROT* rot) {
    struct rot_state* state = rot != nullptr ? state_of(rot) : nullptr;
    if (state == nullptr || state->priv == nullptr) {
        throw std::invalid_argument("not a Winegard rotator set up by rot_init");
    }
    return *static_cast<WinegardPriv*>(state->priv);
}

// Every C entry point runs its body in here: whatever the C++ below throws becomes a -RIG_E* code
// and a log line, never an exception unwinding into Hamlib's C (which would end the process).
template <class Body>
int guarded(const char* where, Body&& body) noexcept {
    try {
        return body();
    } catch (const std::bad_alloc&) {
        rot_debug(RIG_DEBUG_ERR, "winegard: %s: out of memory\n", where);
        return -RIG_ENOMEM;
    } catch (const std::invalid_argument& e) {
        rot_debug(RIG_DEBUG_ERR, "winegard: %s: %s\n", where, e.what());
        return -RIG_EINVAL;
    } catch (const std::exception& e) {
        rot_debug(RIG_DEBUG_BUG, "winegard: %s: internal error: %s\n", where, e.what());
        return -RIG_EINTERNAL;
    } catch (...) {
        rot_debug(RIG_DEBUG_BUG, "winegard: %s: internal error\n", where);
        return -RIG_EINTERNAL;
    }
}

// The extension levels' tokens (winegard_ext_levels).
enum ExtLevelToken : int { tok_rssi = 101, tok_rssi_samples = 102, tok_lnb_volts = 103 };

// A line for Hamlib's debug log.
void say(rig_debug_level_e level, const std::string& text);

// Logs a failed status with where it failed and returns the Hamlib error for it.
int report(const char* where, const Status& status);

// The variant row a model's caps name (rot_caps.priv: "auto", "hal205", ...); nullptr if none.
const FirmwareProfile* profile_for_caps(const struct rot_caps& caps);

// The console's transport over the port Hamlib opened, and how to open it again after a hang-up.
struct PortLink {
    std::unique_ptr<Transport> transport;
    TransportFactory reopen;
};
Result<PortLink> open_port_link(ROT* rot);

#if defined(BIRDCAGE_PRELOAD)
// A note logged at open, set by the preload build when the running Hamlib is another release of
// the build's ABI.
std::string& load_note();
#endif

}  // namespace birdcage::hamlib
