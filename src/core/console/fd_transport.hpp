// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A POSIX fd as the console's transport: Hamlib's serial fd in the preload build, ptys in tests.
#pragma once

#include <memory>
#include <string>

#include "console/transport.hpp"

namespace birdcage {

// POSIX fd (tty, pty, pipe, socket); blocking or non-blocking (Hamlib's serial fd is non-blocking).
class FdTransport final : public Transport {
public:
    FdTransport(int fd, bool owns_fd);
    ~FdTransport() override;
    FdTransport(const FdTransport&) = delete;
    FdTransport& operator=(const FdTransport&) = delete;

    // Opens a tty or pty: O_NOCTTY, non-blocking, raw 8N1 at `baud`.
    static Result<std::unique_ptr<FdTransport>> open(const std::string& path, int baud);

    Status write(std::string_view bytes, Deadline deadline) override;
    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override;
    void discard_input() override;

    int fd() const { return fd_; }

private:
    int fd_;
    bool owns_fd_;
};

}  // namespace birdcage
