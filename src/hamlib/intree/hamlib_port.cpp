// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The console's transport inside Hamlib's tree: every byte to and from the dish goes through
// Hamlib's port I/O (write_block, read_block, rig_flush), so `-vvvvv` shows it as it shows any
// backend's, and after a hang-up the port is reopened by Hamlib (port_close, port_open) with the
// settings it was opened with.
//
// Waiting is the one thing done beside Hamlib's I/O: read_block blocks until it has all the bytes
// it was asked for, and on a hung-up tty (an unplugged USB adapter) its select() keeps reporting
// data while read() returns 0, so it would spin for ever. The transport therefore waits for the
// console with poll() (no bytes move), in slices no longer than the port's timeout (the caps'
// 1000 ms, or rotctld's `-C timeout=`), and asks read_block only for bytes the port already holds.
#include "winegard_priv.hpp"

// Hamlib's port I/O; its header has no C++ guard of its own.
extern "C" {
#include "iofunc.h"
}

#include <poll.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>

namespace birdcage::hamlib {
namespace {

class HamlibPortTransport final : public Transport {
public:
    explicit HamlibPortTransport(hamlib_port_t* port) : port_(port) {}

    // write_block writes everything or fails; a failed write means the port is gone.
    Status write(std::string_view bytes, Deadline) override {
        if (bytes.empty()) {
            return Status::ok();
        }
        const int rc = write_block(port_, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
        if (rc != RIG_OK) {
            return {Errc::disconnected, "write_block failed (" + std::to_string(rc) + ")"};
        }
        return Status::ok();
    }

    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override {
        for (;;) {
            const Result<int> held = bytes_held();
            if (!held) {
                return {0, held.status};
            }
            if (held.value > 0) {
                const std::size_t count = std::min(static_cast<std::size_t>(held.value), n);
                const int got = read_block(port_, reinterpret_cast<unsigned char*>(buf), count);
                if (got <= 0) {
                    return {0, Status{Errc::disconnected, "read_block failed (" + std::to_string(got) + ")"}};
                }
                return {static_cast<std::size_t>(got), Status::ok()};
            }
            const auto left = std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()).count();
            if (left <= 0) {
                return {0, Status{Errc::timeout, "no data before the deadline"}};
            }
            const long slice = port_->timeout > 0 ? std::min<long>(left, port_->timeout) : left;
            if (Status waited = wait_readable(static_cast<int>(slice)); !waited) {
                return {0, waited};
            }
        }
    }

    void discard_input() override { rig_flush(port_); }

private:
    // How many received bytes the port holds. A hung-up tty refuses the question (EIO).
    Result<int> bytes_held() const {
        int count = 0;
        if (::ioctl(port_->fd, FIONREAD, &count) != 0) {
            return {0, Status{Errc::disconnected, std::string("the port hung up: ") + std::strerror(errno)}};
        }
        return {count, Status::ok()};
    }

    // Ok when data arrived or `ms` passed; disconnected on a hang-up. Readable with nothing held is
    // the end of the stream (a closed socket, a hung-up tty).
    Status wait_readable(int ms) const {
        pollfd descriptor{port_->fd, POLLIN, 0};
        const int ready = ::poll(&descriptor, 1, ms);
        if (ready < 0 && errno != EINTR) {
            return {Errc::disconnected, std::string("poll: ") + std::strerror(errno)};
        }
        if (ready <= 0) {
            return Status::ok();
        }
        if ((descriptor.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0) {
            return {Errc::disconnected, "the port hung up"};
        }
        const Result<int> held = bytes_held();
        if (held && held.value == 0) {
            return {Errc::disconnected, "the port reached its end (closed)"};
        }
        return held.status;
    }

    hamlib_port_t* port_;
};

}  // namespace

Result<PortLink> open_port_link(ROT* rot) {
    hamlib_port_t* port = ROTPORT(rot);
    if (port->fd < 0) {
        return {{}, Status{Errc::io, "the port is not open"}};
    }
    PortLink link;
    link.transport = std::make_unique<HamlibPortTransport>(port);
    // After a hang-up the worker asks for the port again: Hamlib closes and reopens it, with the
    // rate and framing it was opened with, and the new fd stays Hamlib's (rot_close closes it).
    link.reopen = [port]() -> Result<std::unique_ptr<Transport>> {
        port_close(port, port->type.rig);
        const int rc = port_open(port);
        if (rc != RIG_OK) {
            return {nullptr, Status{Errc::disconnected, "port_open failed (" + std::to_string(rc) + ")"}};
        }
        return {std::make_unique<HamlibPortTransport>(port), Status::ok()};
    };
    return {std::move(link), Status::ok()};
}

}  // namespace birdcage::hamlib
