// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Byte transport under the console session. Implementations convert their own errors to Errc once.
#pragma once

#include <chrono>
#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include "base/errors.hpp"
#include "base/plain_types.hpp"

struct sp_port;

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

// A pseudo-terminal (/dev/pts/N, or a link to one, such as the emulator's --link): no line speed
// applies to it, whatever rate it was opened at.
bool is_pseudo_terminal(const std::string& path);

// Real serial ports through libserialport, for standalone tools. libserialport cannot open ptys
// (codebases.md 3), so tests use FdTransport.
class SerialPortTransport final : public Transport {
public:
    static Result<std::unique_ptr<SerialPortTransport>> open(const std::string& path, int baud);

    Status write(std::string_view bytes, Deadline deadline) override;
    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override;
    void discard_input() override;

private:
    struct PortDeleter {
        void operator()(sp_port* port) const;
    };
    explicit SerialPortTransport(std::unique_ptr<sp_port, PortDeleter> port);

    std::unique_ptr<sp_port, PortDeleter> port_;
};

}  // namespace birdcage
