// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The console synchroniser over scripted consoles: every state a console can be in when the
// backend opens it (booting with late lines, idle, echo or none, CR/LF/CRLF, prompt + space,
// garbage, NULs, a wrong baud rate), and the failure messages.
#include <catch2/catch.hpp>

#include "console/synchroniser.hpp"
#include "dish/controller.hpp"
#include "fake_transport.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;

namespace {

using Commands = std::vector<std::string>;

struct Logged {
    std::vector<std::pair<LogLevel, std::string>> lines;
    LogSink sink() {
        return [this](LogLevel level, const std::string& m) { lines.emplace_back(level, m); };
    }
    bool has(LogLevel level, std::string_view text) const {
        return std::any_of(lines.begin(), lines.end(),
                           [&](const auto& l) { return l.first == level && l.second.find(text) != std::string::npos; });
    }
    std::size_t count(std::string_view text) const {
        return static_cast<std::size_t>(std::count_if(
            lines.begin(), lines.end(), [&](const auto& l) { return l.second.find(text) != std::string::npos; }));
    }
};

// A clock that never moves by itself: only the synchroniser's timed-out reads advance its time.
Clock::time_point frozen_time() {
    return Clock::time_point{} + 1000h;
}
const DishClock frozen = DishClock::manual(frozen_time);

SyncSettings g2_settings(std::chrono::milliseconds budget = 60s) {
    return console_sync_settings(profile(VariantId::carryout_g2), budget);
}

// A console answering a bare line ending with `prompt`, in a given line-ending and echo style.
FakeTransport::Responder prompt_console(std::string prompt, std::string eol, bool echo) {
    return [=](const std::string& command) -> Commands {
        std::string out = echo ? command + eol : std::string();
        if (command.empty()) {
            out += eol;
        }
        return {out + prompt};
    };
}

}  // namespace

TEST_CASE("sync: the prompt is taken from the end of the output, never from a stale line") {
    CHECK(trailing_prompt("\r\nTRK>") == "TRK>");
    CHECK(trailing_prompt("\r\nMOT> ") == "MOT>");
    CHECK(trailing_prompt("TRK>\r\n") == "TRK>");  // a prompt on a line of its own
    CHECK(trailing_prompt("\nTRK>\r\nLoc Startup: IDU NOT Present\r\n").empty());
    CHECK(trailing_prompt("Enter <a3981> - A3981 menu\r\n").empty());
    CHECK(trailing_prompt("\r\nT\x00RK>").empty());  // garbage inside: not a prompt
    CHECK(trailing_prompt("").empty());
}

TEST_CASE("sync: a booted console is confirmed on two consecutive pokes, in any line style") {
    const std::string eol = GENERATE(std::string("\r\n"), std::string("\n"), std::string("\r"));
    const bool echo = GENERATE(true, false);
    const std::string prompt = GENERATE(std::string("TRK>"), std::string("TRK> "), std::string(">"));
    FakeTransport wire(prompt_console(prompt, eol, echo));
    Logged log;
    ConsoleSynchroniser sync(wire, g2_settings(), log.sink(), frozen);
    const auto synced = sync.synchronise();
    INFO(synced.status.message);
    REQUIRE(synced);
    CHECK(synced.value.prompt == (prompt == "TRK> " ? "TRK>" : prompt));
    CHECK(wire.commands() == Commands{"", ""});
    CHECK_FALSE(log.has(LogLevel::warning, "waiting"));
}

TEST_CASE("sync: stale input is drained and never taken for a prompt") {
    FakeTransport wire;
    wire.push_input("Boot Complete\r\nTRK>");  // left in the buffer from before we opened
    int pokes = 0;
    wire.set_responder([&](const std::string&) -> Commands {
        return {++pokes == 1 ? "\r\nLoc Startup: IDU NOT Present\r\n" : "\r\nTRK>"};
    });
    ConsoleSynchroniser sync(wire, g2_settings(), {}, frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(synced.value.prompt == "TRK>");
    CHECK(pokes == 3);  // the first reply ended on a boot line: two more to confirm
    CHECK(synced.value.last_boot_line == "Loc Startup: IDU NOT Present");
}

TEST_CASE("controller G2: rotctld started during boot survives the late Loc Startup line") {
    // The reported failure: after `Boot Complete` the backend sent CR, the late boot line arrived,
    // it sent `mot`, read a stale `TRK>` and gave up ("expected the motor prompt MOT>, console
    // shows TRK>"). The console here prints the late line after the first CR's prompt.
    FakeG2 dish;
    bool booted = false;
    bool late_line_pending = true;
    FakeTransport wire;
    wire.set_responder([&](const std::string& command) -> Commands {
        if (!booted) {
            return {};
        }
        auto reply = dish.respond(command);
        if (late_line_pending) {
            late_line_pending = false;
            reply.push_back("\r\nLoc Startup: IDU NOT Present\r\n");
        }
        return reply;
    });
    wire.push_delayed("Bootloader v1.01\r\nMotor init: System=12Inch, master=40000 steps\r\n", 2);
    wire.push_delayed("Ant ID - 12-IN G2\r\nAntenna Facing Front\r\nBoot Complete\r\n", 3);
    Logged log;
    ControllerOptions options{};
    options.variant = VariantId::carryout_g2;
    options.leapfrog = false;
    options.boot_timeout = 900s;
    options.log = [&](LogLevel level, const std::string& m) {
        log.lines.emplace_back(level, m);
        if (m.find("Boot Complete") != std::string::npos) {
            booted = true;
        }
    };
    Controller controller(wire, options);
    const Status status = controller.initialize();
    INFO(status.message);
    REQUIRE(status);
    CHECK(controller.initialised());
    CHECK_FALSE(dish.shell_killed);
    CHECK(dish.menu == "MOT");
    // Never `q` at the root, and `mot` only after the prompt was confirmed.
    const auto& sent = wire.commands();
    CHECK(std::find(sent.begin(), sent.end(), "q") == sent.end());
    CHECK(log.has(LogLevel::warning,
                  "the dish is booting (\"Motor init: System=12Inch, master=40000 steps\"); waiting for it to finish"));
}

TEST_CASE("sync: while boot output is in progress the console is only listened to") {
    FakeTransport wire;
    int pokes_while_booting = 0;
    bool booted = false;
    wire.set_responder([&](const std::string&) -> Commands {
        if (!booted) {
            ++pokes_while_booting;
            return {};
        }
        return {"\r\nTRK>"};
    });
    wire.push_input("Bootloader v1.01\r\n");
    wire.push_delayed("Motor init: System=12Inch\r\n", 0);
    wire.push_delayed("Boot Complete\r\n", 0);
    Logged log;
    ConsoleSynchroniser sync(
        wire, g2_settings(),
        [&](LogLevel l, const std::string& m) {
            log.lines.emplace_back(l, m);
            booted = booted || m.find("Boot Complete") != std::string::npos;
        },
        frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(pokes_while_booting == 0);
    CHECK(synced.value.boot_heard);
}

TEST_CASE("sync: a dish that prints its boot log for minutes is announced and reported every 30 s") {
    FakeTransport wire;
    bool booted = false;  // a booting dish ignores its input
    wire.set_responder([&](const std::string&) -> Commands { return booted ? Commands{"\r\nTRK>"} : Commands{}; });
    wire.push_input("Bootloader v1.01\r\n");
    for (int i = 0; i < 12; ++i) {
        wire.push_delayed("Motor init: homing step " + std::to_string(i) + "\r\n", 2);
    }
    wire.push_delayed("Boot Complete\r\n", 2);
    Logged log;
    ConsoleSynchroniser sync(
        wire, g2_settings(900s),
        [&](LogLevel l, const std::string& m) {
            log.lines.emplace_back(l, m);
            booted = booted || m.find("Boot Complete") != std::string::npos;
        },
        frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(synced.value.prompt == "TRK>");
    CHECK(log.count("the dish is booting (\"Bootloader v1.01\"); waiting for it to finish (up to 900 s)") == 1);
    REQUIRE(synced.value.waited >= 30s);
    CHECK(log.count("still waiting for the dish to boot: 30 s; last boot output \"Motor init: homing step") == 1);
}

TEST_CASE("sync: a silent console is waited for with progress every 30 s, then the reason") {
    FakeTransport wire;  // never says anything
    Logged log;
    ConsoleSynchroniser sync(wire, g2_settings(100s), log.sink(), frozen);
    const auto synced = sync.synchronise();
    REQUIRE_FALSE(synced);
    CHECK(synced.status.code == Errc::timeout);
    CHECK(log.count("the console does not answer yet; waiting for the dish to finish booting (up to 100 s)") == 1);
    CHECK(log.count("still waiting for the dish to boot: 30 s") == 1);
    CHECK(log.count("still waiting for the dish to boot: 60 s") == 1);
    CHECK(log.count("still waiting for the dish to boot: 90 s") == 1);
    CHECK(log.count("still waiting") == 3);
    CHECK(synced.status.message.find("expected the console's prompt (TRK>") != std::string::npos);
    CHECK(synced.status.message.find("stayed silent") != std::string::npos);
    CHECK(synced.status.message.find("115200") != std::string::npos);
    // Bounded: every poke took at least a reply window of the 100 s budget.
    CHECK(wire.commands().size() <= 100);
}

TEST_CASE("sync: giving up quotes the last lines seen, escaped") {
    FakeTransport wire([](const std::string&) -> Commands { return {"\r\nUnknown thing\r\nweird\x01line\r\n"}; });
    ConsoleSynchroniser sync(wire, g2_settings(10s), {}, frozen);
    const auto synced = sync.synchronise();
    REQUIRE_FALSE(synced);
    INFO(synced.status.message);
    CHECK(synced.status.message.find("\"Unknown thing\", \"weird\\x01line\"") != std::string::npos);
    CHECK(synced.status.message.find("bytes unprintable") != std::string::npos);
}

TEST_CASE("sync: garbage and NULs around a prompt never confirm a garbage prompt") {
    // Line noise on an idle RS-485 bus: random bytes, some of which look like `X>`.
    int poke = 0;
    FakeTransport wire([&](const std::string&) -> Commands {
        ++poke;
        switch (poke % 3) {
            case 0:
                return {std::string("\x00\x00Q>", 4)};
            case 1:
                return {
                    "\xff\xfe"
                    "A>"};
            default:
                return {std::string("\r\n\x00TRK>", 7)};
        }
    });
    ConsoleSynchroniser sync(wire, g2_settings(20s), {}, frozen);
    const auto synced = sync.synchronise();
    // Each reply ends on a different candidate (or a noisy line): nothing is confirmed.
    CHECK_FALSE(synced);
}

TEST_CASE("sync: NULs before a clean prompt line are dropped") {
    FakeTransport wire([](const std::string&) -> Commands { return {std::string("\x00\r\nMOT>", 7)}; });
    ConsoleSynchroniser sync(wire, g2_settings(), {}, frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(synced.value.prompt == "MOT>");
}

TEST_CASE("sync: replies that look like a wrong baud rate get a warning naming the usual rate") {
    FakeTransport wire(
        [](const std::string&) -> Commands { return {std::string("\xf0\x8a\x00\xfe\x9c\x13\xe0\x80\xff\x11", 10)}; });
    Logged log;
    ConsoleSynchroniser sync(wire, g2_settings(10s), log.sink(), frozen);
    CHECK_FALSE(sync.synchronise());
    CHECK(log.count("look like a wrong baud rate") == 1);
    CHECK(log.has(LogLevel::warning, "usually runs at 115200 baud"));
    CHECK(looks_like_wrong_baud(std::string_view("\xf0\x8a\x00\xfe\x9c\x13\xe0\x80", 8)));
    CHECK_FALSE(looks_like_wrong_baud("Angle[0] = 180.00\r\nMOT>"));
}

TEST_CASE("sync: auto-detect names every variant's usual rate") {
    const auto settings = console_sync_settings(probe_profile(), 10s);
    CHECK(settings.usual_baud.find("57600 (hal000") != std::string::npos);
    CHECK(settings.usual_baud.find("115200 (g2)") != std::string::npos);
    CHECK(settings.probe_command == "?");
}

TEST_CASE("sync: a prompt-less console is live once ? is answered the same twice") {
    FakeTravler dish;
    dish.echo = GENERATE(true, false);
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    ConsoleSynchroniser sync(wire, console_sync_settings(profile(VariantId::travler_hal205), 60s), {}, frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(synced.value.prompt.empty());
    CHECK(synced.value.probe_reply.size() == 4);
    CHECK(wire.commands() == Commands{"", "?", "", "?"});
}

TEST_CASE("sync: boot chatter answering a prompt-less probe is not taken for a live console") {
    FakeTransport wire;
    int probes = 0;
    wire.set_responder([&](const std::string& c) -> Commands {
        if (c == "?") {
            ++probes;
            return {"Calibrating step " + std::to_string(probes) + "\r\n"};  // different each time
        }
        return {};
    });
    ConsoleSynchroniser sync(wire, console_sync_settings(profile(VariantId::travler_hal000), 20s), {}, frozen);
    CHECK_FALSE(sync.synchronise());
}

namespace {

// A line that is never quiet: between the console's replies it carries random bytes at a steady
// rate (a noisy idle RS-485 bus; the e2e fault test runs 200 B/s), one byte per read, with time
// advancing by one byte interval per noise byte. The console's own replies arrive at once.
class NoisyLine final : public Transport {
public:
    NoisyLine(FakeTransport& console, int bytes_per_second)
        : console_(console), byte_interval_(std::chrono::microseconds(1'000'000 / bytes_per_second)) {}

    Status write(std::string_view bytes, Deadline deadline) override { return console_.write(bytes, deadline); }
    Result<std::size_t> read(char* buf, std::size_t n, Deadline deadline) override {
        if (auto reply = console_.read(buf, n, now_)) {
            return reply;
        }
        if (now_ + byte_interval_ > deadline) {
            now_ = std::max(now_, deadline);
            return {0, Status{Errc::timeout, "noisy line: deadline"}};
        }
        now_ += byte_interval_;
        state_ = state_ * 1103515245u + 12345u;  // deterministic: the same bytes every run
        buf[0] = static_cast<char>(state_ >> 24);
        ++noise_bytes_;
        return {1, Status::ok()};
    }
    void discard_input() override { console_.discard_input(); }

    Clock::time_point now() const { return now_; }
    std::size_t noise_bytes() const { return noise_bytes_; }

private:
    FakeTransport& console_;
    Clock::duration byte_interval_;
    Clock::time_point now_ = frozen_time();
    std::uint32_t state_ = 1;
    std::size_t noise_bytes_ = 0;
};

}  // namespace

TEST_CASE("sync: a line that is never quiet still comes into sync (noise is not output)") {
    // The e2e failure: under steady idle noise the recovery re-sync waited for a quiet gap that
    // never came (every printable noise byte counted as the console speaking) and printable noise
    // after the prompt hid it, so a re-initialisation never finished.
    const int rate = GENERATE(200, 2000);
    const bool echo = GENERATE(true, false);
    FakeTransport console(prompt_console("MOT>", "\r\n", echo));
    NoisyLine line(console, rate);
    Logged log;
    // The recovery slice (RotatorTiming::recovery_boot_slice).
    ConsoleSynchroniser sync(line, g2_settings(5s), log.sink(), DishClock::manual([&] { return line.now(); }));
    const auto synced = sync.synchronise();
    INFO(synced.status.message);
    REQUIRE(synced);
    CHECK(synced.value.prompt == "MOT>");
    CHECK(console.commands() == Commands{"", ""});  // two pokes, nothing but line endings
    CHECK(line.noise_bytes() > 100);
    CHECK(std::none_of(synced.value.heard.begin(), synced.value.heard.end(),
                       [](const std::string& l) { return l != "MOT>"; }));  // noise is never a line heard
    CHECK(line.now() - frozen_time() < 3s);
}

TEST_CASE("sync: under steady noise a late boot line after a stale prompt still voids it") {
    FakeTransport console;
    int pokes = 0;
    console.set_responder([&](const std::string&) -> Commands {
        return {++pokes == 1 ? "\r\nTRK>\r\nLoc Startup: IDU NOT Present\r\n" : "\r\nTRK>"};
    });
    NoisyLine line(console, 200);
    ConsoleSynchroniser sync(line, g2_settings(5s), {}, DishClock::manual([&] { return line.now(); }));
    const auto synced = sync.synchronise();
    INFO(synced.status.message);
    REQUIRE(synced);
    CHECK(synced.value.prompt == "TRK>");
    CHECK(pokes == 3);
    CHECK(synced.value.last_boot_line == "Loc Startup: IDU NOT Present");
}

TEST_CASE("sync: noise after a prompt leaves it the prompt, text after it on its line does not") {
    SECTION("prompt, then noise read with it and after it, a noise line ending among it") {
        FakeTransport wire([](const std::string&) -> Commands { return {"\r\nMOT>k\x9aQ", "\x01\r7\xfe", "\xe0"}; });
        ConsoleSynchroniser sync(wire, g2_settings(), {}, frozen);
        const auto synced = sync.synchronise();
        INFO(synced.status.message);
        REQUIRE(synced);
        CHECK(synced.value.prompt == "MOT>");
        CHECK(wire.commands() == Commands{"", ""});
    }
    SECTION("two prompts run together (fuzz finding): the line is text, not a prompt") {
        FakeTransport wire([](const std::string&) -> Commands { return {"\r\nTRK>", "TRK>"}; });
        ConsoleSynchroniser sync(wire, g2_settings(10s), {}, frozen);
        CHECK_FALSE(sync.synchronise());
    }
}

TEST_CASE("sync: a dish is up once two pokes find a prompt, whatever its last boot line was") {
    // The reported G2: after `Loc Startup: IDU NOT Present` one more line nobody documented, then
    // `TRK>` and silence. When that line happened to contain a boot marker the backend kept
    // waiting ("still waiting for the dish to boot: 60 s; last boot output ...") at a ready console.
    const std::string extra =
        GENERATE(std::string("Antenna Facing Rear: re-homing skipped"), std::string("Motor init: wrap manager on"),
                 std::string("Ant ID - check passed"), std::string("Tracker disabled (NVS 20)"));
    const bool auto_detect = GENERATE(true, false);
    FakeTransport wire;
    bool booted = false;  // a booting dish ignores its input
    wire.set_responder([&](const std::string&) -> Commands { return booted ? Commands{"\r\nTRK>"} : Commands{}; });
    wire.push_input("Bootloader v1.01\r\nMotor init: System=12Inch, master=40000 steps\r\n");
    wire.push_delayed("Ant ID - 12-IN G2\r\nAntenna Facing Front\r\nBoot Complete\r\n", 2);
    wire.push_delayed("Loc Startup: IDU NOT Present\r\n", 1);
    wire.push_delayed(extra + "\r\nTRK>", 1);
    Logged log;
    const FirmwareProfile& row = auto_detect ? probe_profile() : profile(VariantId::carryout_g2);
    ConsoleSynchroniser sync(
        wire, console_sync_settings(row, 120s),
        [&](LogLevel l, const std::string& m) {
            log.lines.emplace_back(l, m);
            booted = booted || m.find("Loc Startup") != std::string::npos;
        },
        frozen);
    const auto synced = sync.synchronise();
    INFO(extra << (auto_detect ? " (auto-detect)" : " (G2 profile)") << ": " << synced.status.message);
    REQUIRE(synced);
    CHECK(synced.value.prompt == "TRK>");
    CHECK(synced.value.waited < 30s);
    CHECK(log.count("still waiting") == 0);
    // Nothing but bare line endings while boot output was in progress.
    for (const auto& c : wire.commands()) {
        CHECK((c.empty() || c == "?"));
    }
}

TEST_CASE("sync: silences of several seconds inside a boot are waited out, not taken for the end") {
    // Homing can take its 8 s stall timeout without a line; a quiet line alone is not proof.
    FakeTransport wire;
    bool booted = false;
    int pokes_while_booting = 0;
    wire.set_responder([&](const std::string&) -> Commands {
        if (!booted) {
            ++pokes_while_booting;
            return {};
        }
        return {"\r\nTRK>"};
    });
    wire.push_input("Bootloader v1.01\r\nMotor init: System=12Inch\r\n");
    wire.push_delayed("wrap_min:-42333 wrap_max:2333\r\n", 6);  // after a long silence
    wire.push_delayed("Boot Complete\r\n", 4);
    Logged log;
    ConsoleSynchroniser sync(
        wire, g2_settings(120s),
        [&](LogLevel l, const std::string& m) {
            log.lines.emplace_back(l, m);
            booted = booted || m.find("Boot Complete") != std::string::npos;
        },
        frozen);
    const auto synced = sync.synchronise();
    REQUIRE(synced);
    CHECK(synced.value.prompt == "TRK>");
    CHECK(synced.value.last_boot_line == "Boot Complete");
    CHECK(pokes_while_booting > 0);  // poked during the silences, unanswered, so still booting
    for (const auto& c : wire.commands()) {
        CHECK(c.empty());
    }
}

// A G2 console whose prompts carry a product tag (`WG TRK>`, `[G2]MOT>`) is the same firmware: its
// prompt is known by its shape, and the session learns the menu from the documented text.
TEST_CASE("sync: a prompt with a tag before it or marks after it is confirmed as its documented text") {
    const std::string prompt =
        GENERATE(std::string("WG TRK>"), std::string("[G2]MOT>"), std::string("TRK>$"), std::string("dish: TRK> "));
    FakeTransport wire(prompt_console(prompt, "\r\n", true));
    Logged log;
    ConsoleSynchroniser sync(wire, g2_settings(), log.sink(), frozen);
    const auto synced = sync.synchronise();
    INFO(prompt << ": " << synced.status.message);
    REQUIRE(synced);
    CHECK(synced.value.prompt == (prompt.find("MOT") != std::string::npos ? "MOT>" : "TRK>"));
    CHECK(wire.commands() == Commands{"", ""});
}

// The waiting messages say what the console showed: a console that answers every poke with a
// line that is no prompt never reads "no boot output yet" as if it were silent.
TEST_CASE("sync: while waiting the messages name the last line the console showed and the pokes it answered") {
    FakeTransport wire(prompt_console("tracker ready, type help", "\r\n", false));
    Logged log;
    ConsoleSynchroniser sync(wire, g2_settings(40s), log.sink(), frozen);
    const auto synced = sync.synchronise();
    REQUIRE_FALSE(synced);
    CHECK(log.count("the console shows no prompt confirmed yet (it last showed \"tracker ready, type help\")") == 1);
    CHECK(log.count("still waiting for the dish to boot: 30 s; no boot output; the console last showed "
                    "\"tracker ready, type help\"; ") == 1);
    CHECK(log.count("no boot output yet") == 0);
    CHECK(log.count(" pokes answered") == 1);
}
