// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/fd_transport.hpp"

#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

namespace birdcage {
namespace {

// Milliseconds until the deadline for poll(): rounded up so we never wake just before it,
// 0 when it has passed.
int poll_timeout_ms(Deadline deadline) {
    const auto remaining = deadline - Clock::now();
    if (remaining <= Clock::duration::zero()) {
        return 0;
    }
    const auto ms = std::chrono::ceil<std::chrono::milliseconds>(remaining).count();
    return ms > 60'000 ? 60'000 : static_cast<int>(ms);
}

// The one place errno becomes an Errc for this transport.
Status errno_status(const char* operation, int error) {
    const Errc code = (error == EIO || error == EPIPE || error == ENXIO || error == ENODEV || error == EBADF)
                          ? Errc::disconnected
                          : Errc::io;
    return Status{code, std::string(operation) + ": " + std::strerror(error)};
}

speed_t speed_for(int baud) {
    switch (baud) {
        case 9600:
            return B9600;
        case 19200:
            return B19200;
        case 38400:
            return B38400;
        case 57600:
            return B57600;
        case 115200:
            return B115200;
        case 230400:
            return B230400;
        default:
            return B0;
    }
}

}  // namespace

FdTransport::FdTransport(int fd, bool owns_fd) : fd_(fd), owns_fd_(owns_fd) {}

FdTransport::~FdTransport() {
    if (owns_fd_ && fd_ >= 0) {
        ::close(fd_);
    }
}

Result<std::unique_ptr<FdTransport>> FdTransport::open(const std::string& path, int baud) {
    const speed_t speed = speed_for(baud);
    if (speed == B0) {
        return {nullptr, Status{Errc::invalid_argument, "unsupported baud rate " + std::to_string(baud)}};
    }
    const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int error = errno;
        return {nullptr, Status{Errc::io, "cannot open " + path + ": " + std::strerror(error)}};
    }
    auto transport = std::make_unique<FdTransport>(fd, true);
    termios settings{};
    if (::tcgetattr(fd, &settings) != 0) {
        const int error = errno;
        return {nullptr, Status{Errc::io, path + " is not a terminal: " + std::strerror(error)}};
    }
    ::cfmakeraw(&settings);
    settings.c_cflag |= CLOCAL | CREAD;
    settings.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS);
    settings.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
    settings.c_cc[VMIN] = 0;
    settings.c_cc[VTIME] = 0;
    if (::cfsetispeed(&settings, speed) != 0 || ::cfsetospeed(&settings, speed) != 0 ||
        ::tcsetattr(fd, TCSANOW, &settings) != 0) {
        const int error = errno;
        return {nullptr, Status{Errc::io, "cannot configure " + path + ": " + std::strerror(error)}};
    }
    ::tcflush(fd, TCIOFLUSH);
    return {std::move(transport), Status::ok()};
}

Status FdTransport::write(std::string_view bytes, Deadline deadline) {
    while (!bytes.empty()) {
        const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
        if (written > 0) {
            bytes.remove_prefix(static_cast<std::size_t>(written));
            continue;
        }
        const int error = errno;
        if (written < 0 && error == EINTR) {
            continue;
        }
        if (written < 0 && error != EAGAIN && error != EWOULDBLOCK) {
            return errno_status("write", error);
        }
        pollfd descriptor{fd_, POLLOUT, 0};
        const int ready = ::poll(&descriptor, 1, poll_timeout_ms(deadline));
        if (ready == 0) {
            return Status{Errc::timeout, "write timed out with " + std::to_string(bytes.size()) + " bytes unsent"};
        }
        if (ready < 0 && errno != EINTR) {
            return errno_status("poll", errno);
        }
        if (ready > 0 && (descriptor.revents & (POLLERR | POLLHUP | POLLNVAL)) != 0 &&
            (descriptor.revents & POLLOUT) == 0) {
            return Status{Errc::disconnected, "write: port hung up"};
        }
    }
    return Status::ok();
}

Result<std::size_t> FdTransport::read(char* buf, std::size_t n, Deadline deadline) {
    for (;;) {
        pollfd descriptor{fd_, POLLIN, 0};
        const int ready = ::poll(&descriptor, 1, poll_timeout_ms(deadline));
        if (ready < 0) {
            if (errno == EINTR) {
                continue;
            }
            return {0, errno_status("poll", errno)};
        }
        if (ready == 0) {
            if (Clock::now() < deadline) {
                continue;  // poll's timeout is capped; keep waiting
            }
            return {0, Status{Errc::timeout, "no data before the deadline"}};
        }
        if ((descriptor.revents & POLLNVAL) != 0) {
            return {0, Status{Errc::disconnected, "read: invalid descriptor"}};
        }
        const ssize_t got = ::read(fd_, buf, n);
        if (got > 0) {
            return {static_cast<std::size_t>(got), Status::ok()};
        }
        if (got == 0) {
            return {0, Status{Errc::disconnected, "read: end of file (port closed)"}};
        }
        const int error = errno;
        if (error == EINTR || error == EAGAIN || error == EWOULDBLOCK) {
            if ((descriptor.revents & POLLHUP) != 0) {
                return {0, Status{Errc::disconnected, "read: port hung up"}};
            }
            continue;
        }
        return {0, errno_status("read", error)};
    }
}

void FdTransport::discard_input() {
    ::tcflush(fd_, TCIFLUSH);
    // Not every fd is a tty (pipes and sockets in tests): drop what is readable right now.
    std::array<char, 256> scratch{};
    for (;;) {
        pollfd descriptor{fd_, POLLIN, 0};
        if (::poll(&descriptor, 1, 0) <= 0 || (descriptor.revents & POLLIN) == 0) {
            return;
        }
        if (::read(fd_, scratch.data(), scratch.size()) <= 0) {
            return;
        }
    }
}

}  // namespace birdcage
