// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The load-time check that the running Hamlib is one this backend's build can live in. Plain C++
// (no Hamlib header), so that the rule is unit-tested without a Hamlib to load.
//
// What breaks: a different soname major (Hamlib master, libhamlib.so.5, moved the rotator state
// and ports out of struct s_rot, so a 4.x build would write its private pointer into the wrong
// memory); a different version major; and an older minor than the build's (a 4.6+ build calls
// rot_data_pointer(), which 4.5 lacks). A newer minor of the same soname keeps struct s_rot and
// rot_caps as they were (measured: the same offsets in 4.5.4, 4.6 and 4.7), so it is accepted.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace birdcage::hamlib {

struct Version {
    int major = 0;
    int minor = 0;
    int patch = 0;
};

// "4.5.4", "Hamlib 4.6.2 2025-01-01T00:00:00Z SHA=..." or "5.0.0~git": the first N.N[.N].
std::optional<Version> parse_version(std::string_view text);

// The N of the first ".so.N" in a library path or name (libhamlib.so.4.0.6 -> 4); nullopt if none.
std::optional<int> soname_major(std::string_view path);

struct AbiVerdict {
    bool compatible = false;
    std::string message;  // one line naming both Hamlibs; empty when they are the same release
};

// built_*: what the backend was compiled against (pkg-config's version, the linked library's
// soname major, 0 if unknown); running_*: hamlib_version2 and the soname of the library that
// provides rot_register in this process (0 if unknown).
AbiVerdict check_abi(std::string_view built_version, int built_soname, std::string_view running_version,
                     int running_soname);

}  // namespace birdcage::hamlib
