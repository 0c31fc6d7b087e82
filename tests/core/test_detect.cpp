// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Auto-detection over scripted consoles: help listings in any layout, boot lines, prompts, the
// ranking, and the rule that `q` goes only to a positively recognised submenu.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <map>

#include "birdcage/console/detect.hpp"
#include "birdcage/console/session.hpp"
#include "birdcage/console/synchroniser.hpp"
#include "fake_transport.hpp"

using namespace birdcage;
using namespace birdcage::test;
using namespace std::chrono_literals;

namespace {

using Commands = std::vector<std::string>;

// A console with menus: each menu has a prompt and a `?` listing; `q` returns to the root; the
// root's `q` is counted (on a G2 it would kill the shell).
struct MenuConsole {
    std::string root = "TRK";
    std::map<std::string, std::string> listing;   // menu -> `?` reply text
    std::string menu = "TRK";
    std::string eol = "\r\n";
    bool echo = true;
    bool bare_prompts = false;   // every menu prints `>` (Trav'ler, docs/firmware.md 3.1 "likely")
    int q_at_root = 0;
    int help_requests = 0;

    Commands respond(const std::string& command) {
        std::string out = echo ? command + eol : std::string();
        if (command.empty()) {
            out += eol;
        } else if (command == "?") {
            ++help_requests;
            out += listing[menu];
        } else if (command == "q") {
            if (menu == root) {
                ++q_at_root;
            }
            menu = root;
        } else if (listing.count(command) > 0) {
            menu = command;
        }
        std::string prompt = bare_prompts ? std::string() : menu;
        for (char& c : prompt) {
            c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        }
        return {out + prompt + ">"};
    }
};

Result<Detection> detect(MenuConsole& console, LogSink log = {}) {
    FakeTransport wire([&](const std::string& c) { return console.respond(c); });
    return detect_variant(wire, log, 60s);
}

const std::string g2_root_enter =
    "Enter <a3981> - A3981 menu\r\nEnter <adc> - ADC menu\r\nEnter <dipswitch> - Dip switch menu\r\n"
    "Enter <dvb> - DVB menu\r\nEnter <eeprom> - EEPROM menu\r\nEnter <gpio> - GPIO menu\r\n"
    "Enter <latlon> - Lat/Lon menu\r\nEnter <mot> - Motor menu\r\nEnter <nvs> - NVS menu\r\n"
    "Enter <os> - OS menu\r\nEnter <peak> - Peak menu\r\nEnter <step> - Step menu\r\nhelp [<command>]\r\n";

}  // namespace

TEST_CASE("detect: help listings in any layout give the same commands") {
    const std::vector<std::vector<std::string>> layouts = {
        {"mot", "os", "nvs"},                                             // one per line
        {"mot os nvs"},                                                   // all on one line
        {"mot, os, nvs"},                                                 // other separator
        {"mot - Motor menu", "os - OS menu", "nvs - Non-volatile storage"},   // descriptions
        {"MOT  Motor menu", "OS   OS menu", "NVS  Storage"},              // columns, upper case
        {"Enter <mot> - Motor menu", "Enter <os> - OS", "Enter <nvs> - NVS"},   // the G2's layout
        {"mot: motor menu; os: os menu; nvs: storage"},                   // described, one line
        {"Enter <mot> - Motor menu Enter <os> - OS Enter <nvs> - NVS"},   // G2 layout on one line
    };
    for (const auto& lines : layouts) {
        INFO(lines.front());
        const HelpListing listing = parse_help_listing(lines);
        CHECK(listing.commands.count("mot") == 1);
        CHECK(listing.commands.count("os") == 1);
        CHECK(listing.commands.count("nvs") == 1);
        CHECK(listing.commands.count("menu") == 0);
    }
    // A word only in a description is not in a command's place.
    const HelpListing described = parse_help_listing({"g <az> <el> - go to target"});
    CHECK(described.commands.count("target") == 0);
    CHECK(described.words.count("target") == 1);
}

TEST_CASE("detect: every variant's root listing wins clearly, in any layout") {
    struct Case {
        VariantId expected;
        std::vector<std::string> listing;
    };
    const std::vector<Case> cases = {
        {VariantId::carryout_g2, {"A3981 ADC DIPSWITCH DVB EEPROM GPIO LATLON MOT NVS OS PEAK STEP"}},
        {VariantId::travler_pro, {"odu - Connect to ODU"}},
        {VariantId::carryout2003, {"target  Send dish to AZ/EL", "motor  Motor", "dvb  DVB", "os  OS", "nvs  NVS"}},
        {VariantId::travler_hal205, {"motor, ngsearch, nvs, os"}},
        {VariantId::travler_hal000, {"mot - motor", "os - os", "nvs - storage", "stow - stow the dish"}},
    };
    for (const auto& c : cases) {
        INFO(c.listing.front());
        ConsoleEvidence evidence;
        evidence.help = parse_help_listing(c.listing);
        const auto winner = clear_winner(rank_evidence(evidence));
        REQUIRE(winner);
        CHECK(winner->variant == c.expected);
    }
}

TEST_CASE("detect: boot and version lines alone identify the firmware") {
    ConsoleEvidence g2;
    g2.lines = {"Bootloader v1.01", "Ant ID - 12-IN G2"};
    const auto g2_winner = clear_winner(rank_evidence(g2));
    REQUIRE(g2_winner);
    CHECK(g2_winner->variant == VariantId::carryout_g2);
    CHECK(g2_winner->reasons.front().find("Bootloader v1.01") != std::string::npos);

    ConsoleEvidence hal205;
    hal205.lines = {"Calibrating", "No LNB Voltage"};
    const auto hal205_winner = clear_winner(rank_evidence(hal205));
    REQUIRE(hal205_winner);
    CHECK(hal205_winner->variant == VariantId::travler_hal205);

    ConsoleEvidence nogps;   // printed by both Trav'ler HALs: not enough
    nogps.lines = {"NoGPS"};
    CHECK_FALSE(clear_winner(rank_evidence(nogps)));
}

TEST_CASE("detect: a G2 at TRK> with the Enter <cmd> listing, without any q") {
    MenuConsole g2;
    g2.listing["TRK"] = g2_root_enter;
    g2.echo = GENERATE(true, false);
    std::vector<std::string> log;
    const auto found = detect(g2, [&](LogLevel level, const std::string& m) {
        if (level == LogLevel::verbose) {
            log.push_back(m);
        }
    });
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::carryout_g2);
    CHECK(found.value.evidence.find("? lists a3981") != std::string::npos);
    CHECK(g2.q_at_root == 0);
    CHECK(g2.help_requests == 1);   // `?` once at the root, not five times
    // At verbose level: what won and why.
    CHECK(std::any_of(log.begin(), log.end(), [](const std::string& m) { return m.find("scores: g2 ") != std::string::npos; }));
}

TEST_CASE("detect: a G2 left in MOT> is left with q after MOT> was confirmed, then identified") {
    MenuConsole g2;
    g2.listing["TRK"] = g2_root_enter;
    g2.listing["mot"] = "Enter <a> - angle\r\nEnter <g> - go\r\nEnter <h> - home\r\n";
    g2.menu = "mot";
    FakeTransport wire([&](const std::string& c) { return g2.respond(c); });
    const auto found = detect_variant(wire, {}, 60s);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::carryout_g2);
    CHECK(g2.q_at_root == 0);
    const Commands& sent = wire.commands();
    const auto q = std::find(sent.begin(), sent.end(), "q");
    REQUIRE(q != sent.end());
    // Before the q: two bare line endings both ended on mot> and `?` ended on it too.
    CHECK(Commands(sent.begin(), q) == Commands{"", "", "?"});
}

TEST_CASE("detect: a root that lists nothing known is never sent q, and the failure says what to force") {
    MenuConsole odd;
    odd.root = "TRK";
    odd.listing["TRK"] = "frobnicate - something\r\nwibble - other\r\n";
    const auto found = detect(odd);
    REQUIRE_FALSE(found);
    CHECK(odd.q_at_root == 0);
    CHECK(found.status.message.find("-C variant=") != std::string::npos);
    CHECK(found.status.message.find("frobnicate") != std::string::npos);
}

TEST_CASE("detect: a prompt seen on one read only is never a reason for q") {
    // Line noise on a silent dish: every poke draws a different garbage `X>`.
    int poke = 0;
    FakeTransport wire([&](const std::string&) -> Commands {
        const char letters[] = "QWERTYUIOP";
        return {std::string("\r\n") + letters[poke++ % 10] + ">"};
    });
    const auto found = detect_variant(wire, {}, 20s);
    CHECK_FALSE(found);
    const Commands& sent = wire.commands();
    CHECK(std::find(sent.begin(), sent.end(), "q") == sent.end());
}

TEST_CASE("detect: a Trav'ler HAL 2.05 with bare > prompts, left in its motor menu") {
    MenuConsole hal205;
    hal205.root = "";
    hal205.menu = "motor";
    hal205.listing[""] = "motor - Motor menu\r\nngsearch - Search\r\nnvs - NVS\r\nos - OS\r\n";
    hal205.listing["motor"] = "a - position\r\ng - go\r\n";
    hal205.bare_prompts = true;
    FakeTransport wire([&](const std::string& c) { return hal205.respond(c); });
    const auto found = detect_variant(wire, {}, 60s);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::travler_hal205);
}

TEST_CASE("detect: a HAL 0.0.00 root keeps the Pro's elevation cap unless q reveals the IDU") {
    const bool q_reaches_idu = GENERATE(true, false);
    MenuConsole dish;
    dish.root = "ODU";
    dish.menu = "ODU";
    dish.listing["ODU"] = "mot - Motor\r\nos - OS\r\nnvs - NVS\r\n";
    FakeTransport wire;
    bool on_idu = false;
    wire.set_responder([&](const std::string& c) -> Commands {
        if (on_idu) {
            return {c + "\r\n" + (c == "?" ? "odu - Connect to ODU\r\n" : "") + "IDU>"};
        }
        if (c == "q" && q_reaches_idu) {
            on_idu = true;
            return {"q\r\nIDU>"};
        }
        return dish.respond(c);
    });
    const auto found = detect_variant(wire, {}, 60s);
    INFO(found.status.message);
    REQUIRE(found);
    if (q_reaches_idu) {
        CHECK(found.value.variant == VariantId::travler_pro);
    } else {
        CHECK(found.value.variant == VariantId::travler_hal000);
        CHECK(found.value.maybe_inside == birdcage::VariantId::travler_pro);
    }
}

TEST_CASE("detect: a HAL 0.0.00-looking root with any trace of the G2 gets no q") {
    MenuConsole dish;
    dish.listing["TRK"] = "mot - Motor\r\nos - OS\r\nnvs - NVS\r\nstep - Stepper\r\n";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    const auto found = detect_variant(wire, {}, 60s);
    const Commands& sent = wire.commands();
    CHECK(std::find(sent.begin(), sent.end(), "q") == sent.end());
    CHECK(dish.q_at_root == 0);
    (void)found;
}

TEST_CASE("detect: a booting G2 is identified from its boot lines and prompt") {
    MenuConsole g2;
    g2.listing["TRK"] = "a3981 adc dipswitch dvb eeprom gpio latlon mot nvs os peak step\r\n";
    bool booted = false;
    FakeTransport wire([&](const std::string& c) { return booted ? g2.respond(c) : Commands{}; });
    wire.push_delayed("Bootloader v1.01\r\nAnt ID - 12-IN G2\r\nBoot Complete\r\n", 3);
    wire.push_delayed("Loc Startup: IDU NOT Present\r\nTRK>", 2);
    const auto found = detect_variant(wire, [&](LogLevel, const std::string& m) {
        booted = booted || m.find("Loc Startup") != std::string::npos;
    }, 120s);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::carryout_g2);
    CHECK(found.value.evidence.find("boot line") != std::string::npos);
    CHECK(g2.q_at_root == 0);
}

TEST_CASE("detect: at TRK> a listing showing a Trav'ler root (mot, os, nvs, no G2-only command) gets one q") {
    // The one root where detection sends `q` (docs/firmware.md 2: the upstream Trav'ler clients' own
    // idiom), even at the G2's root shape: it tells a Pro left in its ODU console from a HAL 0.0.00.
    MenuConsole dish;
    dish.listing["TRK"] = "mot - Motor\r\nos - OS\r\nnvs - NVS\r\n";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    const auto found = detect_variant(wire, {}, 60s);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::travler_hal000);
    CHECK(found.value.maybe_inside == birdcage::VariantId::travler_pro);
    const Commands& sent = wire.commands();
    CHECK(std::count(sent.begin(), sent.end(), "q") == 1);
}

TEST_CASE("detect: at TRK> any G2-only command in the listing means no q, and the guard refuses it") {
    const std::string g2_only = GENERATE("a3981", "dipswitch", "latlon", "adc", "eeprom", "gpio", "peak", "step");
    MenuConsole dish;
    dish.listing["TRK"] = "mot - Motor\r\nos - OS\r\nnvs - NVS\r\nstow - Stow\r\n" + g2_only + " - menu\r\n";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    (void)detect_variant(wire, {}, 60s);
    const Commands& sent = wire.commands();
    CHECK(std::find(sent.begin(), sent.end(), "q") == sent.end());
    CHECK(dish.q_at_root == 0);

    // The session's hazard guard, with the auto-detect profile at a confirmed TRK>: `q` never
    // goes out, whatever the caller concluded.
    FakeTransport console([&](const std::string& c) { return dish.respond(c); });
    ConsoleSession session(console, probe_profile(), {});
    REQUIRE(session.synchronise(console_sync_settings(probe_profile(), 10s)));
    REQUIRE(session.menu() == "root");
    const auto q = session.transact("q", 1s);
    CHECK(q.status.code == Errc::hazard);
    CHECK(std::find(console.commands().begin(), console.commands().end(), "q") == console.commands().end());
}

TEST_CASE("detect: a G2-only command printed anywhere earlier means no q at TRK> (fuzz finding)") {
    // The latest listing looks like a Trav'ler root, but the console printed a G2 listing line
    // before: it may be a G2, where `q` at TRK> kills the shell.
    MenuConsole dish;
    dish.listing["TRK"] = "mot - Motor\r\nos - OS\r\nnvs - NVS\r\n";
    FakeTransport wire([&](const std::string& c) { return dish.respond(c); });
    wire.push_input("Enter <a3981> - A3981 menu\r\nTRK>");
    (void)detect_variant(wire, {}, 60s);
    const Commands& sent = wire.commands();
    CHECK(std::find(sent.begin(), sent.end(), "q") == sent.end());
}
