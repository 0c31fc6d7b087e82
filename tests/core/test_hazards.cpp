// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The one hazard rule (hazards.hpp, docs/firmware.md §15): a caller gets exactly the well-formed
// commands it asked for, and no caller gets the words that move, release, stream, change state,
// write NVS or reboot outside such a request.
#include <catch2/catch.hpp>

#include <optional>
#include <string>

#include "firmware/hazards.hpp"
#include "firmware/menus.hpp"
#include "firmware/prompt.hpp"

using namespace birdcage;

namespace {

constexpr std::optional<VariantId> g2 = VariantId::carryout_g2;
constexpr std::optional<VariantId> unknown_variant = std::nullopt;

bool refused(std::optional<VariantId> variant, std::string_view menu, std::string_view command,
             HazardRequests requests) {
    return judge_command(variant, menu, command, requests).hazard();
}

}  // namespace

TEST_CASE("hazard rule: the backend's move, home and search requests pass, nothing else of their words") {
    for (const char* command :
         {"a 0 180.00", "a 1 45.5", "a 0 -12.25", "a 0 +5", "g 180.00 45.00", "h 0", "h 1", "h *"}) {
        INFO(command);
        CHECK_FALSE(refused(g2, "mot", command, backend_requests));
        CHECK_FALSE(refused(unknown_variant, "", command, backend_requests));
        CHECK(classify_command(g2, "mot", command).kind == HazardKind::moves);
    }
    CHECK_FALSE(refused(VariantId::travler_hal000, "os", "kill Search", backend_requests));
    CHECK_FALSE(refused(VariantId::travler_hal205, "ngsearch", "s", backend_requests));
    CHECK_FALSE(refused(g2, "dvb", "lnbdc odu", backend_requests));
    CHECK_FALSE(refused(g2, "dvb", "lnbdc stb", backend_requests));
    // Malformed versions of the same words are not what was asked for.
    for (const char* command : {"a 0", "a 5 10", "a x 10", "a 0 1e5", "g", "g 10", "h", "h 2", "h 0 1"}) {
        INFO(command);
        CHECK(refused(g2, "mot", command, backend_requests));
    }
    CHECK(refused(VariantId::travler_hal000, "os", "kill Shell", backend_requests));
    CHECK(refused(g2, "dvb", "lnbdc", backend_requests));
}

TEST_CASE("hazard rule: bare e, r, h, g and the life tests are refused to every caller") {
    for (const char* command : {"e", "r", "h", "g", "life", "motorlife", "motorboth", "azscan", "azscanwxp", "sd", "sp",
                                "sw", "w", "v", "vms", "pid", "p", "ma 0 100", "mv 0 10"}) {
        INFO(command);
        CHECK(refused(g2, "mot", command, backend_requests));
        CHECK(refused(g2, "mot", command, request_nothing));
        CHECK(refused(g2, "", command, request_nothing));  // unknown menu: every menu's rules
    }
    // What the MOT listing reads without moving.
    for (const char* command : {"a", "l", "ma", "mv", "elminmaxhome", "ela2s 45", "els2a 3116", "?", ""}) {
        INFO(command);
        CHECK_FALSE(refused(g2, "mot", command, request_nothing));
    }
    CHECK(classify_command(g2, "mot", "r").kind == HazardKind::releases);
    CHECK(classify_command(g2, "mot", "life").kind == HazardKind::moves);
}

TEST_CASE("hazard rule: a caller that asks for nothing gets no move at all") {
    for (const char* command : {"a 0 180.00", "g 180 45", "h 0", "kill Search", "lnbdc odu"}) {
        INFO(command);
        CHECK(refused(unknown_variant, "", command, request_nothing));
    }
    CHECK(refused(VariantId::travler_hal205, "ngsearch", "s", request_nothing));
}

TEST_CASE("hazard rule: NVS writes only where the user allowed them") {
    CHECK(refused(g2, "nvs", "e 20 1", backend_requests));
    CHECK(refused(g2, "nvs", "s", backend_requests));
    CHECK_FALSE(refused(g2, "nvs", "e 20 1", backend_requests | request_nvs_write));
    CHECK_FALSE(refused(g2, "nvs", "s", backend_requests | request_nvs_write));
    CHECK_FALSE(refused(g2, "nvs", "e 20", request_nothing));  // a read
    CHECK_FALSE(refused(g2, "nvs", "d 20", request_nothing));
    CHECK(refused(g2, "eeprom", "ee 3 1", request_nothing));
    CHECK_FALSE(refused(g2, "eeprom", "ee 3", request_nothing));
    // Never granted, whatever was allowed.
    const HazardRequests everything = backend_requests | request_nvs_write;
    for (const char* command : {"def", "inv", "inv 0", "reboot", "stow", "Q"}) {
        INFO(command);
        CHECK(refused(g2, "eeprom", command, everything));
        CHECK(refused(VariantId::travler_hal000, "", command, everything));
    }
    CHECK(classify_command(g2, "nvs", "s").kind == HazardKind::writes_nvs);
}

TEST_CASE("hazard rule: per menu and variant") {
    // `e` reads NVS with one argument, edits a DVB channel parameter with two, engages in MOT.
    CHECK(classify_command(g2, "dvb", "e 1 2").kind == HazardKind::changes_state);
    CHECK_FALSE(classify_command(g2, "dvb", "h 3").hazard());  // DVB parameter help, not a homing
    CHECK(classify_command(g2, "dvb", "ls").kind == HazardKind::streams);
    CHECK_FALSE(classify_command(g2, "dvb", "rssi 10").hazard());
    CHECK(classify_command(g2, "peak", "ts").kind == HazardKind::streams);
    CHECK(classify_command(g2, "adc", "scan").kind == HazardKind::moves);
    CHECK(classify_command(g2, "adc", "m").kind == HazardKind::streams);
    CHECK_FALSE(classify_command(g2, "adc", "rssi").hazard());
    CHECK(classify_command(g2, "step", "r").kind == HazardKind::releases);
    CHECK_FALSE(classify_command(g2, "step", "mv").hazard());
    CHECK(classify_command(g2, "gpio", "w A 5").kind == HazardKind::changes_state);
    CHECK(classify_command(g2, "a3981", "reset").kind == HazardKind::changes_state);
    // q: the G2's root (or an unknown menu, or an unknown variant) only.
    CHECK(classify_command(g2, "root", "q").kind == HazardKind::kills_shell);
    CHECK(classify_command(g2, "", "q").kind == HazardKind::kills_shell);
    CHECK(classify_command(unknown_variant, "root", "q").kind == HazardKind::kills_shell);
    CHECK_FALSE(classify_command(g2, "mot", "q").hazard());
    CHECK_FALSE(classify_command(VariantId::travler_hal000, "root", "q").hazard());
    // The menu words themselves are harmless.
    for (const char* word : {"mot", "motor", "nvs", "dvb", "os", "target", "ngsearch", "odu", "eeprom", "peak"}) {
        INFO(word);
        CHECK_FALSE(classify_command(unknown_variant, "", word).hazard());
    }
    CHECK(hazard_kind_name(HazardKind::writes_nvs) == "writes NVS");
}

TEST_CASE("menus: prompts are known by their shape, decorations before and after allowed") {
    CHECK(prompt_word("MOT>") == "MOT");
    CHECK(prompt_word("dish:MOT> ") == "MOT");
    CHECK(prompt_word("[WG]TRK>#") == "TRK");
    CHECK(prompt_word("(wg) EE>>") == "EE");
    CHECK(prompt_word(">") == "");
    CHECK_FALSE(prompt_word("Angle[0] = 180.00"));
    CHECK_FALSE(prompt_word("help [<command>]"));
    CHECK_FALSE(prompt_word("a rather long line of output that ends in MOT>"));
    CHECK(menu_with_prompt_word("EE")->word == "eeprom");
    CHECK(menu_entered_by("MOT")->prompt_word == "MOT");
    CHECK(is_root_prompt_word("trk"));
    CHECK(menu_entered_by("life") == nullptr);  // a MOT> command, not a menu
}

// The probe and the backend's framer once each had a prompt rule; they disagreed on echoes and
// listing words (`mot>`), on a third mark after '>' and on trailing blanks. One rule now.
TEST_CASE("menus: the probe's prompt word follows the framer's prompt rule") {
    for (const char* text : {"MOT>", "WG TRK>", "[G2]MOT>$", "dish:TRK>$ ", "#>", "TRK>>", "mot>", "Gmot>", "MOT>#$%",
                             "MOT>  ", "TRK>nvs", "Enter <a3981>", "a very long banner TRK>", "A3981>", "ee>"}) {
        INFO(text);
        CHECK(prompt_word(text).has_value() == looks_like_prompt(text));
        if (const auto word = prompt_word(text)) {
            CHECK(*word + ">" == prompt_text(text));
        }
    }
    CHECK_FALSE(prompt_word("mot>"));     // an echo or a listing word, not a prompt
    CHECK_FALSE(prompt_word("MOT>#$%"));  // at most two marks after '>'
}
