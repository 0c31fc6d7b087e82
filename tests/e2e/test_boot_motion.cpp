// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// A dish whose boot moves are still running when the backend starts (the emulator's
// --boot-moves-overlap, sim/README.md), through the stock rotctld: the ready line (or, on the
// silent Pro and 2003 Carryout, the first prompt) comes while the calibration still turns the dish,
// and a calibration that stands still between its legs (--boot-move-pause), or a motor that starts
// seconds after its command, shows two readings that agree while it has not finished. The client's
// first target must still end with the dish on it, and `p` must say so.
//
// The Trav'lers start on the wrap's second branch (mechanical 420, displayed 60), where a reading
// in motion names the wrong branch, with the motor of the dialects cell that failed under load (it
// starts 2.4 s after each command, runs at 26.6 deg/s, brakes at 4.8 deg/s2): there the backend
// took two readings a moment apart for a dish at rest, sent its leg behind the boot's moves, took
// the motor's start-up delay for a stop short and sent a waypoint that the firmware ran last (the
// dish came to rest at azimuth 243.61, halfway from where the boot had left it).
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>
#include <string>

using namespace std::chrono_literals;
using birdcage::sim::Options;
using birdcage::sim::TravlerBootMoves;
using birdcage::sim::Variant;

namespace {

// The Pro's boot is silent: the backend knows it has ended only from a second of quiet on the
// line (and sync pokes), so at 30x the calibration would be over before the backend reads the dish.
constexpr double kTimeScale = 30.0, kSilentBootTimeScale = 10.0;
constexpr double kTargetAz = 150.0, kTargetEl = 40.0;
// Failure bounds in real time (not timing assertions): the calibration crosses the travel twice at
// most (about 50 simulated seconds, under 2 s here), then the leg to the target.
constexpr auto kSettledWithin = 60s;
constexpr auto kReportedWithin = 30s;

struct Cell {
    Variant variant;
    int model;
    TravlerBootMoves moves;
    double pause_s;  // --boot-move-pause
};

std::string cell_name(const Cell& cell) {
    std::ostringstream name;
    name << birdcage::sim::variant_name(cell.variant);
    if (cell.variant != Variant::carryout2003)
        name << " " << birdcage::sim::travler_boot_moves_name(cell.moves);
    name << ", pause " << cell.pause_s << " s";
    return name.str();
}

void run_cell(const Cell& cell) {
    INFO(cell_name(cell));
    const double scale = cell.variant == Variant::travler_pro ? kSilentBootTimeScale : kTimeScale;
    Options o = e2e::dish_options(cell.variant, 420.0, 30.0, scale);
    o.already_booted = false;
    o.travler_boot_moves = cell.moves;
    o.boot_moves_overlap = 1.0;
    o.boot_move_pause = cell.pause_s;
    o.motor.startup_delay = 2.4;
    o.motor.az_velocity = o.motor.el_velocity = 26.6;
    o.motor.accel = 4.8;
    if (cell.variant == Variant::carryout2003) {
        o.start_az = 200.0;  // its travel is 0..360: no second branch
        o.start_el = 50.0;
        o.carryout_search_seconds = 0.0;  // its search off (all DIP switches up, docs/firmware.md §8.2)
    }
    e2e::Rig rig(o, cell.model, {"-C", "time_scale=" + std::to_string(scale)});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.ask("P " + std::to_string(kTargetAz) + " " + std::to_string(kTargetEl), 1) == "RPRT 0\n");
    const bool settled =
        e2e::wait_until([&] { return e2e::settled_at(rig.dish(), kTargetAz, kTargetEl); }, kSettledWithin);
    const birdcage::sim::Pose pose = rig.dish().true_position();
    INFO("dish at az " << pose.az << " el " << pose.el << (rig.dish().moving() ? " (moving)" : " (at rest)")
                       << "; rotctld log, last part:\n"
                       << rig.rotctld_log_text().substr(
                              rig.rotctld_log_text().size() > 4000 ? rig.rotctld_log_text().size() - 4000 : 0));
    REQUIRE(settled);
    e2e::RotctldConnection::Position reported;
    const bool reports = e2e::wait_until(
        [&] {
            reported = client.get_position();
            return reported.ok && e2e::angle_between(reported.az, kTargetAz) <= 0.1 &&
                   std::fabs(reported.el - kTargetEl) <= 0.1;
        },
        kReportedWithin);
    INFO("p: " << reported.az << " " << reported.el << " " << reported.error);
    CHECK(reports);
    // No fault made of the calibration's motion (readings "not repeated", a recovery).
    CHECK(rig.rotctld_log_text().find("recovering:") == std::string::npos);
    CHECK(rig.dish().shell_alive());
}

}  // namespace

TEST_CASE("boot motion: a Trav'ler HAL 0.0.00 still calibrating when the backend starts ends on the target",
          "[e2e][boot-motion]") {
    const TravlerBootMoves moves = GENERATE(TravlerBootMoves::park, TravlerBootMoves::home_return);
    const double pause = GENERATE(0.0, 3.0);
    run_cell({Variant::travler_hal000, 90101, moves, pause});
}

TEST_CASE("boot motion: a Trav'ler HAL 2.05 still calibrating when the backend starts ends on the target",
          "[e2e][boot-motion]") {
    const TravlerBootMoves moves = GENERATE(TravlerBootMoves::park, TravlerBootMoves::home_return);
    const double pause = GENERATE(0.0, 3.0);
    run_cell({Variant::travler_hal205, 90102, moves, pause});
}

TEST_CASE("boot motion: a Trav'ler Pro still calibrating when the backend starts ends on the target",
          "[e2e][boot-motion]") {
    const TravlerBootMoves moves = GENERATE(TravlerBootMoves::park, TravlerBootMoves::home_return);
    const double pause = GENERATE(0.0, 3.0);
    run_cell({Variant::travler_pro, 90103, moves, pause});
}

TEST_CASE("boot motion: a 2003 Carryout still calibrating when the backend starts ends on the target",
          "[e2e][boot-motion]") {
    const double pause = GENERATE(0.0, 3.0);
    run_cell({Variant::carryout2003, 90104, TravlerBootMoves::none, pause});
}
