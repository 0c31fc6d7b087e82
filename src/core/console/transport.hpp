// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Byte transport under the console session. Implementations convert their own errors to Errc once:
// FdTransport (console/fd_transport.hpp), SerialPortTransport (console/serial_port_transport.hpp),
// and in a Hamlib tree the backend's transport over Hamlib's port I/O.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "base/errors.hpp"
#include "base/plain_types.hpp"

namespace birdcage {

class Transport {
public:
    virtual ~Transport();
    // Writes all bytes, or fails with Errc::timeout at the deadline / Errc::disconnected / Errc::io.
    virtual Status write(std::string_view bytes, Deadline deadline) = 0;
    // Returns >0 bytes as soon as any are available, Errc::timeout at the deadline (also when the
    // deadline has already passed and nothing is buffered), Errc::disconnected on hang-up.
    virtual Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) = 0;
    // Drops whatever has been received and not yet read.
    virtual void discard_input() = 0;
};

// A pseudo-terminal (/dev/pts/N, or a link to one, such as the emulator's --link): no line speed
// applies to it, whatever rate it was opened at.
bool is_pseudo_terminal(const std::string& path);

}  // namespace birdcage
