// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A Trav'ler that reboots calibrates in silence, prints its ready line (`NoGPS`; HAL 2.05 may print
// `No LNB Voltage`) and starts its TV search at once (docs/firmware.md 3.2, 3.6, 4.2). Every moment
// the backend then spends confirming a prompt lets the search swing the dish, so the search stop
// must be the first thing the dish hears after that line: no poke, no `?`. Against the emulator's
// console in dish time (emulated_console.hpp), whichever part of the backend hears the line: a
// position poll (the dish rebooted under it) or the synchroniser (waiting out the boot).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "dish/controller.hpp"
#include "emulated_console.hpp"

using namespace birdcage;
using namespace std::chrono_literals;

namespace {

struct ReadyCase {
    const char* name;
    sim::Variant sim_variant;
    VariantId variant;
    sim::BootMarker marker;
    std::string ready_line;
    std::string stop_first;  // the search stop's first command (docs/firmware.md 3.6, 4.3)
    std::string stop_last;   // the command that stops the search
};

struct Rig {
    test::EmulatedConsole dish;
    std::optional<Controller> controller;

    explicit Rig(const ReadyCase& c) : dish(options(c)) {
        ControllerOptions controller_options{};
        controller_options.variant = c.variant;
        controller_options.leapfrog = false;
        controller_options.clock = dish.clock();
        controller.emplace(dish, controller_options);
        const Status initialised = controller->initialize();
        INFO(initialised.message);
        REQUIRE(initialised);
    }

    static sim::Options options(const ReadyCase& c) {
        sim::Options o;
        o.variant = c.sim_variant;
        o.hal205_boot_marker = c.marker;
        o.start_az = 20.0;  // near where the emulated calibration ends (AZ 0, EL 45): a short boot
        o.start_el = 40.0;
        return o;
    }
};

}  // namespace

TEST_CASE("ready line: after a Trav'ler reboot the search stop is the first thing the dish hears", "[ready_line]") {
    const ReadyCase c =
        GENERATE(ReadyCase{"HAL 0.0.00", sim::Variant::travler_hal000, VariantId::travler_hal000,
                           sim::BootMarker::no_gps, "NoGPS", "os\r", "kill Search\r"},
                 ReadyCase{"HAL 2.05, NoGPS", sim::Variant::travler_hal205, VariantId::travler_hal205,
                           sim::BootMarker::no_gps, "NoGPS", "ngsearch\r", "s\r"},
                 ReadyCase{"HAL 2.05, No LNB Voltage", sim::Variant::travler_hal205, VariantId::travler_hal205,
                           sim::BootMarker::no_lnb_voltage, "No LNB Voltage", "ngsearch\r", "s\r"});
    INFO(c.name);
    Rig rig(c);
    const std::size_t output_before = rig.dish.dish_output().size();
    rig.dish.console().power_cycle();

    // Dish time passes in the test's ticks (and a slice per unanswered read): the boot runs
    // between two of the backend's reads, and the ready line waits in the line's buffer.
    SECTION("heard by a position poll") {
        for (int polls = 0; polls < 1000 && !rig.controller->needs_reinit(); ++polls) {
            rig.dish.tick(100ms);
            (void)rig.controller->query_position();
        }
        REQUIRE(rig.controller->needs_reinit());
        const Status reinitialised = rig.controller->reinitialize(5000ms);
        INFO(reinitialised.message);
        REQUIRE(reinitialised);
    }
    SECTION("heard by the synchroniser") {
        for (int ticks = 0; ticks < 1000 && rig.dish.console().booting(); ++ticks) {
            rig.dish.tick(100ms);
        }
        const Status reinitialised = rig.controller->reinitialize(5000ms);
        INFO(reinitialised.message);
        REQUIRE(reinitialised);
    }

    const auto& output = rig.dish.dish_output();
    const auto ready =
        std::find_if(output.begin() + static_cast<std::ptrdiff_t>(output_before), output.end(),
                     [&](const auto& chunk) { return chunk.bytes.find(c.ready_line) != std::string::npos; });
    REQUIRE(ready != output.end());
    std::vector<test::EmulatedConsole::Timed> after;
    for (const auto& write : rig.dish.writes()) {
        if (write.at >= ready->at) {
            after.push_back(write);
        }
    }
    REQUIRE_FALSE(after.empty());
    CHECK(after.front().bytes == c.stop_first);  // not a bare line ending or `?` to confirm a prompt first
    const auto stop = std::find_if(after.begin(), after.end(), [&](const auto& w) { return w.bytes == c.stop_last; });
    REQUIRE(stop != after.end());
    if (c.sim_variant == sim::Variant::travler_hal000) {
        // `os`, its prompt, `kill Search`: nothing waits in between (HAL 2.05's documented 0.2 s
        // pause after `ngsearch` is a real-time wait, which dish time here does not measure).
        CHECK(stop->at - ready->at <= 0.3);
    }
    CHECK_FALSE(rig.dish.console().search_running());
}
