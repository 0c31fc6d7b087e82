// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Fault injection (docs/reliability.md): each fault observed through the real pty with a tiny client, the
// way the backend will meet it. Deterministic: seeded RNG, time scale and deadlines, no sleeping
// for motion.
#include <catch2/catch.hpp>

#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <chrono>
#include <optional>

#include "birdcage_sim/console.hpp"
#include "birdcage_sim/emulator.hpp"
#include "pty_client.hpp"

using namespace birdcage::sim;
using namespace birdcage::sim::testing;
using namespace std::chrono_literals;

namespace {

Options fast(Variant variant, double time_scale = 50.0) {
    Options options;
    options.variant = variant;
    options.time_scale = time_scale;
    return options;
}

std::string inverted(std::string_view text) {
    std::string out;
    for (const char byte : text)
        out.push_back(static_cast<char>(~static_cast<unsigned char>(byte)));
    return out;
}

bool is_subsequence(std::string_view part, std::string_view whole) {
    std::size_t at = 0;
    for (const char byte : part) {
        at = whole.find(byte, at);
        if (at == std::string_view::npos)
            return false;
        ++at;
    }
    return true;
}

bool path_exists(const std::string& path) {
    struct stat info {};
    return ::lstat(path.c_str(), &info) == 0;
}

// A /dev/pts node's change time, set when its pty is allocated. A process running beside the test
// may be given the same number as soon as the emulator releases it, so a released node is one that
// is gone or was allocated again since (the node's name alone cannot tell).
std::optional<timespec> pty_node_time(const std::string& path) {
    struct stat info {};
    if (::stat(path.c_str(), &info) != 0) {
        return std::nullopt;
    }
    return info.st_ctim;
}

bool pty_node_released(const std::string& path, const std::optional<timespec>& allocated) {
    const auto now = pty_node_time(path);
    return !now || !allocated || now->tv_sec != allocated->tv_sec || now->tv_nsec != allocated->tv_nsec;
}

// The G2's full NVS dump: a long reply (about 10 kB).
std::string nvs_dump_reply(PtyClient& client) {
    REQUIRE(client.command("nvs", "NVS>") == "nvs\r\nNVS>");
    return client.command("d", "NVS>");
}

}  // namespace

TEST_CASE("faults: injected garbage appears on the line, seeded, and the console still works", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    dish.inject_garbage(64);
    const std::string garbage = client.read_count(64);
    REQUIRE(garbage.size() == 64);
    CHECK(client.read_for(50ms).empty());
    CHECK(dish.fault_counters().garbage_bytes == 64);
    CHECK(dish.faults_injected() == 1);
    CHECK(client.command("", "TRK>") == "\r\nTRK>");

    Emulator twin(fast(Variant::carryout_g2));  // same seed: same bytes
    PtyClient twin_client(twin.device_path());
    twin.inject_garbage(64);
    CHECK(twin_client.read_count(64) == garbage);

    Options other = fast(Variant::carryout_g2);
    other.seed = 2;
    Emulator different(other);
    PtyClient different_client(different.device_path());
    different.inject_garbage(64);
    CHECK(different_client.read_count(64) != garbage);
}

TEST_CASE("faults: idle noise streams garbage while the console is quiet, 0 turns it off", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    dish.set_idle_noise(5000.0);
    CHECK(dish.line_faults().idle_noise_bps == 5000.0);
    CHECK(client.read_for(200ms).size() >= 300);  // ~1000 expected
    // Commands still reach the dish; the reply comes through between noise bytes.
    client.send("\r");
    CHECK(client.read_until("TRK>").ends_with("\r\nTRK>"));
    dish.set_idle_noise(0.0);
    client.read_for(50ms);  // drain what was in flight
    CHECK(client.read_for(200ms).empty());
    CHECK(dish.fault_counters().garbage_bytes >= 300);
}

TEST_CASE("faults: swapped RX pair - every byte is the bitwise NOT, input still parsed", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    REQUIRE(client.command("mot", "MOT>") == "mot\r\nMOT>");
    const std::string normal = client.command("a", "MOT>");
    REQUIRE(normal == "a\r\n    Angle[0] = 180.00\r\n    Angle[1] = 45.00\r\nMOT>");
    dish.set_inverted_polarity(true);
    CHECK(client.command("a", inverted("MOT>")) == inverted(normal));
    CHECK(dish.received_commands() == std::vector<std::string>{"mot", "a", "a"});
    dish.set_inverted_polarity(false);
    CHECK(client.command("a", "MOT>") == normal);
}

TEST_CASE("faults: swapped TX pair - the dish silently ignores input", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    dish.set_ignore_input(true);
    client.send("mot\r");
    CHECK(client.read_for(300ms).empty());
    CHECK(dish.received_commands().empty());
    CHECK(dish.fault_counters().ignored_bytes == 4);
    dish.set_ignore_input(false);
    CHECK(client.command("", "TRK>") == "\r\nTRK>");  // still at the root: `mot` never arrived
}

TEST_CASE("faults: dropped bytes - rate about p, seeded so the losses repeat exactly", "[faults]") {
    Emulator reference(fast(Variant::carryout_g2));
    PtyClient reference_client(reference.device_path());
    const std::string full = nvs_dump_reply(reference_client);
    REQUIRE(full.size() > 5000);

    const auto lossy_dump = [&](std::uint32_t seed, std::uint64_t& dropped) {
        Options options = fast(Variant::carryout_g2);
        options.seed = seed;
        Emulator dish(options);
        PtyClient client(dish.device_path());
        REQUIRE(client.command("nvs", "NVS>") == "nvs\r\nNVS>");
        dish.set_drop_probability(0.1);
        client.send("d\r");
        const std::string got = client.read_until_quiet(300ms);
        dropped = dish.fault_counters().dropped_bytes;
        return got;
    };
    std::uint64_t dropped = 0;
    const std::string got = lossy_dump(1, dropped);
    CHECK(got.size() + dropped == full.size());
    CHECK(is_subsequence(got, full));
    CHECK(dropped > full.size() * 7 / 100);
    CHECK(dropped < full.size() * 13 / 100);

    std::uint64_t dropped_again = 0;
    CHECK(lossy_dump(1, dropped_again) == got);
    CHECK(dropped_again == dropped);
    std::uint64_t dropped_other_seed = 0;
    CHECK(lossy_dump(7, dropped_other_seed) != got);
}

TEST_CASE("faults: output paced at the baud rate - a long reply takes bytes x 10 / baud", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    constexpr int baud = 19200;
    dish.set_output_pacing(baud);
    const auto start = std::chrono::steady_clock::now();
    const std::string help = client.command("?", "Raw stepper\r\nTRK>", 10s);
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    REQUIRE(help.size() > 300);
    // Every byte of the reply went out at the paced rate, so it cannot have arrived sooner than
    // the line allows (a lower bound: load can only make it later).
    CHECK(dish.fault_counters().paced_bytes >= help.size());
    CHECK(elapsed >= static_cast<double>(help.size()) * 10.0 / baud);
    dish.set_output_pacing(0);
    const auto paced_before = dish.fault_counters().paced_bytes;
    CHECK(client.command("?", "Raw stepper\r\nTRK>") == help);
    CHECK(dish.fault_counters().paced_bytes == paced_before);  // pacing off: nothing held back
}

TEST_CASE("faults: output stall - nothing for that long, then the buffered input is answered", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));  // 10 simulated s = 200 ms real
    PtyClient client(dish.device_path());
    REQUIRE(client.command("mot", "MOT>") == "mot\r\nMOT>");
    REQUIRE(client.command("a 0 210", "MOT>") == "a 0 210\r\n    Angle = 210.00\r\nMOT>");
    // Judged on the dish's own clock, so a slow test thread cannot make it fail: the first byte
    // of the answer must come after the stall's 10 simulated seconds.
    const double stalled_at = dish.sim_time();
    dish.stall_output(10.0);
    client.send("a\r");
    std::string reply;
    for (int reads = 0; reply.empty() && reads < 1000; ++reads)
        reply = client.read_for(5ms);
    REQUIRE_FALSE(reply.empty());
    CHECK(dish.sim_time() >= stalled_at + 10.0);
    if (reply.find("MOT>") == std::string::npos)
        reply += client.read_until("MOT>", 5s);
    // Motion went on during the stall: the late answer shows the finished move.
    CHECK(reply == "a\r\n    Angle[0] = 210.00\r\n    Angle[1] = 45.00\r\nMOT>");
    CHECK(dish.faults_injected() == 1);
}

TEST_CASE("faults: power cycle mid-move stops the move dead, boots, restarts the search (console)", "[faults][boot]") {
    Options options;
    options.variant = Variant::travler_hal205;
    Console console(options);
    console.feed("motor\ra 0 400\r");
    console.advance(5.0);
    console.take_output();
    REQUIRE(console.moving());
    const double stopped_at = console.mechanical_az();
    REQUIRE(stopped_at > 181.0);
    console.power_cycle();
    console.advance(1.5);  // HAL 2.05 boot: 2 s of silence before the calibration moves
    CHECK(console.mechanical_az() == stopped_at);
    CHECK(console.booting());
    console.feed("\r");  // ignored while booting
    std::string boot;
    for (int i = 0; i < 2000 && console.booting(); ++i) {
        console.advance(0.05);
        boot += console.take_output();
    }
    CHECK(boot == "NoGPS\r\n");
    CHECK(console.search_running());
    console.feed("\r");
    CHECK(console.take_output() == "\r\nTRK>");  // menu back at the root
}

TEST_CASE("faults: G2 power cycle mid-move - boot lines on the pty, root menu, search per NVS 20",
          "[faults][g2][boot]") {
    Options options = fast(Variant::carryout_g2);
    options.search_running = true;  // NVS 20 FALSE: the tracker searches after boot
    Emulator dish(options);
    PtyClient client(dish.device_path());
    REQUIRE(wait_for([&] { return dish.search_running(); }));
    client.send("\r");
    REQUIRE_FALSE(client.read_until("TRK>").empty());
    REQUIRE(client.command("mot", "MOT>") == "mot\r\nMOT>");
    REQUIRE(wait_for([&] { return dish.moving(); }));
    dish.power_cycle();
    CHECK_FALSE(dish.search_running());
    const std::string boot = client.read_until("Loc Startup: IDU NOT Present\r\n", 10s);
    REQUIRE_FALSE(boot.empty());
    CHECK(boot.find("Bootloader version: 1.01\r\n") != std::string::npos);
    // With the tracker on, the boot homes (the search needs calibrated axes): the captured `h *` text.
    CHECK(boot.find("home:0  wrap_pos:0  wrap_min:-42333  wrap_max:2333\r\n") != std::string::npos);
    REQUIRE(wait_for([&] { return dish.search_running(); }));  // the search restarts
    CHECK(client.command("", "TRK>").ends_with("\r\nTRK>"));   // root menu, no TRK> at boot end
    CHECK(dish.faults_injected() == 1);
}

TEST_CASE("faults: hang-up of the pty, and its return at the same link path", "[faults]") {
    Options options = fast(Variant::carryout_g2);
    options.link_path = "/tmp/birdcage-sim-faults-" + std::to_string(::getpid());
    {
        Emulator dish(options);
        PtyClient client(dish.device_path());
        REQUIRE(client.command("mot", "MOT>") == "mot\r\nMOT>");
        REQUIRE(client.command("a 0 300", "MOT>") == "a 0 300\r\n    Angle = 300.00\r\nMOT>");
        char target[256] = {};
        REQUIRE(::readlink(options.link_path.c_str(), target, sizeof target - 1) > 0);
        const std::string old_slave = target;
        REQUIRE(path_exists(old_slave));
        const auto allocated = pty_node_time(old_slave);
        dish.hang_up();
        CHECK(pty_node_released(old_slave, allocated));  // even though the client still holds it open
        CHECK_FALSE(dish.connected());
        CHECK_FALSE(path_exists(options.link_path));
        CHECK(dish.device_path() == options.link_path);
        // The client sees the hang-up: POLLHUP, and read returns 0 (EOF) or fails with EIO.
        CHECK(client.read_for(1s).empty());
        CHECK((client.last_revents & POLLHUP) != 0);
        CHECK((client.last_read == 0 || (client.last_read < 0 && client.last_errno == EIO)));
        UNSCOPED_INFO("read after hang-up: " << client.last_read << " errno " << client.last_errno);
        CHECK(::write(client.fd(), "a\r", 2) < 0);
        // The dish itself keeps running while unplugged.
        REQUIRE(wait_for([&] { return !dish.moving(); }));
        CHECK(dish.true_position().az == Approx(300.0).margin(0.01));

        dish.reconnect();
        CHECK(dish.connected());
        CHECK(dish.device_path() == options.link_path);
        REQUIRE(path_exists(options.link_path));
        PtyClient again(dish.device_path());
        CHECK(again.command("", "MOT>") == "\r\nMOT>");  // the console state survived
        CHECK(again.command("a", "MOT>") == "a\r\n    Angle[0] = 300.00\r\n    Angle[1] = 45.00\r\nMOT>");
        CHECK(dish.faults_injected() == 1);
    }
    CHECK_FALSE(path_exists(options.link_path));
}

TEST_CASE("faults: hang-up without a link - the /dev/pts node goes, reconnect gives a new one", "[faults]") {
    Emulator dish(fast(Variant::carryout_g2));
    const std::string before = dish.device_path();
    const auto allocated = pty_node_time(before);
    REQUIRE(allocated);
    dish.hang_up();
    dish.hang_up();  // idempotent
    CHECK(pty_node_released(before, allocated));
    dish.reconnect();
    dish.reconnect();  // no-op while connected
    REQUIRE(dish.device_path().starts_with("/dev/pts/"));
    PtyClient client(dish.device_path());
    CHECK(client.command("", "TRK>") == "\r\nTRK>");
}

TEST_CASE("faults: AZ motor stall - message, axis short of its target, EL stall ends a g", "[faults][g2]") {
    Options options = fast(Variant::carryout_g2);
    options.g2_console = G2Console::reconstructed;  // `g` is the reconstruction's (the captured MOT> has none)
    Emulator dish(options);
    PtyClient client(dish.device_path());
    REQUIRE(client.command("mot", "MOT>") == "mot\r\nMOT>");
    dish.inject_motor_stall(0);  // arms the next AZ move
    CHECK(client.command("a 0 300", "MOT>") == "a 0 300\r\nAngle = 300.00\r\nMOT>");
    CHECK(client.read_until("\r\n") == "AZ MOTOR STALLED\r\n");
    REQUIRE(wait_for([&] { return !dish.moving(); }));
    const double az = dish.true_position().az;
    CHECK(az > 235.0);  // halfway, within one step of the model
    CHECK(az < 250.0);
    CHECK(dish.fault_counters().motor_stalls == 1);

    dish.inject_motor_stall(1);
    // g: AZ runs first, EL stalls halfway from 45 to 25; the prompt comes when motion ends.
    CHECK(client.command("g 200 25", "MOT>") == "g 200 25\r\nEL MOTOR STALLED\r\nMOT>");
    CHECK(dish.true_position().az == Approx(200.0).margin(0.01));
    CHECK(dish.true_position().el > 33.0);
    CHECK(dish.true_position().el < 37.0);
    CHECK(dish.fault_counters().motor_stalls == 2);

    // One stall per injection: the next move completes.
    client.command("a 1 25", "MOT>");
    REQUIRE(wait_for([&] { return !dish.moving(); }));
    CHECK(dish.true_position().el == Approx(25.0).margin(0.015));
    CHECK(dish.faults_injected() == 2);
}

TEST_CASE("faults: motor stall in the console engine - exact bytes, queued moves dropped", "[faults][hal205]") {
    Options options;
    options.variant = Variant::travler_hal205;
    Console console(options);
    console.feed("motor\r");
    CHECK(console.take_output() == "motor\r\nMOTOR>");
    console.inject_motor_stall(0);
    console.feed("a 0 200\ra 1 60\r");
    CHECK(console.take_output() == "a 0 200\r\nMOTOR>a 1 60\r\nMOTOR>");
    std::string later;
    for (int i = 0; i < 2000 && console.moving(); ++i) {
        console.advance(0.05);
        later += console.take_output();
    }
    CHECK(later == "AZ MOTOR STALLED\r\n");
    CHECK(console.position().az == Approx(190.0).margin(0.5));
    CHECK(console.position().el == 45.0);  // the queued EL move was abandoned
    CHECK(console.motor_stalls() == 1);
}

TEST_CASE("faults: ADC scan deadlock on the pty - only a power cycle recovers", "[faults][g2][hazard]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    REQUIRE(client.command("adc", "ADC>") == "adc\r\nADC>");
    client.send("scan\r");
    CHECK(client.read_until("\r\n") == "scan\r\n");
    CHECK(client.command("", ">", 300ms).empty());
    client.send("\x03\x1bq\rreboot\r");
    CHECK(client.read_for(300ms).empty());
    CHECK_FALSE(dish.shell_alive());
    CHECK(dish.hazards_received() == 1);
    dish.power_cycle();
    CHECK_FALSE(client.read_until("GPS Not Found\r\nTRK>", 10s).empty());
    CHECK(dish.shell_alive());
    CHECK(client.command("", "TRK>") == "\r\nTRK>");
}

TEST_CASE("faults: G2 root q deadlock - Terminating shell, dead console, power cycle recovers",
          "[faults][g2][hazard]") {
    Emulator dish(fast(Variant::carryout_g2));
    PtyClient client(dish.device_path());
    CHECK(client.command("q", "\r\n") == "q\r\n");
    CHECK(client.read_until("\r\n") == "Terminating shell.\r\n");
    CHECK(client.command("", ">", 300ms).empty());
    CHECK(client.command("mot", ">", 300ms).empty());
    CHECK_FALSE(dish.shell_alive());
    CHECK(dish.hazards_received() == 1);
    dish.power_cycle();
    CHECK_FALSE(client.read_until("TRK>", 10s).empty());
    CHECK(client.command("mot", "MOT>") == "mot\r\nMOT>");
}

TEST_CASE("faults: line faults from Options at construction", "[faults]") {
    Options options = fast(Variant::carryout_g2);
    options.line_faults.inverted_polarity = true;
    Emulator dish(options);
    CHECK(dish.line_faults().inverted_polarity);
    PtyClient client(dish.device_path());
    CHECK(client.command("", inverted("TRK>")) == inverted("\r\nTRK>"));
}
