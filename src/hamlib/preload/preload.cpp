// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The preload build's entry: a constructor that registers the Winegard models in whatever Hamlib
// the process already runs (stock rotctld/rotctl), after checking that it is one this build can
// live in. A Hamlib tree calls initrots<ABI>_winegard itself and has none of this.
#include "hamlib_abi.hpp"
#include "winegard.h"
#include "winegard_priv.hpp"

#include <dlfcn.h>
#include <climits>
#include <cstdio>
#include <cstdlib>

extern "C" int initrots4_winegard(void* be_handle);

namespace {

// The soname major of the libhamlib that provides rot_register in this process (the one the
// models would be registered with), 0 if it cannot be told.
int running_hamlib_soname() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&rot_register), &info) == 0 || info.dli_fname == nullptr) {
        return 0;
    }
    char resolved[PATH_MAX];
    const char* path = ::realpath(info.dli_fname, resolved) != nullptr ? resolved : info.dli_fname;
    return birdcage::hamlib::soname_major(path).value_or(0);
}

// Hamlib's debug level starts at TRACE before the program sets it, so rot_register() would print
// on every program start that inherits LD_PRELOAD. Register silently, then restore the level.
rig_debug_level_e current_debug_level() {
    int level = RIG_DEBUG_NONE;
    for (int l = RIG_DEBUG_BUG; l <= RIG_DEBUG_CACHE; ++l) {
        if (rig_need_debug(static_cast<rig_debug_level_e>(l))) {
            level = l;
        }
    }
    return static_cast<rig_debug_level_e>(level);
}

__attribute__((constructor)) void winegard_preload_register() {
    // Registering caps built for another Hamlib ABI would let Hamlib write through a struct s_rot
    // of another shape: refuse before touching anything, in one line naming both.
    const birdcage::hamlib::AbiVerdict abi =
        birdcage::hamlib::check_abi(BIRDCAGE_HAMLIB_BUILT_VERSION, BIRDCAGE_HAMLIB_BUILT_SONAME,
                                    hamlib_version2 != nullptr ? hamlib_version2 : "", running_hamlib_soname());
    if (!abi.compatible) {
        std::fprintf(
            stderr,
            "hamlib-winegard: %s; the Winegard models are not registered (rebuild the backend for this Hamlib)\n",
            abi.message.c_str());
        return;
    }
    birdcage::hamlib::load_note() = abi.message;
    const rig_debug_level_e saved = current_debug_level();
    rig_set_debug(RIG_DEBUG_NONE);
    const int rc = initrots4_winegard(nullptr);
    rig_set_debug(saved);
    if (rc != RIG_OK) {
        std::fprintf(stderr, "hamlib-winegard: model registration failed (%s); is model family %d taken?\n",
                     rigerror(rc), ROT_WINEGARD);
    }
}

}  // namespace
