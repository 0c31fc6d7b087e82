// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The rotator service's mailbox and worker driven by hand: no thread, a manual dish clock, and the
// worker's step() called at chosen points between the callers' posts. Every interleaving of `P`,
// `S` and worker steps ends the way the client's last command says.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fake_transport.hpp"
#include "service/service_mailbox.hpp"
#include "service/service_worker.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;

namespace {

// A scripted dish behind a fake wire, the service's mailbox and worker, and a clock the test
// advances. The dish comes first so that it outlives the worker that talks to it.
template <class Dish>
struct HandDriven {
    Dish dish;
    FakeTransport* wire = nullptr;
    Clock::time_point now = Clock::time_point{} + 1h;
    ServiceMailbox mailbox;
    std::unique_ptr<ServiceWorker> worker;

    // No leapfrog (each test sees its own moves), a short boot wait, and the test's clock.
    ControllerOptions options_for(VariantId variant) {
        ControllerOptions options{};
        options.variant = variant;
        options.leapfrog = false;
        options.boot_timeout = 200ms;
        options.clock = DishClock::manual([this] { return now; });
        return options;
    }
    void step() {
        const Clock::duration wait = worker->step();
        now += std::max<Clock::duration>(wait, 1ms);
    }
    // Steps the worker through `dish_time` of the dish's clock.
    void run_for(Clock::duration dish_time) {
        const Clock::time_point until = now + dish_time;
        for (int i = 0; i < 1000 && now < until; ++i) {
            step();
        }
    }
};

// A G2 behind a scripted console.
struct HandDrivenService : HandDriven<FakeG2> {
    // `lnb_polarity`: the tuner's `dis` value (FakeG2::lnb_polarity), none: it lists nothing.
    explicit HandDrivenService(std::optional<std::string> lnb_polarity = std::nullopt) {
        dish.step_per_query = 7.0;  // a move takes several polls, so posts can land mid-move
        dish.lnb_polarity = std::move(lnb_polarity);
        auto transport = std::make_unique<FakeTransport>([this](const std::string& c) { return respond(c); });
        wire = transport.get();
        // The same dish again over a new port after a hang-up (the adapter plugged back).
        TransportFactory reopen = [this]() -> Result<std::unique_ptr<Transport>> {
            auto again = std::make_unique<FakeTransport>([this](const std::string& c) { return respond(c); });
            wire = again.get();
            return {std::move(again), Status::ok()};
        };
        worker = std::make_unique<ServiceWorker>(mailbox, std::move(transport), options_for(VariantId::carryout_g2),
                                                 ServiceTiming{}, reopen);
        PointingOptions pointing;
        pointing.mode = PointingMode::none;
        worker->set_pointing(pointing);
        REQUIRE(worker->start());
        mailbox.open();
    }

    // Set: the next command meets the dish rebooting (power cycled); its boot homes the axes.
    bool reboot_at_next_command = false;
    std::vector<std::string> respond(const std::string& command) {
        if (std::exchange(reboot_at_next_command, false)) {
            dish.menu = "TRK";
            dish.az = dish.target_az = 0.0;
            dish.el = dish.target_el = 65.0;
            return {command + "\r\n", "Bootloader v1.01\r\n", "Boot Complete\r\nTRK>"};
        }
        return dish.respond(command);
    }
    // Steps until the worker has met the reboot and entered its recovery.
    void step_into_recovery() {
        reboot_at_next_command = true;
        for (int i = 0; i < 50 && !mailbox.view().dish.recovering; ++i) {
            step();
        }
        REQUIRE(mailbox.view().dish.recovering);
    }

    // Steps until a recovery under way has ended.
    void recover() {
        for (int i = 0; i < 200 && mailbox.view().dish.recovering; ++i) {
            step();
        }
        REQUIRE_FALSE(mailbox.view().dish.recovering);
    }
    // Steps until the service reports idle (nothing in flight, queued or posted).
    void drain() {
        for (int i = 0; i < 500 && !mailbox.view().idle; ++i) {
            step();
        }
        REQUIRE(mailbox.view().idle);
    }
    // Motor commands (`a <axis> <deg>`) the worker has written so far.
    std::size_t moves_sent() const {
        const auto& sent = wire->commands();
        return static_cast<std::size_t>(std::count_if(sent.begin(), sent.end(), [](const std::string& c) {
            return c.rfind("a 0 ", 0) == 0 || c.rfind("a 1 ", 0) == 0;
        }));
    }
};

struct Post {
    bool stop = false;
    AzEl target{};
};

std::string describe(const std::vector<Post>& posts, unsigned steps_after) {
    std::string text;
    for (std::size_t i = 0; i < posts.size(); ++i) {
        text += posts[i].stop ? "S" : "P(" + std::to_string(static_cast<int>(posts[i].target.az)) + ")";
        if (steps_after & (1u << i)) {
            text += " step";
        }
        text += i + 1 < posts.size() ? ", " : "";
    }
    return text;
}

}  // namespace

TEST_CASE("service worker: every interleaving of P, S and worker steps ends as the last command says") {
    const Post p1{false, {100, 30}}, p2{false, {250, 50}}, s{true, {}};
    const std::vector<std::vector<Post>> schedules = {
        {p1, s}, {s, p1}, {p1, s, p2}, {s, p1, s}, {p1, p2, s}, {p1, s, p1}, {p2, s, p1, s}, {s, s, p2},
    };
    for (const auto& posts : schedules) {
        // Bit i set: the worker runs one step right after post i (else the next post lands first).
        for (unsigned steps_after = 0; steps_after < (1u << posts.size()); ++steps_after) {
            HandDrivenService service;
            std::size_t moves_at_last_stop = 0;
            for (std::size_t i = 0; i < posts.size(); ++i) {
                if (posts[i].stop) {
                    moves_at_last_stop = service.moves_sent();
                    service.mailbox.post_stop();
                } else {
                    REQUIRE(service.mailbox.post_target(posts[i].target, service.now));
                }
                if (steps_after & (1u << i)) {
                    service.step();
                }
            }
            service.drain();
            INFO(describe(posts, steps_after));
            const Post& last = posts.back();
            if (last.stop) {
                // Nothing is sent after the stop is posted: the leg in flight (if any) was
                // already sent; every leg queued or posted before the stop is dropped.
                CHECK(service.moves_sent() == moves_at_last_stop);
            } else {
                CHECK(service.dish.az == Approx(last.target.az));
                CHECK(service.dish.el == Approx(last.target.el));
            }
        }
    }
}

TEST_CASE("service worker: a target is busy from the moment it is posted until the dish settles") {
    HandDrivenService service;
    REQUIRE(service.mailbox.view().idle);
    REQUIRE(service.mailbox.post_target({120, 40}, service.now));
    CHECK_FALSE(service.mailbox.view().idle);
    // Taken by the worker but not yet published: still busy, never a false idle in between.
    (void)service.mailbox.take();
    CHECK_FALSE(service.mailbox.view().idle);
}

TEST_CASE("service worker: a home requested mid-move is started by the next step, p keeps a position") {
    HandDrivenService service;
    REQUIRE(service.mailbox.post_target({100, 30}, service.now));
    service.step();
    REQUIRE_FALSE(service.mailbox.view().idle);
    REQUIRE(service.mailbox.post_home());
    CHECK(service.mailbox.view().homing);
    service.step();
    const auto& sent = service.wire->commands();
    CHECK(std::find_if(sent.begin(), sent.end(), [](const std::string& c) { return c.rfind("h ", 0) == 0; }) !=
          sent.end());
    // While the firmware homes, the snapshot keeps a position for `p` (never an empty answer).
    CHECK(service.mailbox.view().dish.position.has_value());
    service.drain();
    CHECK_FALSE(service.mailbox.view().homing);
}

TEST_CASE("service worker: R then P, in any timing, homes first and then goes to the target, P then R homes") {
    const AzEl target{150, 40};
    auto position_of = [](const std::vector<std::string>& sent, const std::string& prefix) {
        const auto it =
            std::find_if(sent.rbegin(), sent.rend(), [&](const std::string& c) { return c.rfind(prefix, 0) == 0; });
        return it == sent.rend() ? -1 : static_cast<int>(sent.rend() - it) - 1;
    };
    // Bit 0: a worker step right after the first post; bit 1: after the second.
    for (unsigned steps_after = 0; steps_after < 4; ++steps_after) {
        for (const bool home_first : {true, false}) {
            INFO((home_first ? "R, P" : "P, R") << "; steps after: " << steps_after);
            HandDrivenService service;
            for (int post = 0; post < 2; ++post) {
                if ((post == 0) == home_first) {
                    REQUIRE(service.mailbox.post_home());
                } else {
                    REQUIRE(service.mailbox.post_target(target, service.now));
                }
                if (steps_after & (1u << post)) {
                    service.step();
                }
            }
            service.drain();
            const auto& sent = service.wire->commands();
            const int home_end = position_of(sent, "h 0");
            REQUIRE(home_end >= 0);
            const int last_az_move = position_of(sent, "a 0 ");
            if (home_first) {
                // Measured through rotctld: a P taken in the same step as the home was dropped by it.
                CHECK(last_az_move > home_end);
                CHECK(service.dish.az == Approx(target.az));
                CHECK(service.dish.el == Approx(target.el));
            } else {
                CHECK(last_az_move < home_end);  // nothing of the target before the home survives it
            }
        }
    }
}

TEST_CASE("service worker: a receiver job withdrawn before the worker takes it never runs") {
    HandDrivenService service;
    auto job = std::make_shared<ServiceJob>();
    bool ran = false;
    job->work = [&ran](Controller&) {
        ran = true;
        return Status::ok();
    };
    // The mailbox hands the worker only the job it still holds; a stale pointer is refused.
    CHECK_FALSE(service.mailbox.job_started(job));
    service.step();
    CHECK_FALSE(ran);
}

TEST_CASE("service worker: while the dish reboots the last reading stays and P is kept, then a fresh reading comes") {
    HandDrivenService service;
    service.drain();
    const std::optional<AzEl> before = service.mailbox.view().dish.position;
    REQUIRE(before);
    service.step_into_recovery();
    // Nothing new was read: the snapshot still holds the reading from before the reboot.
    CHECK(service.mailbox.view().dish.position->az == Approx(before->az));
    CHECK(service.mailbox.view().dish.position->el == Approx(before->el));
    CHECK_FALSE(service.mailbox.view().idle);
    // A target posted now is accepted and waits for the dish (above the G2's 65 deg: clamped).
    REQUIRE(service.mailbox.post_target({250, 80}, service.now));
    const std::size_t moves_before = service.moves_sent();
    service.step();
    const ServiceSnapshot recovered = service.mailbox.view().dish;
    REQUIRE_FALSE(recovered.recovering);
    CHECK(recovered.recoveries == 1);
    // The first position published after the recovery is where the reboot left the dish.
    REQUIRE(recovered.position);
    CHECK(recovered.position->az == Approx(0.0));
    CHECK(recovered.position->el == Approx(65.0));
    CHECK(service.moves_sent() == moves_before);  // the target is resumed by the steps that follow
    service.drain();
    CHECK(service.dish.az == Approx(250.0));
    CHECK(service.dish.el == Approx(65.0));
}

TEST_CASE("service worker: S while the dish reboots drops the target posted before it") {
    HandDrivenService service;
    service.drain();
    service.step_into_recovery();
    REQUIRE(service.mailbox.post_target({250, 40}, service.now));
    service.mailbox.post_stop();
    const std::size_t moves_before = service.moves_sent();
    service.drain();
    CHECK(service.mailbox.view().dish.recoveries == 1);
    CHECK(service.moves_sent() == moves_before);
    CHECK(service.dish.az == Approx(0.0));
    CHECK(service.dish.el == Approx(65.0));
}

// After rotctld restarts, the dish may still be at 13 V: the LNB supply the backend reports is the
// one its tuner lists (DVB `dis`), or unknown, never the boot default assumed. A reboot of the dish
// makes the boot default (18 V) true again.
TEST_CASE("service worker: the LNB supply is read from the dish at open or unknown and a reboot makes it 18 V") {
    SECTION("the tuner lists 13 V") {
        HandDrivenService service(std::string("ODU:13V"));
        CHECK(service.mailbox.view().lnb_supply == LnbSupply::odu_13v);
        CHECK(std::count(service.wire->commands().begin(), service.wire->commands().end(), "dis") == 1);
        service.step_into_recovery();
        service.recover();
        CHECK(service.mailbox.view().lnb_supply == LnbSupply::stb_18v);
    }
    SECTION("the tuner lists nothing we can read") {
        HandDrivenService service;
        CHECK_FALSE(service.mailbox.view().lnb_supply.has_value());
        service.step_into_recovery();
        service.recover();
        CHECK(service.mailbox.view().lnb_supply == LnbSupply::stb_18v);
    }
}

// What the backend learnt of the dish (its motors' step time, pace and start-up, from which the
// pointing mode is chosen) and of the client (the satellite's motion, the orbit, the lead) are
// facts a reboot of the dish or an unplugged adapter does not change: recovery keeps them, and the
// client's targets sent meanwhile keep teaching the estimate.
TEST_CASE("service worker: what was learnt about the dish and the client survives a reboot and an unplug") {
    HandDrivenService service;
    // Small steps (0.4-2 deg) time the motors.
    for (const double d : {1.0, 2.0, 3.0}) {
        REQUIRE(service.mailbox.post_target({180.0 + d, 45.0 + d}, service.now));
        service.drain();
    }
    REQUIRE(service.worker->learnt_step_seconds(Axis::azimuth));
    REQUIRE(service.worker->learnt_step_seconds(Axis::elevation));

    // A client tracking at 0.5 deg/s in azimuth, one target a second.
    AzEl sat{190.0, 50.0};
    auto track_for = [&](int seconds) {
        for (int s = 0; s < seconds; ++s) {
            sat.az += 0.5;
            REQUIRE(service.mailbox.post_target(sat, service.now));
            for (int i = 0; i < 5; ++i) {
                (void)service.worker->step();  // the dish's time moves with the client's second only
            }
            service.now += 1s;
        }
    };
    track_for(25);  // an established track (PredictorSettings::established_track_s)
    const auto before = service.worker->predictor().predict(service.now);
    REQUIRE(before);
    REQUIRE(before->moving);
    REQUIRE(before->az_rate == Approx(0.5).margin(0.05));
    // What the dish taught up to the fault (tracking's own steps keep refining it).
    const auto az_step = service.worker->learnt_step_seconds(Axis::azimuth);
    const auto el_step = service.worker->learnt_step_seconds(Axis::elevation);
    const auto mode = service.worker->pointing_mode();

    SECTION("a reboot") {
        service.step_into_recovery();
        track_for(3);  // the client goes on while the dish boots
        service.recover();
    }
    SECTION("an unplug") {
        service.wire->hang_up();
        for (int i = 0; i < 50 && !service.mailbox.view().dish.recovering; ++i) {
            service.step();
        }
        REQUIRE(service.mailbox.view().dish.recovering);
        track_for(3);
        service.recover();
    }
    INFO("step seconds before " << az_step.value_or(-1) << " / " << el_step.value_or(-1) << ", after "
                                << service.worker->learnt_step_seconds(Axis::azimuth).value_or(-1) << " / "
                                << service.worker->learnt_step_seconds(Axis::elevation).value_or(-1));
    // Still known, within what the legs since (the return to the target) refined.
    REQUIRE(service.worker->learnt_step_seconds(Axis::azimuth));
    REQUIRE(service.worker->learnt_step_seconds(Axis::elevation));
    CHECK(*service.worker->learnt_step_seconds(Axis::azimuth) == Approx(*az_step).epsilon(0.1));
    CHECK(*service.worker->learnt_step_seconds(Axis::elevation) == Approx(*el_step).epsilon(0.1));
    CHECK(service.worker->pointing_mode() == mode);
    // The estimate ran on through the outage: it knows where the satellite is now and how fast it goes.
    const auto after = service.worker->predictor().predict(service.now);
    REQUIRE(after);
    CHECK(after->moving);
    CHECK(after->az_rate == Approx(0.5).margin(0.05));
    CHECK(after->position.az == Approx(sat.az).margin(1.0));
}

// A Gpredict-like client leading by 2 deg compares the satellite with the position `p` last
// answered, and its timer may tick again before its I/O loop has read the dish's move: it then
// re-sends, just past 2 s after its target, a target computed against the old reading. The lead is
// the gap to what the client read back; measured against the dish's reading when the re-send
// arrives (the dish is at the previous target by then) it would be a lead of almost nothing.
TEST_CASE("service worker: the client's lead is learnt from the position p last answered, not the dish now") {
    HandDrivenService service;
    constexpr double lead = 2.0, rate = 0.5;  // deg, deg/s in azimuth
    const Clock::time_point start = service.now;
    auto elapsed = [&] { return std::chrono::duration<double>(service.now - start).count(); };
    auto satellite = [&] { return AzEl{190.0 + rate * elapsed(), 45.0}; };
    auto ahead = [&] { return AzEl{satellite().az + lead, 45.0}; };
    REQUIRE(service.mailbox.post_target(ahead(), service.now));
    service.drain();

    std::optional<double> resend_at;  // a re-send due before the client reads `p` again
    int targets = 1, resends = 0;
    while (elapsed() < 120.0) {
        if (resend_at && elapsed() >= *resend_at) {
            REQUIRE(service.mailbox.post_target(ahead(), service.now));
            resend_at.reset();
            ++targets;
            ++resends;
        } else if (!resend_at) {
            const auto reading = service.mailbox.view().dish.position;
            REQUIRE(reading);
            service.mailbox.note_reported(*reading, service.now);  // what RotatorService::position() answers
            if (satellite().az - reading->az > lead) {
                REQUIRE(service.mailbox.post_target(ahead(), service.now));
                resend_at = elapsed() + 2.2;
                ++targets;
            }
        }
        for (int i = 0; i < 3; ++i) {
            (void)service.worker->step();
        }
        service.now += 100ms;
    }
    const auto learnt = service.worker->predictor().lead_threshold_deg();
    INFO(targets << " targets (" << resends << " re-sends): " << service.worker->predictor().describe());
    REQUIRE(resends >= 5);
    REQUIRE(learnt);
    // Each gap to `p` is 2 leads (a re-send's a little more); to the dish now, a re-send's is 1.1 deg.
    CHECK(*learnt == Approx(lead).margin(0.6));
}

namespace {

// A 2003 Carryout console (docs/firmware.md 8): no position query at rest, `g az el` in `target`
// with a live line at the target. Its prompts are undocumented: one reading prints `TRK>` and
// `TARGET>` after every line, the other prints none and answers only `?` with its listing.
struct Fake2003 {
    bool prints_prompts = true;
    bool silent = false;  // nothing comes back (the RX pair cut)
    bool in_target = false;
    std::string live_line;  // the last `g`'s line at its target

    std::vector<std::string> respond(const std::string& c) {
        if (silent) {
            return {};
        }
        std::vector<std::string> out{c + "\r\n"};
        if (c == "target") {
            in_target = true;
        } else if (c == "q") {
            in_target = false;
        } else if (c == "?") {
            out.emplace_back(in_target ? "g - Go to <az> <el>\r\n" : "target - Send dish to AZ/EL\r\n");
        } else if (c.rfind("g ", 0) == 0 && in_target) {
            double az = 0, el = 0;
            REQUIRE(std::sscanf(c.c_str(), "g %lf %lf", &az, &el) == 2);
            live_line = "az = " + std::to_string(std::lround(az * 100)) +
                        "   el = " + std::to_string(std::lround(el * 100)) + "\r\n";
            if (!prints_prompts) {
                return out;  // the live line comes later (live_line)
            }
            out.push_back(live_line);
        }
        if (prints_prompts) {
            out.emplace_back(in_target ? "TARGET>" : "TRK>");
        }
        return out;
    }
};

struct HandDriven2003 : HandDriven<Fake2003> {
    explicit HandDriven2003(bool prints_prompts) {
        dish.prints_prompts = prints_prompts;
        auto transport = std::make_unique<FakeTransport>([this](const std::string& c) { return dish.respond(c); });
        wire = transport.get();
        worker = std::make_unique<ServiceWorker>(mailbox, std::move(transport), options_for(VariantId::carryout2003),
                                                 ServiceTiming{}, TransportFactory{});
        REQUIRE(worker->start());
        mailbox.open();
    }
};

}  // namespace

// Silence is what "not answering" means: a dish that has no position query at rest but answers its
// console is idle, and its last known position stays; one that prints nothing is not answering.
TEST_CASE(
    "service worker: a 2003 Carryout at rest answers a poke that moves nothing, and only silence is not answering") {
    const bool prints_prompts = GENERATE(true, false);
    INFO((prints_prompts ? "prompts after every line" : "no prompts, `?` answers"));
    HandDriven2003 service(prints_prompts);
    const std::size_t opened = service.wire->commands().size();

    service.run_for(10s);
    ServiceView view = service.mailbox.view();
    INFO(view.dish.last_error.message);
    CHECK(view.dish.last_error);  // the idle polls were answered
    CHECK_FALSE(view.dish.recovering);
    CHECK(view.idle);
    CHECK_FALSE(view.dish.position);  // none read nor commanded: p has none to give
    const std::vector<std::string> idle_polls(service.wire->commands().begin() + static_cast<long>(opened),
                                              service.wire->commands().end());
    CHECK(idle_polls.size() >= 9);
    const std::string poke = prints_prompts ? "" : "?";
    CHECK(std::count(idle_polls.begin(), idle_polls.end(), poke) >= 9);
    for (const std::string& sent : idle_polls) {
        CHECK((sent.empty() || sent == "?"));  // never a word that moves, nor one that leaves `target`
    }

    // After a move the live line's position is the one known, and stays while the dish answers.
    REQUIRE(service.mailbox.post_target({150, 40}, service.now));
    service.run_for(100ms);
    if (!prints_prompts) {
        service.wire->push_input(service.dish.live_line);
    }
    service.run_for(10s);
    view = service.mailbox.view();
    CHECK(view.dish.last_error);
    CHECK(view.idle);
    REQUIRE(view.dish.position);
    CHECK(view.dish.position->az == Approx(150.0));
    CHECK(view.dish.position->el == Approx(40.0));

    // Cut the line: the pokes draw nothing, which is an error, and two in a row start a recovery.
    service.dish.silent = true;
    service.run_for(1500ms);
    view = service.mailbox.view();
    CHECK((!view.dish.last_error || view.dish.recovering));
    service.run_for(3s);
    CHECK(service.mailbox.view().dish.recovering);
    REQUIRE(service.mailbox.view().dish.position);
    CHECK(service.mailbox.view().dish.position->az == Approx(150.0));
}
