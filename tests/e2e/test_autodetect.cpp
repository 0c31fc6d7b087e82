// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end: model 90100 identifies every emulated firmware variant from what its console prints,
// reports it in get_info, then drives the dish. No hazard may reach the dish while probing.
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <functional>
#include <thread>

using namespace std::chrono_literals;
using birdcage::sim::Options;
using birdcage::sim::Variant;

namespace {

constexpr int kAutoModel = 90100;

struct AutoCase {
    std::string name;
    Variant variant;
    std::string expected;  // text get_info must contain
    std::function<void(Options&)> apply = [](Options&) {};
    std::vector<std::string> typed = {};  // left in a submenu before the backend opens the port
};

void detect_and_drive(const AutoCase& c) {
    Options o;
    o.variant = c.variant;
    o.time_scale = 50.0;
    o.start_az = 100.0;
    o.start_el = 30.0;
    c.apply(o);
    const auto typed = c.typed;
    e2e::Rig rig(o, kAutoModel, {"-C", "leapfrog=0"}, [typed](birdcage::sim::Emulator& dish) {
        if (!typed.empty()) {
            e2e::type_into(dish, typed);
        }
    });
    // Stock NET rotctl reads `_` into 64 bytes (63 characters): the dish and its state are in them.
    const e2e::CommandResult info = rig.rotctl({"_"});
    INFO(info.out << info.err);
    CHECK(info.out.rfind("Winegard ", 0) == 0);
    const std::size_t state = info.out.find("(auto-detected): ");
    REQUIRE(state != std::string::npos);
    // Whole, so inside the 63 characters.
    const std::string after = info.out.substr(state + std::string("(auto-detected): ").size());
    const bool known_state = after.rfind("idle;", 0) == 0 || after.rfind("moving;", 0) == 0;
    CHECK(known_state);
    e2e::RotctldConnection client(rig.port());
    if (c.variant == Variant::carryout2003) {
        // No position query at rest (docs/firmware.md 8.3), yet the console answers: idle it stays,
        // past the real-time silence after which a dish counts as not answering (5 s).
        const auto opened = std::chrono::steady_clock::now();
        while (std::chrono::steady_clock::now() - opened < 6s) {
            const std::string now = client.ask("_", 1);
            INFO(now);
            REQUIRE(now.find("(auto-detected): idle;") != std::string::npos);
            REQUIRE(client.ask("s", 1).find("BUSY") == std::string::npos);
            std::this_thread::sleep_for(500ms);
        }
    }
    const std::string full = client.ask("_", 1);
    INFO(full);
    CHECK(full.find(c.expected) != std::string::npos);
    CHECK(full.find("lists") != std::string::npos);  // the evidence
    CHECK(rig.dish().hazards_received() == 0);

    REQUIRE(rig.rotctl({"P", "150", "40"}).exit_code == 0);
    const bool settled = e2e::wait_until(
        [&] {
            const auto p = rig.dish().true_position();
            return !rig.dish().moving() && e2e::angle_between(p.az, 150.0) <= 0.1 && std::fabs(p.el - 40.0) <= 0.1;
        },
        30s);
    if (!settled) {
        INFO(rig.rotctld_log_text());
        CHECK(settled);
    }
    CHECK(rig.dish().hazards_received() == 0);
    CHECK(rig.dish().shell_alive());
}

}  // namespace

TEST_CASE("auto-detect (90100) identifies every emulated variant without sending a hazard", "[e2e][autodetect]") {
    const std::vector<AutoCase> cases = {
        {"hal000", Variant::travler_hal000, "HAL 0.0.00"},
        {"hal205", Variant::travler_hal205, "HAL 2.05"},
        {"pro", Variant::travler_pro, "Trav'ler Pro"},
        {"carryout2003", Variant::carryout2003, "Carryout HAL 1.00.065"},
        {"g2", Variant::carryout_g2, "Carryout G2"},
        {"g2 left in MOT>", Variant::carryout_g2, "Carryout G2", [](Options&) {}, {"mot"}},
        {"g2 left in NVS>", Variant::carryout_g2, "Carryout G2", [](Options&) {}, {"nvs"}},
        {"g2 booting", Variant::carryout_g2, "Carryout G2", [](Options& o) { o.already_booted = false; }},
        {"g2, echo off, LF", Variant::carryout_g2, "Carryout G2",
         [](Options& o) {
             o.echo = false;
             o.line_ending = birdcage::sim::LineEnding::lf;
         }},
        {"hal205 bare prompts, left in motor",
         Variant::travler_hal205,
         "HAL 2.05",
         [](Options& o) { o.prompt_style = birdcage::sim::PromptStyle::bare; },
         {"motor"}},
        {"hal000 bare root, named submenus, left in mot",
         Variant::travler_hal000,
         "HAL 0.0.00",
         [](Options& o) { o.prompt_style = birdcage::sim::PromptStyle::bare_root; },
         {"mot"}},
        {"hal000 booting", Variant::travler_hal000, "HAL 0.0.00", [](Options& o) { o.already_booted = false; }},
        // `?` answers one line, a label then the command words, at `>` prompts: dish up and booting
        // (where `NoGPS` alone ties the two Trav'ler HALs).
        {"hal000, ? is a label then the words", Variant::travler_hal000, "HAL 0.0.00",
         [](Options& o) {
             o.help_layout = birdcage::sim::HelpLayout::labelled_line;
             o.prompt_style = birdcage::sim::PromptStyle::bare;
         }},
        {"hal000 booting, ? is a label then the words", Variant::travler_hal000, "HAL 0.0.00",
         [](Options& o) {
             o.help_layout = birdcage::sim::HelpLayout::labelled_line;
             o.prompt_style = birdcage::sim::PromptStyle::bare;
             o.already_booted = false;
         }},
        {"hal205 booting, ? is a label then the words", Variant::travler_hal205, "HAL 2.05",
         [](Options& o) {
             o.help_layout = birdcage::sim::HelpLayout::labelled_line;
             o.already_booted = false;
         }},
        // One more boot line nobody documented after `Loc Startup: IDU NOT Present`, then `TRK>`.
        {"g2 booting, one more line after Loc Startup", Variant::carryout_g2, "Carryout G2",
         [](Options& o) {
             o.already_booted = false;
             o.after_boot_line = "Antenna Facing Front: tracker disabled";
         }},
        {"carryout2003 left in target, no unknown-command text",
         Variant::carryout2003,
         "Carryout HAL 1.00.065",
         [](Options& o) { o.unknown_command_reply = ""; },
         {"target"}},
        {"pro left in ODU mot, q returns to the IDU",
         Variant::travler_pro,
         "Trav'ler Pro",
         [](Options& o) { o.pro_q_at_odu_root_returns_to_idu = true; },
         {"odu", "mot"}},
        // Indistinguishable from a HAL 0.0.00 root: reported as such, with the Pro's 75 deg cap kept.
        {"pro left in ODU mot, q stays on the ODU",
         Variant::travler_pro,
         "el limits 15.00..75.00",
         [](Options&) {},
         {"odu", "mot"}},
    };
    for (const AutoCase& c : cases) {
        DYNAMIC_SECTION(c.name) {
            detect_and_drive(c);
        }
    }
}

TEST_CASE("rotctl -l lists the auto-detecting model", "[e2e][autodetect][registration]") {
    const e2e::CommandResult with = e2e::run({"/usr/bin/rotctl", "-l"}, e2e::preload_environment());
    REQUIRE(with.exit_code == 0);
    CHECK(with.out.find(std::to_string(kAutoModel)) != std::string::npos);
    CHECK(with.out.find("Auto-detect") != std::string::npos);
}

// A G2 whose prompts carry a product tag (`WG TRK>`, `[G2]MOT>`) or marks after the '>' is the same
// firmware: it opens with its own model and with 90100, booting or up, and is driven. Before prompts
// were known by their shape it never opened ("still waiting for the dish to boot" for ever).
TEST_CASE("a G2 whose prompts carry a tag opens with its own model and auto-detected when booting and when up",
          "[e2e][autodetect][prompt_shape]") {
    struct TagCase {
        const char* name;
        std::string prefix, suffix;
        bool booting;
        int model;
    };
    const TagCase c = GENERATE(TagCase{"WG , own model, up", "WG ", "", false, 90105},
                               TagCase{"[G2], own model, booting", "[G2]", "", true, 90105},
                               TagCase{"WG , auto, up", "WG ", "", false, kAutoModel},
                               TagCase{"[G2] and $, auto, booting", "[G2]", "$", true, kAutoModel});
    INFO(c.name);
    Options o;
    o.variant = Variant::carryout_g2;
    o.time_scale = 50.0;
    o.start_az = 100.0;
    o.start_el = 30.0;
    o.prompt_prefix = c.prefix;
    o.prompt_suffix = c.suffix;
    o.already_booted = !c.booting;
    e2e::Rig rig(o, c.model, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    const std::string info = client.ask("_", 1);
    INFO(info);
    CHECK(info.find("Carryout G2") != std::string::npos);
    REQUIRE(rig.rotctl({"P", "150", "40"}).exit_code == 0);
    const bool settled = e2e::wait_until(
        [&] {
            const auto p = rig.dish().true_position();
            return !rig.dish().moving() && e2e::angle_between(p.az, 150.0) <= 0.1 && std::fabs(p.el - 40.0) <= 0.1;
        },
        30s);
    if (!settled) {
        INFO(rig.rotctld_log_text());
        CHECK(settled);
    }
    CHECK(rig.dish().hazards_received() == 0);
    CHECK(rig.dish().shell_alive());
}
