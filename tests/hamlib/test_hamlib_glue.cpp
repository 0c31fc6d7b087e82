// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The C entry points never let an exception reach Hamlib's C (it would end the process): each one
// runs in guarded(), which answers a -RIG_E* code. Here every entry point is made to throw, on a
// rotator whose rot_init never ran (no Winegard state: priv_of() throws), and must answer an error.
#include <catch2/catch.hpp>

#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include "winegard.h"
#include "winegard_priv.hpp"

using birdcage::hamlib::guarded;

namespace {

struct QuietHamlib {
    QuietHamlib() { rig_set_debug(RIG_DEBUG_NONE); }
};

}  // namespace

TEST_CASE("every C entry point answers an error code when what it calls throws") {
    QuietHamlib quiet;
    struct s_rot rot {};  // rot_init never ran: no Winegard state, so each body throws
    azimuth_t az = 0;
    elevation_t el = 0;
    rot_status_t status{};
    value_t value{};
    char text[64] = "unchanged";

    CHECK(winegard_rot_init(nullptr) == -RIG_EINVAL);
    CHECK(winegard_rot_cleanup(&rot) == -RIG_EINVAL);
    CHECK(winegard_rot_open(&rot) == -RIG_EINVAL);
    CHECK(winegard_rot_close(&rot) == -RIG_EINVAL);
    CHECK(winegard_set_position(&rot, 100, 30) == -RIG_EINVAL);
    CHECK(winegard_get_position(&rot, &az, &el) == -RIG_EINVAL);
    CHECK(winegard_stop(&rot) == -RIG_EINVAL);
    CHECK(winegard_park(&rot) == -RIG_EINVAL);
    CHECK(winegard_reset(&rot, ROT_RESET_ALL) == -RIG_EINVAL);
    CHECK(winegard_get_status(&rot, &status) == -RIG_EINVAL);
    CHECK(winegard_set_conf(&rot, 1, "auto") == -RIG_EINVAL);
    CHECK(winegard_get_conf(&rot, 1, text) == -RIG_EINVAL);
    CHECK(winegard_get_conf2(&rot, 1, text, sizeof text) == -RIG_EINVAL);
    CHECK(winegard_set_ext_level(&rot, birdcage::hamlib::tok_lnb_volts, value) == -RIG_EINVAL);
    CHECK(winegard_get_ext_level(&rot, birdcage::hamlib::tok_rssi, &value) == -RIG_EINVAL);
    CHECK(winegard_send_cmd(&rot, "r", text, sizeof text) == -RIG_EINVAL);
    CHECK(std::string(text) == "unchanged");
    // get_info answers text, never an exception and never a null pointer.
    const char* info = winegard_get_info(&rot);
    REQUIRE(info != nullptr);
    CHECK(std::string(info).find("no information") != std::string::npos);
}

TEST_CASE("the guard answers each kind of exception with its code") {
    QuietHamlib quiet;
    CHECK(guarded("t", []() -> int { return RIG_OK; }) == RIG_OK);
    CHECK(guarded("t", []() -> int { return -RIG_EPROTO; }) == -RIG_EPROTO);
    CHECK(guarded("t", []() -> int { throw std::bad_alloc(); }) == -RIG_ENOMEM);
    CHECK(guarded("t", []() -> int { throw std::invalid_argument("x"); }) == -RIG_EINVAL);
    CHECK(guarded("t", []() -> int { throw std::runtime_error("x"); }) == -RIG_EINTERNAL);
    CHECK(guarded("t", []() -> int { throw 42; }) == -RIG_EINTERNAL);
}

TEST_CASE("rotctl's raw w is refused on an open model's state, and nothing is written back") {
    QuietHamlib quiet;
    // A rotator rot_init set up (no port opened): send_cmd needs nothing else to refuse.
    REQUIRE(winegard_init_tables() == RIG_OK);
    struct rot_caps caps {};
    caps.model_name = "Carryout G2";
    caps.serial_rate_max = 115200;
    caps.reset = winegard_reset;
    caps.priv = const_cast<char*>("g2");
    struct s_rot rot {};
    rot.caps = &caps;
    REQUIRE(winegard_rot_init(&rot) == RIG_OK);
    char reply[16] = "x";
    CHECK(winegard_send_cmd(&rot, "r", reply, sizeof reply) == -RIG_ERJCTED);
    CHECK(reply[0] == '\0');
    CHECK(winegard_rot_cleanup(&rot) == RIG_OK);
}
