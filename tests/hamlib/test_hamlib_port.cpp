// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The in-tree port link (src/hamlib/intree/hamlib_port.cpp) against the installed Hamlib's own port
// I/O, over a pty whose other end plays the dish: bytes both ways through write_block and
// read_block, a read that times out at its deadline, the port reopened by Hamlib, and a hang-up
// that ends a read as disconnected (Hamlib's read_block would spin on it).
#include <catch2/catch.hpp>

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fcntl.h>
#include <unistd.h>

#include "../core/pty_pair.hpp"
#include "winegard_priv.hpp"

extern "C" {
#include "iofunc.h"
}

using namespace birdcage;
using birdcage::testing::Pty;
using namespace std::chrono_literals;

namespace {

// What the dish end reads within a second.
std::string dish_reads(int fd, std::size_t want) {
    std::string got;
    const auto until = Clock::now() + 1s;
    std::array<char, 64> buffer{};
    while (got.size() < want && Clock::now() < until) {
        const ssize_t n = ::read(fd, buffer.data(), buffer.size());
        if (n > 0) {
            got.append(buffer.data(), static_cast<std::size_t>(n));
        }
    }
    return got;
}

std::string backend_reads(Transport& transport, std::size_t want) {
    std::string got;
    std::array<char, 64> buffer{};
    while (got.size() < want) {
        const auto r = transport.read(buffer.data(), buffer.size(), Clock::now() + 1s);
        if (!r) {
            break;
        }
        got.append(buffer.data(), r.value);
    }
    return got;
}

}  // namespace

TEST_CASE("the in-tree port link moves the console's bytes through Hamlib's port I/O") {
    rig_set_debug(RIG_DEBUG_NONE);
    Pty pty;
    ::fcntl(pty.master, F_SETFL, ::fcntl(pty.master, F_GETFL) | O_NONBLOCK);
    struct s_rot rot {};
    hamlib_port_t* port = ROTPORT(&rot);
    std::strncpy(port->pathname, pty.slave_path.c_str(), sizeof port->pathname - 1);
    port->type.rig = RIG_PORT_SERIAL;
    port->parm.serial.rate = 115200;
    port->parm.serial.data_bits = 8;
    port->parm.serial.stop_bits = 1;
    port->parm.serial.parity = RIG_PARITY_NONE;
    port->parm.serial.handshake = RIG_HANDSHAKE_NONE;
    port->timeout = 100;                 // each wait a slice of it
    REQUIRE(port_open(port) == RIG_OK);  // as rot_open opens it

    auto link = hamlib::open_port_link(&rot);
    REQUIRE(link);
    Transport& transport = *link.value.transport;

    REQUIRE(transport.write("a\r", Clock::now() + 1s));
    CHECK(dish_reads(pty.master, 2) == "a\r");
    REQUIRE(::write(pty.master, "MOT>", 4) == 4);
    CHECK(backend_reads(transport, 4) == "MOT>");

    // Nothing sent: the read ends at its deadline (several of the port's timeouts), as a timeout.
    std::array<char, 8> buffer{};
    const auto silent = transport.read(buffer.data(), buffer.size(), Clock::now() + 350ms);
    CHECK(silent.status.code == Errc::timeout);

    // After a hang-up the worker asks for the port again: Hamlib reopens it.
    auto reopened = link.value.reopen();
    REQUIRE(reopened);
    REQUIRE(::write(pty.master, "TRK>", 4) == 4);
    CHECK(backend_reads(*reopened.value, 4) == "TRK>");

    // The dish end goes away: the read says so instead of waiting or spinning.
    pty.hang_up();
    const auto gone = reopened.value->read(buffer.data(), buffer.size(), Clock::now() + 5s);
    CHECK(gone.status.code == Errc::disconnected);
    port_close(port, RIG_PORT_SERIAL);
}
