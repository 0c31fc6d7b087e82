// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "pty.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>
#include <cerrno>
#include <cstdlib>
#include <system_error>

namespace birdcage::sim {
namespace {

[[noreturn]] void fail(const char* what) {
    throw std::system_error(errno, std::generic_category(), what);
}

}  // namespace

Pty::Pty() {
    // Close-on-exec: a program the tests start (rotctld, the probe) must not hold the dish's side.
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master_ < 0)
        fail("posix_openpt");
    try {
        if (::grantpt(master_) != 0)
            fail("grantpt");
        if (::unlockpt(master_) != 0)
            fail("unlockpt");
        char name[128];
        if (::ptsname_r(master_, name, sizeof name) != 0)
            fail("ptsname_r");
        slave_path_ = name;
        guard_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
        if (guard_ < 0)
            fail("open pty slave");
        termios attributes{};
        if (::tcgetattr(guard_, &attributes) != 0)
            fail("tcgetattr");
        ::cfmakeraw(&attributes);  // no echo or CR/LF translation by the tty layer itself
        if (::tcsetattr(guard_, TCSANOW, &attributes) != 0)
            fail("tcsetattr");
        const int flags = ::fcntl(master_, F_GETFL);
        if (flags < 0 || ::fcntl(master_, F_SETFL, flags | O_NONBLOCK) != 0)
            fail("fcntl O_NONBLOCK");
    } catch (...) {
        if (guard_ >= 0)
            ::close(guard_);
        ::close(master_);
        throw;
    }
}

Pty::~Pty() {
    ::close(guard_);
    ::close(master_);
}

}  // namespace birdcage::sim
