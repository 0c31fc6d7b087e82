// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end, per firmware variant: every unknown-behaviour switch of the emulator, and the
// start-up situations of real life (already booted, still booting, left inside a submenu, search
// running or already stopped, skip_init). Each case: rotctld opens the dish (init), then P, p, S.
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <sstream>

using namespace std::chrono_literals;
using birdcage::sim::Options;
using birdcage::sim::Variant;

namespace {

struct Setting {
    std::string name;
    std::function<void(Options&)> apply;
    std::vector<std::string> rotctld_args = {};
    std::function<void(birdcage::sim::Emulator&)> prepare = {};
};

struct VariantUnderTest {
    Variant variant;
    int model;
    const char* name;
    double el_min, el_max;
    std::vector<std::string> motor_menu_keys;  // what a user types to reach the motor menu
};

const VariantUnderTest kHal000{Variant::travler_hal000, 90101, "hal000", 15.0, 90.0, {"mot"}};
const VariantUnderTest kHal205{Variant::travler_hal205, 90102, "hal205", 15.0, 90.0, {"motor"}};
const VariantUnderTest kPro{Variant::travler_pro, 90103, "pro", 12.0, 75.0, {"odu", "mot"}};
const VariantUnderTest kCarryout{Variant::carryout2003, 90104, "carryout2003", 22.0, 73.0, {"target"}};
const VariantUnderTest kG2{Variant::carryout_g2, 90105, "g2", 18.0, 65.0, {"mot"}};

// init (rotctld open) + P + p + S through stock rotctld; no hazard may reach the dish.
void init_move_report_stop(const VariantUnderTest& v, const Setting& s, double time_scale = 50.0) {
    Options o;
    o.variant = v.variant;
    o.time_scale = time_scale;
    o.start_az = 100.0;
    o.start_el = 30.0;
    s.apply(o);
    std::vector<std::string> args = {"-C", "leapfrog=0"};
    args.insert(args.end(), s.rotctld_args.begin(), s.rotctld_args.end());
    e2e::Rig rig(o, v.model, args, s.prepare);
    INFO(v.name << " / " << s.name);

    const e2e::CommandResult set = rig.rotctl({"P", "150", "40"});
    INFO(set.out << set.err);
    REQUIRE(set.exit_code == 0);
    const bool settled = e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0, 0.1); }, 30s);
    INFO("dish at " << rig.dish().true_position().az << " " << rig.dish().true_position().el);
    if (!settled) {
        INFO(rig.rotctld_log_text());
        CHECK(settled);
    }
    std::vector<double> reported;
    const bool reports = e2e::wait_until(
        [&] {
            reported = e2e::numbers(rig.rotctl({"p"}).out);
            return reported.size() == 2 && e2e::angle_between(reported[0], 150.0) <= 0.1 &&
                   std::fabs(reported[1] - 40.0) <= 0.1;
        },
        10s);
    CHECK(reports);
    const e2e::CommandResult stop = rig.rotctl({"S"});
    CHECK(stop.exit_code == 0);
    CHECK(rig.dish().hazards_received() == 0);
    CHECK(rig.dish().shell_alive());
}

std::vector<Setting> common_switches() {
    return {
        {"defaults", [](Options&) {}},
        {"echo off", [](Options& o) { o.echo = false; }},
        {"LF line endings", [](Options& o) { o.line_ending = birdcage::sim::LineEnding::lf; }},
        {"unknown command prints nothing", [](Options& o) { o.unknown_command_reply = ""; }},
        {"unknown command prints ?", [](Options& o) { o.unknown_command_reply = "?"; }},
        {"unknown command prints an error with >",
         [](Options& o) { o.unknown_command_reply = "Error: bad command -> type ? for help"; }},
        {"out-of-range rejected", [](Options& o) { o.out_of_range = birdcage::sim::OutOfRange::reject; }},
    };
}

std::vector<Setting> position_query_switches() {
    return {
        {"position answered only at rest", [](Options& o) { o.answer_position_while_moving = false; }},
        {"azimuth reported mechanically", [](Options& o) { o.az_report = birdcage::sim::AzReport::mechanical; }},
        {"move acknowledged after the motion", [](Options& o) { o.move_ack = birdcage::sim::MoveAck::after_motion; }},
    };
}

Setting bare_prompts() {
    return {"bare > prompts", [](Options& o) { o.prompt_style = birdcage::sim::PromptStyle::bare; }};
}

// `>` at the root, `MOT>` in the motor menu, where the backend finds the console.
Setting bare_root_left_in_motor_menu(const VariantUnderTest& v) {
    const std::vector<std::string> keys = v.motor_menu_keys;
    return {"bare > root, named submenus, left inside the motor menu",
            [](Options& o) { o.prompt_style = birdcage::sim::PromptStyle::bare_root; },
            {},
            [keys](birdcage::sim::Emulator& dish) { e2e::type_into(dish, keys); }};
}

void run_all(const VariantUnderTest& v, const std::vector<Setting>& settings) {
    for (const Setting& s : settings) {
        DYNAMIC_SECTION(s.name) {
            init_move_report_stop(v, s);
        }
    }
}

template <class... Lists>
std::vector<Setting> concat(Lists... lists) {
    std::vector<Setting> out;
    (out.insert(out.end(), lists.begin(), lists.end()), ...);
    return out;
}

// Start-up situations every variant must cope with.
std::vector<Setting> init_situations(const VariantUnderTest& v) {
    const std::vector<std::string> keys = v.motor_menu_keys;
    return {
        {"still booting", [](Options& o) { o.already_booted = false; }},
        {"left inside the motor menu",
         [](Options&) {},
         {},
         [keys](birdcage::sim::Emulator& dish) { e2e::type_into(dish, keys); }},
        {"skip_init with the motor menu open",
         [](Options&) {},
         {"-C", "skip_init=1"},
         [keys](birdcage::sim::Emulator& dish) { e2e::type_into(dish, keys); }},
        {"left inside the nvs menu",
         [](Options&) {},
         {},
         [v](birdcage::sim::Emulator& dish) {
             if (v.variant == Variant::travler_pro) {
                 e2e::type_into(dish, {"odu", "nvs"});
             } else {
                 e2e::type_into(dish, {"nvs"});
             }
         }},
    };
}

const std::vector<Setting> search_running = {
    {"TV search running", [](Options& o) { o.search_running = true; }},
};

}  // namespace

TEST_CASE("hal000: every unknown-behaviour switch and start-up situation", "[e2e][variants][hal000]") {
    run_all(kHal000, concat(common_switches(), position_query_switches(),
                            std::vector<Setting>{bare_prompts(), bare_root_left_in_motor_menu(kHal000)},
                            init_situations(kHal000), search_running));
}

TEST_CASE("hal205: every unknown-behaviour switch and start-up situation", "[e2e][variants][hal205]") {
    const std::vector<Setting> own = {
        bare_prompts(),
        {"mot accepted besides motor", [](Options& o) { o.hal205_accepts_mot = true; }},
        {"booting, boot marker No LNB Voltage",
         [](Options& o) {
             o.already_booted = false;
             o.hal205_boot_marker = birdcage::sim::BootMarker::no_lnb_voltage;
         }},
    };
    run_all(kHal205,
            concat(common_switches(), position_query_switches(), own, init_situations(kHal205), search_running));
}

TEST_CASE("pro: every unknown-behaviour switch and start-up situation", "[e2e][variants][pro]") {
    const std::vector<Setting> own = {
        bare_prompts(),
        {"q at the ODU root returns to the IDU", [](Options& o) { o.pro_q_at_odu_root_returns_to_idu = true; }},
        {"q returns to the IDU, left inside the ODU motor menu",
         [](Options& o) { o.pro_q_at_odu_root_returns_to_idu = true; },
         {},
         [](birdcage::sim::Emulator& dish) {
             e2e::type_into(dish, {"odu", "mot"});
         }},
    };
    run_all(kPro, concat(common_switches(), position_query_switches(), own, init_situations(kPro), search_running));
}

TEST_CASE("carryout2003: every unknown-behaviour switch and start-up situation", "[e2e][variants][carryout2003]") {
    const std::vector<Setting> own = {
        bare_prompts(),
        bare_root_left_in_motor_menu(kCarryout),
        {"g not aborted by input", [](Options& o) { o.g_aborts_on_input = false; }},
    };
    // No TV-search case: the 2003 Carryout's search cannot be stopped from the console (8.2).
    run_all(kCarryout, concat(common_switches(), own, init_situations(kCarryout)));
}

TEST_CASE("g2: every unknown-behaviour switch and start-up situation", "[e2e][variants][g2]") {
    const std::vector<Setting> own = {
        {"q at TRK> does not kill the shell", [](Options& o) { o.g2_root_q = birdcage::sim::G2RootQ::harmless; }},
        {"q at TRK> restarts the shell", [](Options& o) { o.g2_root_q = birdcage::sim::G2RootQ::restart; }},
        {"RSSI floor 500", [](Options& o) { o.rssi_floor = 500.0; }},
        {"moves overshoot as captured", [](Options& o) { o.g2_overshoot = true; }},
        // The console this emulator played before the captures: paraphrased boot with homing,
        // `Enter <cmd> - ...` help, `Unknown command`, no indentation, `g` in MOT>.
        {"reconstructed console", [](Options& o) { o.g2_console = birdcage::sim::G2Console::reconstructed; }},
        {"booting, reconstructed console",
         [](Options& o) {
             o.already_booted = false;
             o.g2_console = birdcage::sim::G2Console::reconstructed;
         }},
        // One more boot line after `GPS Not Found` that nobody documented, shaped like a boot
        // marker: the dish is up once two pokes find TRK>, whatever that last line said.
        {"booting, one more line after the last boot line",
         [](Options& o) {
             o.already_booted = false;
             o.after_boot_line = "Motor init: wrap manager on";
         }},
    };
    run_all(kG2, concat(common_switches(), position_query_switches(), own, init_situations(kG2)));
}
