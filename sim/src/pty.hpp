// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Pseudo-terminal pair whose master end plays the dish.
#pragma once

#include <string>

namespace birdcage::sim {

class Pty {
public:
    Pty();  // throws std::system_error
    ~Pty();
    Pty(const Pty&) = delete;
    Pty& operator=(const Pty&) = delete;

    int master() const { return master_; }
    const std::string& slave_path() const { return slave_path_; }

private:
    int master_ = -1;
    // Held open for the emulator's lifetime: while any slave fd exists the master never sees
    // EIO/HUP, so clients (rotctld) may close and reopen the device freely.
    int guard_ = -1;
    std::string slave_path_;
};

}  // namespace birdcage::sim
