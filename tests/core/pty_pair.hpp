// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A pseudo-terminal for transport tests: the test holds the master (the dish's end) and opens
// slave_path as the backend would. hang_up() closes the master, as an unplugged adapter does.
// Test-local, shared by tests/core and tests/hamlib.
#pragma once

#include <catch2/catch.hpp>

#include <cstdlib>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace birdcage::testing {

struct Pty {
    int master = -1;
    std::string slave_path;
    Pty() {
        master = ::posix_openpt(O_RDWR | O_NOCTTY);
        REQUIRE(master >= 0);
        REQUIRE(::grantpt(master) == 0);
        REQUIRE(::unlockpt(master) == 0);
        slave_path = ::ptsname(master);
    }
    ~Pty() { hang_up(); }
    void hang_up() {
        if (master >= 0) {
            ::close(master);
            master = -1;
        }
    }
    Pty(const Pty&) = delete;
    Pty& operator=(const Pty&) = delete;
};

}  // namespace birdcage::testing
