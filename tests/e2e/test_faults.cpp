// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End to end under line and dish faults (docs/reliability.md): emulator with fault injection <- pty <- stock
// /usr/bin/rotctld + preloaded backend <- one TCP client connection (like Gpredict's), plus bad
// client input. Recovery times are printed (WARN) and collected in docs/reliability.md.
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <algorithm>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

using namespace std::chrono_literals;
using birdcage::sim::Variant;
using Clock = std::chrono::steady_clock;

namespace {

constexpr int kG2 = 90105;
constexpr double kG2ElMin = 18.0;
constexpr double kG2ElMax = 65.0;

birdcage::sim::Options g2_at(double az, double el, double time_scale = 50.0) {
    return e2e::dish_options(Variant::carryout_g2, az, el, time_scale);
}

// The position the backend reports matches the dish's true one (dish at rest).
bool reports_true_position(e2e::RotctldConnection& client, birdcage::sim::Emulator& dish) {
    const auto p = client.get_position();
    const birdcage::sim::Pose truth = dish.true_position();
    return p.ok && e2e::angle_between(p.az, truth.az) <= 0.1 && std::fabs(p.el - truth.el) <= 0.1;
}

std::string temp_link(const char* what) {
    return "/tmp/birdcage-e2e-" + std::string(what) + "-" + std::to_string(::getpid()) + "-" +
           std::to_string(Clock::now().time_since_epoch().count());
}

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

long rss_kib(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) {
            return std::stol(line.substr(6));
        }
    }
    return -1;
}

bool elevation_stayed_in_limits(birdcage::sim::Emulator& dish) {
    for (const auto& s : dish.history()) {
        if (s.el < kG2ElMin - 0.05 || s.el > kG2ElMax + 0.05) {
            return false;
        }
    }
    return true;
}

}  // namespace

TEST_CASE("faults: idle garbage and noise during tracking leave the position exact", "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    rig.dish().set_idle_noise(200.0);
    const double targets[][2] = {{120.0, 35.0}, {140.0, 40.0}};
    int wrong_positions = 0;
    for (const auto& t : targets) {
        rig.dish().inject_garbage(64);
        REQUIRE(client.ask("P " + std::to_string(t[0]) + " " + std::to_string(t[1]), 1) == "RPRT 0\n");
        REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), t[0], t[1]); }, 8s));
        REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
        // From then on every position reported at rest is the true one (errors allowed, garbage never).
        const auto until = Clock::now() + 1200ms;
        while (Clock::now() < until) {
            const auto p = client.get_position();
            if (p.ok && (e2e::angle_between(p.az, t[0]) > 0.1 || std::fabs(p.el - t[1]) > 0.1)) {
                ++wrong_positions;
            }
            std::this_thread::sleep_for(100ms);
        }
    }
    const auto counters = rig.dish().fault_counters();
    WARN("idle noise: " << counters.garbage_bytes << " garbage bytes on the line, " << wrong_positions
                        << " reported positions off the truth at rest");
    CHECK(counters.garbage_bytes > 0);
    CHECK(wrong_positions == 0);
    CHECK(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("faults: inverted polarity: p keeps the last reading and s says BUSY until the pair is fixed",
          "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.get_position().ok);
    rig.dish().set_inverted_polarity(true);
    const auto t0 = Clock::now();
    int errors = 0;
    // Never a position parsed from inverted bytes, and never an error: the last reading.
    const auto p_is_the_last_reading = [&] {
        const auto p = client.get_position();
        if (!p.ok) {
            ++errors;
            return false;
        }
        return e2e::angle_between(p.az, 100.0) <= 0.1 && std::fabs(p.el - 30.0) <= 0.1;
    };
    REQUIRE(e2e::wait_until(
        [&] {
            CHECK(p_is_the_last_reading());
            return client.ask("s", 1).find("BUSY") != std::string::npos;
        },
        10s));
    const double detect_s = seconds_since(t0);
    CHECK(client.ask("_", 1).find("p gives the last position read") != std::string::npos);
    CHECK(p_is_the_last_reading());
    rig.dish().set_inverted_polarity(false);
    const auto t1 = Clock::now();
    REQUIRE(e2e::wait_until([&] { return client.ask("s", 1).find("BUSY") == std::string::npos; }, 10s));
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 10s));
    const double recover_s = seconds_since(t1);
    WARN("inverted polarity: s reports BUSY " << detect_s << " s after the fault (p errors: " << errors
                                              << "); the dish answers again " << recover_s
                                              << " s after the pair is fixed");
    CHECK(errors == 0);
    REQUIRE(client.ask("P 150 40", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0); }, 8s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("faults: the dish reboots mid-move, the backend re-initialises and resumes", "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.ask("P 300 50", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return rig.dish().moving(); }, 5s));
    rig.dish().power_cycle();
    const auto t0 = Clock::now();
    int errors = 0;
    const bool resumed = e2e::wait_until(
        [&] {
            const auto p = client.get_position();
            errors += p.ok ? 0 : 1;
            return e2e::settled_at(rig.dish(), 300.0, 50.0);
        },
        9s);
    const double resume_s = seconds_since(t0);
    CHECK(resumed);
    // While the dish reboots p gives the last reading (test_client_faults.cpp: through long boots).
    CHECK(errors == 0);
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    const std::string info = client.ask("_", 1);
    CHECK(info.find("recovered 1 time") != std::string::npos);
    WARN("reboot mid-move: at the pending target again " << resume_s << " s after the power cycle (time scale 50)");
    REQUIRE(client.ask("P 200 40", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 40.0); }, 8s));
    CHECK(rig.dish().hazards_received() == 0);
}

// A G2 boot of about 25 simulated seconds (2 s between boot lines, then homing to AZ 0, EL 65):
// a G2 whose boot homes (the captured unit's does not; §6.2 leaves it a switch), so that the
// position after the boot differs from the last reading.
TEST_CASE("faults: while the dish reboots p gives its last reading, s BUSY and _ why, P is kept and S drops it",
          "[e2e][faults]") {
    auto options = g2_at(100.0, 30.0, 10.0);
    options.boot_line_gap = 2.0;
    options.g2_boot_homes = true;
    e2e::Rig rig(options, kG2, {"-C", "leapfrog=0", "-C", "time_scale=10"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(reports_true_position(client, rig.dish()));
    int errors = 0;
    auto last_reading = [&](double az, double el) {
        const auto p = client.get_position();
        errors += p.ok ? 0 : 1;
        return p.ok && e2e::angle_between(p.az, az) <= 0.01 && std::fabs(p.el - el) <= 0.01;
    };

    rig.dish().power_cycle();
    REQUIRE(e2e::wait_until(
        [&] {
            CHECK(last_reading(100.0, 30.0));
            return client.ask("s", 1).find("BUSY") != std::string::npos;
        },
        10s));
    const std::string info = client.ask("_", 1);
    CHECK(info.rfind("Winegard Carryout G2: RECOVERING; last known: ", 0) == 0);  // in what netrotctl shows
    CHECK(info.find("RECOVERING for ") != std::string::npos);
    CHECK(info.find("rebooted") != std::string::npos);
    CHECK(last_reading(100.0, 30.0));
    // Kept for after the recovery, clamped then as ever (the G2 tops out at 65 deg).
    REQUIRE(client.ask("P 200 89", 1) == "RPRT 0\n");
    // The first position that is not the last reading is a fresh one: the boot left the dish at
    // EL 65 (homing), and the target keeps it there.
    e2e::RotctldConnection::Position fresh;
    REQUIRE(e2e::wait_until(
        [&] {
            const auto p = client.get_position();
            errors += p.ok ? 0 : 1;
            if (p.ok && !(e2e::angle_between(p.az, 100.0) <= 0.01 && std::fabs(p.el - 30.0) <= 0.01)) {
                fresh = p;
                return true;
            }
            return false;
        },
        20s));
    CHECK(fresh.el == Approx(kG2ElMax).margin(0.1));
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, kG2ElMax); }, 20s));
    CHECK(client.ask("_", 1).find("recovered 1 time") != std::string::npos);

    // S while it reboots drops a target set before it: the boot leaves the dish homed at AZ 0.
    const std::size_t commands_before = rig.dish().received_commands().size();
    rig.dish().power_cycle();
    REQUIRE(e2e::wait_until([&] { return client.ask("s", 1).find("BUSY") != std::string::npos; }, 10s));
    REQUIRE(client.ask("P 150 40", 1) == "RPRT 0\n");
    REQUIRE(client.ask("S", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return client.ask("_", 1).find("recovered 2 time") != std::string::npos; }, 20s));
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    CHECK(e2e::settled_at(rig.dish(), 0.0, kG2ElMax));
    const auto commands = rig.dish().received_commands();
    const auto moves =
        std::count_if(commands.begin() + static_cast<std::ptrdiff_t>(commands_before), commands.end(),
                      [](const std::string& c) { return c.rfind("a 0 ", 0) == 0 || c.rfind("a 1 ", 0) == 0; });
    CHECK(moves == 0);
    CHECK(errors == 0);
    CHECK(rig.dish().hazards_received() == 0);
}

namespace {

struct RebootCase {
    Variant variant;
    int model;
    const char* name;
};

void reboot_mid_move_resumes(const RebootCase& v) {
    auto options = g2_at(100.0, 30.0, 20.0);
    options.variant = v.variant;
    e2e::Rig rig(options, v.model, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.ask("P 200 40", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return rig.dish().moving(); }, 5s));
    rig.dish().power_cycle();
    const auto t0 = Clock::now();
    const bool resumed = e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 40.0, 0.6); }, 20s);
    if (!resumed) {
        FAIL(rig.rotctld_log_text());
    }
    WARN(v.name << ": reboot mid-move, at the pending target again " << seconds_since(t0)
                << " s after the power cycle (time scale 20)");
    CHECK(rig.dish().hazards_received() == 0);
}

}  // namespace

// Not the Carryout 2003: it prints no boot lines and is only listened to during `g`, so a reboot
// mid-move goes unnoticed until the next command (docs/reliability.md, known limits).
TEST_CASE("faults: reboot mid-move, Trav'ler HAL variants", "[e2e][faults][variants]") {
    for (const RebootCase& v :
         {RebootCase{Variant::travler_hal000, 90101, "hal000"}, RebootCase{Variant::travler_hal205, 90102, "hal205"}}) {
        DYNAMIC_SECTION(v.name) {
            reboot_mid_move_resumes(v);
        }
    }
}

// The Pro prints no boot lines either: the reboot shows as its IDU> prompt answering a poll.
TEST_CASE("faults: reboot mid-move, Trav'ler Pro and Carryout G2", "[e2e][faults][variants]") {
    for (const RebootCase& v :
         {RebootCase{Variant::travler_pro, 90103, "pro"}, RebootCase{Variant::carryout_g2, 90105, "g2"}}) {
        DYNAMIC_SECTION(v.name) {
            reboot_mid_move_resumes(v);
        }
    }
}

TEST_CASE("faults: unplug and replug, rotctld and the client connection survive", "[e2e][faults]") {
    auto options = g2_at(100.0, 30.0);
    options.link_path = temp_link("unplug");
    e2e::Rig rig(options, kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.get_position().ok);

    rig.dish().hang_up();
    const auto t0 = Clock::now();
    const bool noticed = e2e::wait_until(
        [&] {
            // The last reading meanwhile, never an error: the dish is where it was.
            const auto p = client.get_position();
            CHECK((p.ok && e2e::angle_between(p.az, 100.0) <= 0.1 && std::fabs(p.el - 30.0) <= 0.1));
            return client.ask("s", 1).find("BUSY") != std::string::npos;
        },
        5s);
    if (!noticed) {
        FAIL(rig.rotctld_log_text());
    }
    const double detect_s = seconds_since(t0);
    CHECK(client.ask("_", 1).find("hung up") != std::string::npos);
    // Still unplugged: the last reading, and the connection stays open.
    for (int i = 0; i < 5; ++i) {
        CHECK(client.get_position().ok);
    }
    // A target set meanwhile is kept for the dish.
    CHECK(client.ask("P 150 40", 1) == "RPRT 0\n");
    CHECK(rig.rotctld_running());

    rig.dish().reconnect();
    const auto t1 = Clock::now();
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0); }, 9s));
    const double resumed_s = seconds_since(t1);
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    CHECK(client.ask("s", 1).find("BUSY") == std::string::npos);
    WARN("unplug: s reports BUSY " << detect_s << " s after the hang-up; the target set while unplugged is reached "
                                   << resumed_s << " s after the replug");
    REQUIRE(client.ask("P 200 35", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 35.0); }, 8s));
    CHECK(rig.rotctld_running());
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("faults: a motor stall is reported once with the firmware's message, then moves work", "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    rig.dish().inject_motor_stall(0);
    REQUIRE(client.ask("P 200 30", 1) == "RPRT 0\n");
    const auto t0 = Clock::now();
    REQUIRE(e2e::wait_until([&] { return client.get_position().error == "RPRT -8"; }, 8s));
    const double report_s = seconds_since(t0);
    CHECK(rig.dish().fault_counters().motor_stalls == 1);
    CHECK(e2e::angle_between(rig.dish().true_position().az, 200.0) > 10.0);  // stopped short
    CHECK(client.ask("_", 1).find("AZ MOTOR STALLED") != std::string::npos);
    // Reported once: the next p answers with the position again.
    CHECK(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    // The same target again retries the move.
    REQUIRE(client.ask("P 200 30", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 200.0, 30.0); }, 8s));
    WARN("motor stall: reported by p " << report_s << " s after the P");
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("faults: an output stall: p answers at once with the last reading, s says BUSY", "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.get_position().ok);
    rig.dish().stall_output(350.0);  // 7 s real at time scale 50
    const auto t0 = Clock::now();
    double slowest = 0;
    int errors = 0;
    double busy_from_s = -1;
    while (seconds_since(t0) < 7.0) {
        const auto asked = Clock::now();
        const auto p = client.get_position();
        slowest = std::max(slowest, seconds_since(asked));
        if (p.ok) {
            CHECK(e2e::angle_between(p.az, 100.0) <= 0.1);
        } else {
            ++errors;
        }
        if (busy_from_s < 0 && client.ask("s", 1).find("BUSY") != std::string::npos) {
            busy_from_s = seconds_since(t0);
        }
        std::this_thread::sleep_for(100ms);
    }
    const auto t1 = Clock::now();
    REQUIRE(e2e::wait_until([&] { return client.ask("s", 1).find("BUSY") == std::string::npos; }, 8s));
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 8s));
    WARN("output stall 7 s: slowest p answer " << slowest << " s; " << errors << " p errors; s BUSY from "
                                               << busy_from_s << " s into the stall; answering again "
                                               << seconds_since(t1) << " s after the stall");
    CHECK(slowest < 1.0);
    CHECK(errors == 0);
    CHECK(busy_from_s > 0);
    if (busy_from_s < 0) {
        FAIL(rig.rotctld_log_text());
    }
    REQUIRE(client.ask("P 150 40", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 150.0, 40.0); }, 8s));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("faults: dropped bytes never produce a garbage position", "[e2e][faults]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    rig.dish().set_drop_probability(0.03);
    REQUIRE(client.ask("P 130 40", 1) == "RPRT 0\n");
    REQUIRE(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 130.0, 40.0); }, 9s));
    REQUIRE(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    int good = 0, errors = 0, wrong = 0;
    const auto until = Clock::now() + 2500ms;
    while (Clock::now() < until) {
        const auto p = client.get_position();
        if (!p.ok) {
            ++errors;
        } else if (e2e::angle_between(p.az, 130.0) <= 0.1 && std::fabs(p.el - 40.0) <= 0.1) {
            ++good;
        } else {
            ++wrong;
        }
        std::this_thread::sleep_for(50ms);
    }
    WARN("3% dropped bytes: " << rig.dish().fault_counters().dropped_bytes << " bytes lost; p at rest: " << good
                              << " exact, " << errors << " errors, " << wrong << " wrong");
    CHECK(wrong == 0);
    CHECK(good > 0);
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("bad client input: refused or clamped, never a crash or a hazardous move", "[e2e][faults][input]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    CHECK(client.ask("P nan 45", 1) == "RPRT -1\n");
    CHECK(client.ask("P inf 45", 1) == "RPRT -1\n");
    CHECK(client.ask("P 1e9 45", 1) == "RPRT -1\n");
    CHECK(client.ask("P 180 -5", 1) == "RPRT -1\n");
    CHECK(client.ask("P 180 95", 1) == "RPRT -1\n");
    // Unknown commands: stock rotctld answers nothing; the connection keeps working.
    REQUIRE(client.send_raw("Z\n"));
    REQUIRE(client.send_raw("\\no_such_command\n"));
    // A partial line, completed later: rotctld waits for the rest.
    REQUIRE(client.send_raw("P 120"));
    std::this_thread::sleep_for(200ms);
    REQUIRE(client.send_raw(" 40\n"));
    CHECK(client.read_lines(1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, 40.0); }, 8s));
    // Elevation within the caps but beyond the G2's limit is clamped.
    CHECK(client.ask("P 120 89", 1) == "RPRT 0\n");
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 120.0, kG2ElMax); }, 8s));
    CHECK(rig.rotctld_running());
    CHECK(elevation_stayed_in_limits(rig.dish()));
    CHECK(rig.dish().hazards_received() == 0);
}

TEST_CASE("bad client input: a flood of 1000 P on one connection", "[e2e][faults][input]") {
    e2e::Rig rig(g2_at(100.0, 30.0), kG2, {"-C", "leapfrog=0"});
    e2e::RotctldConnection client(rig.port());
    REQUIRE(client.get_position().ok);
    const long rss_before = rss_kib(rig.rotctld_pid());
    std::ostringstream flood;
    for (int i = 0; i < 1000; ++i) {
        flood << "P " << (100 + (i % 90)) << " " << (20 + (i % 40)) << "\n";
    }
    flood << "P 222 33\n";
    const auto t0 = Clock::now();
    REQUIRE(client.send_raw(flood.str()));
    const std::string replies = client.read_lines(1001, 20s);
    const double answered_s = seconds_since(t0);
    int ok = 0;
    std::istringstream in(replies);
    for (std::string line; std::getline(in, line);) {
        ok += line == "RPRT 0";
    }
    CHECK(ok == 1001);
    CHECK(e2e::wait_until([&] { return e2e::settled_at(rig.dish(), 222.0, 33.0); }, 9s));
    const long rss_after = rss_kib(rig.rotctld_pid());
    WARN("1001 P on one connection answered in " << answered_s << " s; rotctld RSS " << rss_before << " -> "
                                                 << rss_after << " KiB");
    // What keeps memory bounded: P keeps only the latest target, so the flood is coalesced into
    // far fewer moves than targets.
    const auto commands = rig.dish().received_commands();
    const auto moves = std::count_if(commands.begin(), commands.end(), [](const std::string& c) {
        return c.rfind("a 0 ", 0) == 0 || c.rfind("a 1 ", 0) == 0;
    });
    CHECK(moves < 500);
#ifndef BIRDCAGE_SANITIZER_RUNTIME
    // Under AddressSanitizer the freed memory sits in its quarantine, so RSS measures the
    // allocator, not the backend; the check holds for the real build only.
    CHECK(rss_after - rss_before < 4096);
#endif
    CHECK(e2e::wait_until([&] { return reports_true_position(client, rig.dish()); }, 5s));
    CHECK(elevation_stayed_in_limits(rig.dish()));
    CHECK(rig.dish().hazards_received() == 0);
}
