// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Holding a serial port for one program, the way serial programs on Debian do: a UUCP-style lock
// file (`/run/lock/LCK..<device>` with the holder's PID in HDB format: ten right-aligned digits and a
// newline; a file whose PID is gone is stale and replaced), an exclusive flock() on the device, and
// TIOCEXCL once the port is open. Because programs that take no lock (stock rotctld opening a port
// itself) exist, it also looks through /proc for any other process that has the device open.
#pragma once

#include <sys/types.h>
#include <string>
#include <vector>

#include "base/errors.hpp"

namespace birdcage {

struct PortHolder {
    pid_t pid = 0;
    std::string program;  // /proc/<pid>/comm, when readable
};

// Processes other than this one that have `device` open, read from /proc/*/fd. A process that
// holds the master side of the same pty (the dish emulator, which keeps the slave open as well) is
// the other end of the line, not a competing user, and is left out.
std::vector<PortHolder> other_port_holders(const std::string& device);

// The lock file's name for a device: `LCK..ttyUSB0`; a device below a subdirectory of /dev gets
// its path with `/` as `_` (`LCK..pts_3`).
std::string lock_file_name(const std::string& device);

class PortLock {
public:
    // Takes the lock file in `lock_dir` (empty: $BIRDCAGE_LOCK_DIR, else /run/lock) and flock()s the
    // device. Errc::busy naming the holder when another program has it; a lock directory this
    // program cannot write is skipped (note() says so), as Debian's serial programs do.
    static Result<PortLock> acquire(const std::string& device, const std::string& lock_dir = {});

    PortLock() = default;  // holds nothing
    PortLock(PortLock&& other) noexcept;
    PortLock& operator=(PortLock&& other) noexcept;
    PortLock(const PortLock&) = delete;
    PortLock& operator=(const PortLock&) = delete;
    ~PortLock();

    // TIOCEXCL on the device: further opens fail (except root's) until this lock goes away. Call it
    // once the program's own final open is done. Ok on a device that is not a terminal.
    Status make_exclusive();

    const std::string& lock_file() const { return lock_file_; }  // empty when none was written
    const std::string& note() const { return note_; }            // e.g. why no lock file was written

private:
    void release();

    int device_fd_ = -1;
    bool exclusive_ = false;
    std::string lock_file_;
    std::string note_;
};

}  // namespace birdcage
