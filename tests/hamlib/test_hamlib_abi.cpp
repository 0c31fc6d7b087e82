// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The backend's load-time ABI rule (src/hamlib/hamlib_abi.hpp) with the Hamlib releases users run:
// Debian 12's 4.5.4, Debian 13's 4.6.2 and master's 5.0.
#include <catch2/catch.hpp>

#include "hamlib_abi.hpp"

using birdcage::hamlib::check_abi;
using birdcage::hamlib::parse_version;
using birdcage::hamlib::soname_major;

TEST_CASE("Hamlib version strings as hamlib_version2 and pkg-config give them") {
    const auto bookworm = parse_version("Hamlib 4.5.4 Jan 10 01:31:41Z 2023 SHA=921cc5");
    REQUIRE(bookworm);
    CHECK(bookworm->major == 4);
    CHECK(bookworm->minor == 5);
    CHECK(bookworm->patch == 4);
    const auto master = parse_version("5.0.0~git");
    REQUIRE(master);
    CHECK(master->major == 5);
    CHECK(master->minor == 0);
    const auto two_fields = parse_version("Hamlib 4.6");
    REQUIRE(two_fields);
    CHECK(two_fields->minor == 6);
    CHECK(two_fields->patch == 0);
    CHECK_FALSE(parse_version("Hamlib"));
    CHECK_FALSE(parse_version(""));

    CHECK(soname_major("/usr/lib/x86_64-linux-gnu/libhamlib.so.4.0.6") == 4);
    CHECK(soname_major("libhamlib.so.5") == 5);
    CHECK_FALSE(soname_major("/usr/lib/libhamlib.so"));
}

TEST_CASE("A 4.5.4 build runs in 4.5.4 and 4.6.2 but never in 5.0") {
    const auto same = check_abi("4.5.4", 4, "Hamlib 4.5.4 Jan 10 01:31:41Z 2023 SHA=921cc5", 4);
    CHECK(same.compatible);
    CHECK(same.message.empty());

    const auto trixie = check_abi("4.5.4", 4, "Hamlib 4.6.2 2025-01-05T11:26:45Z SHA=d3fc3d", 4);
    CHECK(trixie.compatible);
    CHECK_THAT(trixie.message, Catch::Contains("built for Hamlib 4.5.4 (libhamlib.so.4), running Hamlib 4.6.2"));

    const auto master = check_abi("4.5.4", 4, "Hamlib 5.0.0~git 2025-06-01 SHA=8319dc", 5);
    CHECK_FALSE(master.compatible);
    CHECK_THAT(master.message,
               Catch::Contains("built for Hamlib 4.5.4 (libhamlib.so.4), running Hamlib 5.0.0 (libhamlib.so.5)"));
    CHECK(master.message.find('\n') == std::string::npos);  // one line

    // The soname unknown at run time: the version major alone still refuses.
    CHECK_FALSE(check_abi("4.5.4", 4, "Hamlib 5.0.0~git", 0).compatible);
}

TEST_CASE("A 4.6.2 build refuses an older 4.5.4 and a 5.0 - a 5.0 build refuses 4.x") {
    const auto older = check_abi("4.6.2", 4, "Hamlib 4.5.4 Jan 10 01:31:41Z 2023 SHA=921cc5", 4);
    CHECK_FALSE(older.compatible);
    CHECK_THAT(older.message, Catch::Contains("built for Hamlib 4.6.2 (libhamlib.so.4), running Hamlib 4.5.4"));
    CHECK_THAT(older.message, Catch::Contains("older"));
    CHECK(check_abi("4.6.2", 4, "Hamlib 4.6.2", 4).compatible);
    CHECK_FALSE(check_abi("4.6.2", 4, "Hamlib 5.0.0~git", 5).compatible);
    CHECK_FALSE(check_abi("5.0.0~git", 5, "Hamlib 4.6.2", 4).compatible);
    CHECK(check_abi("5.0.0~git", 5, "Hamlib 5.0.0~git 2025-06-01", 5).compatible);
}

TEST_CASE("An unreadable version is accepted only on an equal and known soname") {
    CHECK(check_abi("4.5.4", 4, "(custom build)", 4).compatible);
    CHECK_FALSE(check_abi("4.5.4", 4, "(custom build)", 0).compatible);
    CHECK_FALSE(check_abi("4.5.4", 0, "(custom build)", 4).compatible);
    // A different soname refuses whatever the version strings say.
    CHECK_FALSE(check_abi("4.5.4", 4, "Hamlib 4.5.4", 5).compatible);
}
