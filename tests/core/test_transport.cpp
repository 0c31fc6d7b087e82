// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include <catch2/catch.hpp>

#include <array>
#include <cstdlib>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "console/fd_transport.hpp"
#include "console/serial_port_transport.hpp"
#include "pty_pair.hpp"

using namespace birdcage;
using birdcage::testing::Pty;
using namespace std::chrono_literals;

namespace {

std::string read_all(Transport& transport, std::size_t want) {
    std::string got;
    std::array<char, 64> buffer{};
    while (got.size() < want) {
        auto r = transport.read(buffer.data(), buffer.size(), Clock::now() + 1s);
        if (!r) {
            break;
        }
        got.append(buffer.data(), r.value);
    }
    return got;
}

}  // namespace

TEST_CASE("FdTransport over a pty: write, read, timeout, hang-up") {
    Pty pty;
    auto opened = FdTransport::open(pty.slave_path, 115200);
    REQUIRE(opened);
    FdTransport& port = *opened.value;

    REQUIRE(port.write("a\r", Clock::now() + 1s));
    std::array<char, 16> from_port{};
    const ssize_t n = ::read(pty.master, from_port.data(), from_port.size());
    REQUIRE(n == 2);
    CHECK(std::string(from_port.data(), 2) == "a\r");

    const std::string reply = "Angle = 1.00\r\nMOT>";
    REQUIRE(::write(pty.master, reply.data(), reply.size()) == static_cast<ssize_t>(reply.size()));
    CHECK(read_all(port, reply.size()) == reply);

    const auto start = Clock::now();
    std::array<char, 8> buffer{};
    const auto timed_out = port.read(buffer.data(), buffer.size(), start + 50ms);
    CHECK(timed_out.status.code == Errc::timeout);
    CHECK(Clock::now() - start >= 50ms);

    const auto past = port.read(buffer.data(), buffer.size(), start - 1s);
    CHECK(past.status.code == Errc::timeout);

    REQUIRE(::write(pty.master, "junk", 4) == 4);
    ::usleep(20000);
    port.discard_input();
    CHECK(port.read(buffer.data(), buffer.size(), Clock::now() + 20ms).status.code == Errc::timeout);

    ::close(pty.master);
    pty.master = -1;
    CHECK(port.read(buffer.data(), buffer.size(), Clock::now() + 1s).status.code == Errc::disconnected);
}

// `_` and the probe name no line speed on a pty: the emulator's link is a symlink to one.
TEST_CASE("is_pseudo_terminal: a pty and a link to it are, a directory, a missing path and /dev/null are not") {
    Pty pty;
    CHECK(is_pseudo_terminal(pty.slave_path));
    char dir_template[] = "/tmp/birdcage-pty-test.XXXXXX";
    REQUIRE(::mkdtemp(dir_template) != nullptr);
    const std::string link = std::string(dir_template) + "/dish.tty";
    REQUIRE(::symlink(pty.slave_path.c_str(), link.c_str()) == 0);
    CHECK(is_pseudo_terminal(link));
    CHECK_FALSE(is_pseudo_terminal(std::string(dir_template)));
    CHECK_FALSE(is_pseudo_terminal(std::string(dir_template) + "/missing"));
    CHECK_FALSE(is_pseudo_terminal("/dev/null"));
    ::unlink(link.c_str());
    ::rmdir(dir_template);
}

TEST_CASE("FdTransport works on a non-blocking pipe (Hamlib hands us a non-blocking fd)") {
    std::array<int, 2> fds{};
    REQUIRE(::pipe(fds.data()) == 0);
    ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
    FdTransport reader(fds[0], true);
    std::array<char, 8> buffer{};
    CHECK(reader.read(buffer.data(), buffer.size(), Clock::now() + 10ms).status.code == Errc::timeout);
    REQUIRE(::write(fds[1], "MOT>", 4) == 4);
    const auto got = reader.read(buffer.data(), buffer.size(), Clock::now() + 1s);
    REQUIRE(got);
    CHECK(std::string(buffer.data(), got.value) == "MOT>");
    ::close(fds[1]);
    CHECK(reader.read(buffer.data(), buffer.size(), Clock::now() + 1s).status.code == Errc::disconnected);
}

TEST_CASE("FdTransport::open reports unusable paths") {
    const auto missing = FdTransport::open("/nonexistent/ttyUSB9", 57600);
    CHECK_FALSE(missing);
    CHECK(missing.status.code == Errc::io);
    CHECK(missing.status.message.find("/nonexistent/ttyUSB9") != std::string::npos);
    CHECK(FdTransport::open("/dev/null", 57600).status.code == Errc::io);  // not a terminal
    CHECK(FdTransport::open("/dev/null", 12345).status.code == Errc::invalid_argument);
}

TEST_CASE("SerialPortTransport: a nonexistent port yields a clear error") {
    const auto opened = SerialPortTransport::open("/dev/ttyUSB_birdcage_missing", 115200);
    CHECK_FALSE(opened);
    CHECK(opened.value == nullptr);
    CHECK(opened.status.code != Errc::ok);
    CHECK(opened.status.message.find("/dev/ttyUSB_birdcage_missing") != std::string::npos);
}
