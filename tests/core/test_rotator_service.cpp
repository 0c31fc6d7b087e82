// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// RotatorService recovery (docs/reliability.md) over scripted consoles: hang-up + reopen, reboot mid-move,
// motor faults. Real threads and short real periods; every wait has a deadline.
#include <catch2/catch.hpp>

#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <thread>

#include "fake_transport.hpp"
#include "service/rotator_service.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;

namespace {

bool eventually(const std::function<bool()>& condition, std::chrono::milliseconds timeout = 5000ms) {
    const auto deadline = Clock::now() + timeout;
    while (Clock::now() < deadline) {
        if (condition()) {
            return true;
        }
        std::this_thread::sleep_for(2ms);
    }
    return condition();
}

ServiceTiming fast_timing() {
    ServiceTiming timing;
    timing.busy_period = 2ms;
    timing.idle_poll_period = 10ms;
    timing.recovery_backoff_min = 2ms;
    timing.recovery_backoff_max = 10ms;
    timing.recovery_boot_slice = 50ms;
    return timing;
}

ControllerOptions g2_options() {
    ControllerOptions options{};
    options.variant = VariantId::carryout_g2;
    options.leapfrog = false;
    options.boot_timeout = 200ms;
    return options;
}

// One G2 console shared by every transport the service opens; the worker is the only caller.
struct Dish {
    std::mutex mutex;
    FakeG2 g2;
    std::atomic<bool> unplug{false};
    std::atomic<bool> reboot{false};
    std::atomic<int> stall{0};
    std::atomic<bool> booting{false};  // answers every line with boot output, never a prompt
    FakeTransport* current = nullptr;

    FakeTransport::Responder responder() {
        return [this](const std::string& command) -> std::vector<std::string> {
            std::lock_guard lock(mutex);
            if (unplug.exchange(false)) {
                current->hang_up();
                return {};
            }
            if (booting) {
                g2.menu = "TRK";
                return {command + "\r\n", "Bootloader v1.01\r\n"};
            }
            if (reboot.exchange(false)) {
                g2.menu = "TRK";
                g2.target_az = g2.az;
                g2.target_el = g2.el;
                return {command + "\r\n", "Bootloader v1.01\r\n", "Boot Complete\r\nTRK>"};
            }
            if (command == "a" && g2.target_az != g2.az && stall.exchange(0) == 1) {  // mid-move only
                g2.extra_lines_after_query = {"AZ MOTOR STALLED"};
                g2.target_az = g2.az;
            }
            return g2.respond(command);
        };
    }
    std::unique_ptr<FakeTransport> open() {
        auto wire = std::make_unique<FakeTransport>(responder());
        current = wire.get();
        return wire;
    }
    double target_az() {
        std::lock_guard lock(mutex);
        return g2.target_az;
    }
};

}  // namespace

TEST_CASE("service: a hung-up port is reopened with backoff, p gives the last reading meanwhile, then works") {
    Dish dish;
    std::atomic<bool> plugged{true};
    std::atomic<int> opens{0};
    TransportFactory reopen = [&]() -> Result<std::unique_ptr<Transport>> {
        ++opens;
        if (!plugged) {
            return {nullptr, Status{Errc::io, "cannot open /dev/ttyUSB0: No such file or directory"}};
        }
        std::lock_guard lock(dish.mutex);
        return {dish.open(), Status::ok()};
    };
    RotatorService service(dish.open(), g2_options(), fast_timing(), reopen);
    REQUIRE(service.start());
    const auto before = service.position();
    REQUIRE(before);
    CHECK(service.answering());

    plugged = false;
    dish.unplug = true;
    REQUIRE(eventually([&] { return service.recovering(); }));
    // The last reading, not an error (a client such as Gpredict gives up for good after a few);
    // answering() and describe() say that the dish cannot be asked.
    const auto p = service.position();
    REQUIRE(p);
    CHECK(p.value.az == Approx(before.value.az));
    CHECK(p.value.el == Approx(before.value.el));
    CHECK_FALSE(service.answering());
    CHECK(service.describe().find("RECOVERING for ") != std::string::npos);
    CHECK(service.describe().find("p gives the last position read") != std::string::npos);
    REQUIRE(eventually([&] { return opens >= 3; }));  // retried with backoff while unplugged
    plugged = true;
    REQUIRE(eventually([&] { return !service.recovering() && static_cast<bool>(service.position()); }));
    CHECK(service.recoveries() == 1);
    CHECK(service.answering());
    REQUIRE(service.set_target({200, 50}));
    CHECK(eventually([&] { return dish.target_az() == Approx(200); }));
}

TEST_CASE("service: a reboot mid-move re-initialises by itself and resumes the latest target") {
    Dish dish;
    RotatorService service(dish.open(), g2_options(), fast_timing());
    REQUIRE(service.start());
    dish.reboot = true;  // the next command meets a rebooting dish
    REQUIRE(service.set_target({250, 40}));
    REQUIRE(eventually([&] { return service.recoveries() == 1; }));
    CHECK(eventually([&] { return dish.target_az() == Approx(250) && service.idle(); }));
    const auto p = service.position();
    REQUIRE(p);
    CHECK(p.value.az == Approx(250));
    CHECK(service.describe().find("recovered 1 time") != std::string::npos);
}

TEST_CASE("service: a motor stall is reported once by position() and kept by last_error()") {
    Dish dish;
    RotatorService service(dish.open(), g2_options(), fast_timing());
    REQUIRE(service.start());
    dish.stall = 1;
    REQUIRE(service.set_target({250, 40}));
    REQUIRE(eventually([&] { return service.last_error().message.find("AZ MOTOR STALLED") != std::string::npos; }));
    Result<AzEl> p = service.position();
    CHECK(p.status.code == Errc::protocol);
    CHECK(p.status.message.find("AZ MOTOR STALLED") != std::string::npos);
    CHECK(service.position());  // once
    CHECK(service.describe().find("AZ MOTOR STALLED") != std::string::npos);
    CHECK(service.recoveries() == 0);  // a fault is reported, not "recovered" from
    REQUIRE(service.set_target({250, 40}));
    CHECK(eventually([&] { return dish.target_az() == Approx(250) && service.idle(); }));
    CHECK(service.last_error());
}

TEST_CASE("service: with a mount model the dish is sent its own axes, clamped there, and position() answers the sky") {
    MountModel mount;
    mount.az_index = 6.0;
    mount.el_index = 0.8;
    mount.tilt_north = 1.2;
    mount.tilt_east = -0.5;
    Dish dish;
    RotatorService service(dish.open(), g2_options(), fast_timing());
    PointingOptions pointing;
    pointing.mode = PointingMode::none;  // each target to the dish as sent: what it receives is the map's alone
    service.set_pointing(pointing);
    service.set_mount(mount);
    REQUIRE(service.start());
    auto dish_target = [&] {
        std::lock_guard lock(dish.mutex);
        return AzEl{dish.g2.target_az, dish.g2.target_el};
    };
    // Readings come in two decimals: 0.005 per axis on the dish, a little more on the sky.
    constexpr double quantum = 0.011;
    auto same = [](AzEl a, AzEl b, double margin) {
        return std::fabs(azimuth_difference(a.az, b.az)) <= margin && std::fabs(a.el - b.el) <= margin;
    };

    // The fake G2 opens at 180 45 on its axes: the client reads where that points.
    Result<AzEl> p = service.position();
    REQUIRE(p);
    CHECK(same(p.value, dish_to_sky(mount, {180, 45}), quantum));

    REQUIRE(service.set_target({180, 40}));
    const AzEl wanted = sky_to_dish(mount, {180, 40});
    INFO("dish axes for 180 40: " << wanted.az << " " << wanted.el);
    REQUIRE(eventually([&] { return same(dish_target(), wanted, 0.005) && service.idle(); }));
    p = service.position();
    REQUIRE(p);
    CHECK(same(p.value, {180, 40}, quantum));

    // Beyond the G2's 65 deg on its own axis: clamped there, and p says where the clamped dish looks.
    REQUIRE(service.set_target({100, 70}));
    REQUIRE(eventually([&] { return dish_target().el == Approx(65.0) && service.idle(); }));
    const AzEl clamped = dish_target();
    CHECK(same(clamped, {sky_to_dish(mount, {100, 70}).az, 65.0}, 0.005));
    p = service.position();
    REQUIRE(p);
    CHECK(same(p.value, dish_to_sky(mount, clamped), quantum));
    CHECK(p.value.el < 70.0 - 1.0);

    // Park is a pose of the mechanism: the dish goes to the variant's park axes exactly.
    REQUIRE(service.park());
    const FirmwareProfile& g2 = service.profile();
    CHECK(eventually([&] { return same(dish_target(), {g2.park_az, g2.park_el}, 0.005) && service.idle(); }));
}

TEST_CASE("service: a dish still booting when opened is initialised in the background, its target kept") {
    Dish dish;
    dish.booting = true;
    RotatorService service(dish.open(), g2_options(), fast_timing());
    // boot_timeout (200 ms) runs out with the boot heard: start() returns, the worker carries on.
    REQUIRE(service.start());
    CHECK(service.initialising());
    CHECK_FALSE(service.answering());
    CHECK(service.position().status.code == Errc::timeout);
    CHECK(service.describe().find("INITIALISING for ") != std::string::npos);
    REQUIRE(service.set_target({250, 40}));  // kept for when the dish is up
    dish.booting = false;
    REQUIRE(eventually([&] { return !service.initialising() && static_cast<bool>(service.position()); }));
    CHECK(service.recoveries() == 0);  // its first initialisation, not a recovery
    CHECK(eventually([&] { return dish.target_az() == Approx(250) && service.idle(); }));
}

TEST_CASE("service: a console that stays silent fails the start at boot_timeout") {
    RotatorService service(std::make_unique<FakeTransport>(), g2_options(), fast_timing());
    const Status started = service.start();
    CHECK(started.code == Errc::timeout);
    CHECK(started.message.find("silent") != std::string::npos);
    CHECK_FALSE(service.initialising());
}
