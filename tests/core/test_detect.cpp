// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Auto-detection over scripted consoles: help listings in any layout, boot lines, prompts, the
// ranking, and the rule that `q` goes only to a positively recognised submenu.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <map>
#include <random>

#include "console/detect.hpp"
#include "console/session.hpp"
#include "console/synchroniser.hpp"
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
    std::map<std::string, std::string> listing;  // menu -> `?` reply text
    std::string menu = "TRK";
    std::string eol = "\r\n";
    bool echo = true;
    bool bare_prompts = false;  // every menu prints `>` (Trav'ler, docs/firmware.md 3.1 "likely")
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
        {"mot", "os", "nvs"},                                                  // one per line
        {"mot os nvs"},                                                        // all on one line
        {"mot, os, nvs"},                                                      // other separator
        {"mot - Motor menu", "os - OS menu", "nvs - Non-volatile storage"},    // descriptions
        {"MOT  Motor menu", "OS   OS menu", "NVS  Storage"},                   // columns, upper case
        {"Enter <mot> - Motor menu", "Enter <os> - OS", "Enter <nvs> - NVS"},  // the G2's layout
        {"mot: motor menu; os: os menu; nvs: storage"},                        // described, one line
        {"Enter <mot> - Motor menu Enter <os> - OS Enter <nvs> - NVS"},        // G2 layout on one line
    };
    for (const auto& lines : layouts) {
        INFO(lines.front());
        const HelpListing listing = parse_help_listing(lines);
        CHECK(listing.commands.count("mot") == 1);
        CHECK(listing.commands.count("os") == 1);
        CHECK(listing.commands.count("nvs") == 1);
        CHECK(listing.commands.count("menu") == 0);
    }
    // A decorated prompt that reached the listing (`ODU TRK>`, a prompt the synchroniser did not
    // take for one) names no command.
    CHECK(parse_help_listing({"* MOT: motor", "* OS: os", "ODU TRK>"}).commands.count("odu") == 0);
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

    ConsoleEvidence nogps;  // printed by both Trav'ler HALs: not enough
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
    CHECK(g2.help_requests == 1);  // `?` once at the root, not five times
    // At verbose level: what won and why.
    CHECK(std::any_of(log.begin(), log.end(),
                      [](const std::string& m) { return m.find("scores: g2 ") != std::string::npos; }));
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
    const auto found = detect_variant(
        wire, [&](LogLevel, const std::string& m) { booted = booted || m.find("Loc Startup") != std::string::npos; },
        120s);
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

// ---- Consoles nobody wrote down: listings in any layout, and probing where evidence ties ----

namespace {

// A console for one variant's menus (the commands of docs/firmware.md 3.3, 4.3, 5.3, 6.3, 8.3),
// whose `?` listings are drawn from a seed: layout, case, numbering, brackets, separators, titles,
// labels, descriptions or none, columns, wrapped lines. The motor menu answers `a` in the
// variant's documented format; hazards (stow, reboot, a G2 root `q`) are counted.
struct DialectConsole {
    struct Menu {
        std::string prompt;
        std::vector<std::pair<std::string, std::string>> commands;  // word, description
        std::map<std::string, std::string> submenus;                // command -> menu
        std::string position;                                       // `a` answers this, if any
    };
    std::map<std::string, Menu> menus;
    std::string root = "root";
    std::string menu = "root";
    std::string eol = "\r\n";
    bool echo = true;
    bool bare_prompts = false;
    bool q_at_root_kills = false;
    std::string unknown_reply = "Unknown command";
    int hazards = 0;
    bool dead = false;
    std::string listing_style_note;
    std::uint32_t seed = 0;
    std::mt19937 rng;

    std::uint32_t pick(std::uint32_t n) { return static_cast<std::uint32_t>(rng() % n); }

    std::string listing(const Menu& m) {
        std::mt19937 style(seed);  // every menu of one console in the same style
        auto draw = [&](std::uint32_t n) { return static_cast<std::uint32_t>(style() % n); };
        const bool upper = draw(3) == 0;
        const bool described = draw(3) != 0;
        const bool upper_descriptions = upper && draw(2) == 0;
        const std::uint32_t layout = draw(5);     // per line, labelled line, columns, Enter <cmd>, one described line
        const std::uint32_t numbering = draw(4);  // none, 1. , 1) , [1]
        const std::uint32_t bracket = draw(4);    // none, <>, [], ()
        const std::vector<std::string> separators = {" - ", ": ", " = ", "\t", "     ", " -- "};
        const std::string desc_sep = separators[draw(static_cast<std::uint32_t>(separators.size()))];
        const std::vector<std::string> titles = {"", "Main Menu", "== HELP ==", "Available commands:", "Commands"};
        const std::string title = titles[draw(static_cast<std::uint32_t>(titles.size()))];
        const bool wrap = draw(2) == 0;
        const std::vector<std::string> joins = {" ", ", ", " | ", "  ", "; "};
        const std::string join = joins[draw(static_cast<std::uint32_t>(joins.size()))];
        const std::vector<std::string> labels = {"Commands: ", "Valid commands are: ", "Menu - ", "HELP: "};
        const std::string label = labels[draw(static_cast<std::uint32_t>(labels.size()))];
        const std::uint32_t columns = 2 + draw(3);

        auto word_of = [&](std::string w) {
            if (upper) {
                for (char& c : w)
                    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
            }
            switch (bracket) {
                case 1:
                    return "<" + w + ">";
                case 2:
                    return "[" + w + "]";
                case 3:
                    return "(" + w + ")";
                default:
                    return w;
            }
        };
        auto text_of = [&](std::string d) {
            if (upper_descriptions) {
                for (char& c : d)
                    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
            }
            return d;
        };
        auto number = [&](std::size_t i) {
            const std::string n = std::to_string(i + 1);
            switch (numbering) {
                case 1:
                    return n + ". ";
                case 2:
                    return n + ") ";
                case 3:
                    return "[" + n + "] ";
                default:
                    return std::string();
            }
        };
        std::vector<std::string> lines;
        if (!title.empty()) {
            lines.push_back(title);
        }
        auto entries = m.commands;
        entries.push_back({"q", "Quit this menu"});
        entries.push_back({"?", "This help"});
        switch (layout) {
            case 0:  // one per line, maybe wrapped descriptions
            case 3:
                for (std::size_t i = 0; i < entries.size(); ++i) {
                    std::string head = layout == 3 ? "Enter <" + word_of(entries[i].first) + ">"
                                                   : number(i) + word_of(entries[i].first);
                    if (!described) {
                        lines.push_back(head);
                        continue;
                    }
                    std::string text = text_of(entries[i].second);
                    if (wrap && text.size() > 12) {
                        const auto cut = text.find(' ', 10);
                        if (cut != std::string::npos) {
                            lines.push_back(head + (layout == 3 ? " - " : desc_sep) + text.substr(0, cut));
                            lines.push_back("        " + text.substr(cut + 1));
                            continue;
                        }
                    }
                    lines.push_back(head + (layout == 3 ? " - " : desc_sep) + text);
                }
                break;
            case 1: {  // a label, then the command words, maybe wrapped
                std::string line = label;
                for (std::size_t i = 0; i < entries.size(); ++i) {
                    const std::string piece = word_of(entries[i].first);
                    if (wrap && line.size() > 24) {
                        lines.push_back(line);
                        line = std::string(label.size(), ' ');
                    } else if (i > 0) {
                        line += join;
                    }
                    line += piece;
                }
                lines.push_back(line);
                break;
            }
            case 2: {  // columns
                std::string line;
                for (std::size_t i = 0; i < entries.size(); ++i) {
                    std::string cell = word_of(entries[i].first);
                    if (described) {
                        cell += " " + text_of(entries[i].second);
                    }
                    cell.resize(std::max<std::size_t>(cell.size() + 2, 28), ' ');
                    line += cell;
                    if ((i + 1) % columns == 0 || i + 1 == entries.size()) {
                        while (!line.empty() && line.back() == ' ')
                            line.pop_back();
                        lines.push_back(line);
                        line.clear();
                    }
                }
                break;
            }
            default: {  // all on one line, each with its description
                std::string line;
                for (std::size_t i = 0; i < entries.size(); ++i) {
                    line += (i > 0 ? "; " : "") + word_of(entries[i].first) +
                            (described ? ": " + text_of(entries[i].second) : "");
                }
                lines.push_back(line);
                break;
            }
        }
        listing_style_note = lines.empty() ? "" : lines.front() + (lines.size() > 1 ? " / " + lines[1] : "");
        std::string out;
        for (const auto& l : lines) {
            out += l + eol;
        }
        return out;
    }

    std::string prompt_text() const { return bare_prompts ? ">" : menus.at(menu).prompt + ">"; }

    Commands respond(const std::string& command) {
        if (dead) {
            return {};
        }
        std::string out = echo ? command + eol : std::string();
        Menu& m = menus.at(menu);
        if (command.empty()) {
            out += eol;
        } else if (command == "?" || command == "help") {
            out += listing(m);
        } else if (command == "q") {
            if (menu == root) {
                if (q_at_root_kills) {
                    ++hazards;
                    dead = true;
                    return {out + "Terminating shell" + eol};
                }
            } else {
                menu = menu == "odu_root" ? "odu_root" : root;  // the Pro's ODU root stays (sim default)
            }
        } else if (command == "stow" || command == "reboot") {
            ++hazards;
        } else if (m.submenus.count(command) > 0) {
            menu = m.submenus.at(command);
        } else if (command == "a" && !m.position.empty()) {
            out += m.position;
        } else if (!unknown_reply.empty()) {
            out += unknown_reply + eol;
        }
        return {out + prompt_text()};
    }
};

using Entries = std::vector<std::pair<std::string, std::string>>;
const std::string travler_position = "AZ = 100.00 EL = 30.00 SK = 0.00\r\n";

DialectConsole dialect_console(VariantId variant, std::uint32_t seed) {
    DialectConsole c;
    c.seed = seed;
    c.rng.seed(seed * 7919u + 1u);
    c.echo = c.pick(2) == 0;
    const std::vector<std::string> eols = {"\r\n", "\n", "\r"};
    c.eol = eols[c.pick(3)];
    c.bare_prompts = variant != VariantId::carryout_g2 && c.pick(2) == 0;
    c.unknown_reply = c.pick(2) == 0 ? std::string() : std::string("Unknown command");
    // Descriptions as the emulator and the G2's help word them, some naming other variants' words.
    const DialectConsole::Menu travler_motor{
        "MOT", {{"a", "Angle: show, or move motor to a target"}, {"g", "Go to az el sk"}}, {}, travler_position};
    switch (variant) {
        case VariantId::travler_hal000:
            c.menus["root"] = {"TRK",
                               {{"mot", "Motor menu"},
                                {"nvs", "Non-volatile storage"},
                                {"os", "OS"},
                                {"stow", "Stow the dish"},
                                {"reboot", "Reboot"}},
                               {{"mot", "mot"}},
                               ""};
            c.menus["mot"] = travler_motor;
            break;
        case VariantId::travler_hal205:
            c.menus["root"] = {"TRK",
                               {{"motor", "Motor"},
                                {"ngsearch", "Search"},
                                {"nvs", "Non-volatile storage"},
                                {"os", "OS"},
                                {"stow", "Stow"},
                                {"reboot", "Reboot"}},
                               {{"motor", "motor"}},
                               ""};
            c.menus["motor"] = travler_motor;
            c.menus["motor"].prompt = "MOTOR";
            break;
        case VariantId::travler_pro:
            c.menus["root"] = {"IDU", {{"odu", "Connect to ODU"}}, {{"odu", "odu_root"}}, ""};
            c.menus["odu_root"] = {"TRK", {{"mot", "Motor"}, {"nvs", "NVS"}, {"os", "OS"}}, {{"mot", "mot"}}, ""};
            c.menus["mot"] = travler_motor;
            break;
        case VariantId::carryout2003:
            c.menus["root"] = {
                "TRK",
                {{"target", "Send dish to AZ/EL"}, {"motor", "Motor"}, {"dvb", "DVB"}, {"os", "OS"}, {"nvs", "NVS"}},
                {{"target", "target"}, {"motor", "motor"}},
                ""};
            c.menus["target"] = {"TARGET", {{"g", "Go to az el"}}, {}, ""};
            c.menus["motor"] = {"MOTOR", {}, {}, ""};
            break;
        case VariantId::carryout_g2:
            c.menus["root"] = {"TRK",
                               {{"a3981", "A3981 stepper drivers"},
                                {"adc", "ADC"},
                                {"dipswitch", "DIP switches"},
                                {"dvb", "DVB tuner"},
                                {"eeprom", "EEPROM"},
                                {"gpio", "GPIO"},
                                {"latlon", "Lat/Lon"},
                                {"mot", "Motors"},
                                {"nvs", "Non-volatile storage"},
                                {"os", "OS"},
                                {"peak", "Peaking"},
                                {"step", "Raw stepper"},
                                {"reboot", "Reboot"},
                                {"stow", "Stow"}},
                               {{"mot", "mot"}},
                               ""};
            c.menus["mot"] = {
                "MOT", {{"a", "Angle"}, {"g", "Go"}, {"h", "Home"}}, {}, "Angle[0] = 100.00\r\nAngle[1] = 30.00\r\n"};
            c.q_at_root_kills = true;
            break;
    }
    return c;
}

}  // namespace

TEST_CASE("detect: a HAL 0.0.00 whose ? is one line, a label then the command words") {
    // The reported console: `>` prompts and `Commands: ...` on one line. Before: "not sure which
    // firmware this is (prompt ">", ? lists commands; scores: no evidence for any variant)".
    const std::string label =
        GENERATE(std::string("Commands: "), std::string("Available commands - "), std::string("HELP: "));
    MenuConsole dish;
    dish.root = "";
    dish.menu = "";
    dish.bare_prompts = true;
    dish.listing[""] = label + "mot nvs os stow reboot ? q\r\n";
    dish.listing["mot"] = "Commands: a g q\r\n";
    const auto listing = parse_help_listing({label + "mot nvs os stow reboot ? q"});
    CHECK(listing.commands.count("mot") == 1);
    CHECK(listing.commands.count("os") == 1);
    CHECK(listing.commands.count("commands") == 0);
    const auto found = detect(dish);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == VariantId::travler_hal000);
}

TEST_CASE("detect: where the evidence ties, probes decide, log each answer and never send a hazard") {
    // The reported tie: a booting Trav'ler's `NoGPS` scores hal000 1, hal205 1, and the listing
    // says nothing known. Each variant is told apart by entering a motor menu and reading `a`.
    struct Case {
        VariantId variant;
        const char* motor_menu;
        std::string position;
        bool q_kills;
    };
    const Case c = GENERATE(Case{VariantId::travler_hal000, "mot", travler_position, false},
                            Case{VariantId::travler_hal205, "motor", travler_position, false},
                            Case{VariantId::carryout_g2, "mot", "Angle[0] = 100.00\r\nAngle[1] = 30.00\r\n", true});
    DialectConsole dish;
    dish.menus["root"] = {c.q_kills ? "TRK" : "", {}, {{c.motor_menu, "m"}}, ""};
    dish.menus["m"] = {c.q_kills ? "MOT" : "", {}, {}, c.position};
    dish.bare_prompts = !c.q_kills;
    dish.q_at_root_kills = c.q_kills;
    FakeTransport wire([&](const std::string& command) {
        // The listing names nothing: a console whose `?` prints only a title.
        return command == "?" ? Commands{"?\r\nMenu\r\n" + dish.prompt_text()} : dish.respond(command);
    });
    if (!c.q_kills) {
        wire.push_input("NoGPS\r\n");
    }
    std::vector<std::string> log;
    const auto found = detect_variant(
        wire, [&](LogLevel, const std::string& m) { log.push_back(m); }, 60s);
    INFO(found.status.message);
    REQUIRE(found);
    CHECK(found.value.variant == c.variant);
    CHECK(found.value.evidence.find("by probing") != std::string::npos);
    CHECK(dish.hazards == 0);
    CHECK(std::count_if(log.begin(), log.end(),
                        [](const std::string& m) { return m.find("auto-detect probe: \"") == 0; }) >= 1);
    // At the G2 root shape `q` goes only to the motor menu a probe entered (at a Trav'ler `>` root
    // the submenu rule may send its harmless `q` first).
    const Commands& sent = wire.commands();
    for (std::size_t i = 0; i < sent.size() && c.q_kills; ++i) {
        if (sent[i] == "q") {
            REQUIRE(i >= 1);
            CHECK(std::find(sent.begin(), sent.begin() + static_cast<std::ptrdiff_t>(i), std::string(c.motor_menu)) !=
                  sent.begin() + static_cast<std::ptrdiff_t>(i));
        }
    }
}

TEST_CASE("detect: generated listing layouts, every variant, identified without a hazard") {
    // A seeded generator rather than a hand-made list: the layouts nobody thought of are the point.
    const std::vector<VariantId> variants = {VariantId::travler_hal000, VariantId::travler_hal205,
                                             VariantId::travler_pro, VariantId::carryout2003, VariantId::carryout_g2};
    int probed = 0;
    for (VariantId variant : variants) {
        for (std::uint32_t seed = 1; seed <= 40; ++seed) {
            DialectConsole dish = dialect_console(variant, seed + 1000u * static_cast<std::uint32_t>(variant));
            const bool booting_trace =
                variant != VariantId::carryout_g2 && variant != VariantId::carryout2003 && seed % 3 == 0;
            FakeTransport wire([&](const std::string& command) { return dish.respond(command); });
            if (booting_trace) {
                wire.push_input("NoGPS" + dish.eol);  // the tie of both Trav'ler HALs
            }
            const auto found = detect_variant(wire, {}, 60s);
            (void)dish.listing(dish.menus.at(dish.root));
            INFO(profile(variant).short_name << " seed " << seed << ": " << dish.listing_style_note << " -> "
                                             << found.status.message << found.value.evidence);
            CHECK(found);
            CHECK((found && found.value.variant == variant));
            CHECK(dish.hazards == 0);
            probed += found.value.evidence.find("by probing") != std::string::npos;
        }
    }
    // Most layouts are read without a probe; a few are not (upper-case descriptions in columns).
    INFO(probed << " of 200 needed a probe");
    CHECK(probed < 40);
}
