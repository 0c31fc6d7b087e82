// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The console's transport in the preload build: the fd the running rotctld opened, read and
// written directly (Debian's Hamlib 4.5 installs no header for its port I/O). A Hamlib tree uses
// Hamlib's port I/O instead (src/hamlib/intree/hamlib_port.cpp).
#include "console/fd_transport.hpp"
#include "winegard_priv.hpp"

#include <memory>
#include <string>

namespace birdcage::hamlib {

Result<PortLink> open_port_link(ROT* rot) {
    hamlib_port_t* port = ROTPORT(rot);
    if (port->fd < 0) {
        return {{}, Status{Errc::io, "the port is not open"}};
    }
    PortLink link;
    // Hamlib owns the fd (it closes it in rot_close); it is non-blocking, which FdTransport polls.
    link.transport = std::make_unique<FdTransport>(port->fd, false);
    // After a hang-up (adapter unplugged) Hamlib's fd is dead and rotctld never reopens it: the
    // service opens the same path itself, on its own fd (Hamlib's stays untouched for rot_close).
    const std::string path = port->pathname;
    const int baud = port->parm.serial.rate > 0 ? port->parm.serial.rate : rot->caps->serial_rate_max;
    link.reopen = [path, baud]() -> Result<std::unique_ptr<Transport>> {
        auto opened = FdTransport::open(path, baud);
        if (!opened) {
            return {nullptr, opened.status};
        }
        return {std::move(opened.value), Status::ok()};
    };
    return {std::move(link), Status::ok()};
}

}  // namespace birdcage::hamlib
