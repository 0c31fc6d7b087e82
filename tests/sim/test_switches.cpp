// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The switches for docs/firmware.md's open questions (§14; sim/README.md, Switches), each driven on the
// I/O-free Console in simulated time: the default and every alternative.
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "birdcage_sim/console.hpp"

using namespace birdcage::sim;

namespace {

Options options_for(Variant variant) {
    Options options;
    options.variant = variant;
    return options;
}

std::string send(Console& console, std::string_view bytes) {
    console.feed(bytes);
    return console.take_output();
}

struct Chunk {
    double t;
    std::string bytes;
};

// Output chunks with the simulated time they appeared, in steps of `step`, until `until`.
std::vector<Chunk> run_for(Console& console, double until, double step = 0.001) {
    std::vector<Chunk> chunks;
    while (console.time() < until - 1e-9) {
        console.advance(step);
        std::string bytes = console.take_output();
        if (!bytes.empty())
            chunks.push_back({console.time(), std::move(bytes)});
    }
    return chunks;
}

std::string joined(const std::vector<Chunk>& chunks) {
    std::string all;
    for (const Chunk& chunk : chunks)
        all += chunk.bytes;
    return all;
}

// Simulated time at which `text` had completely appeared; negative if never.
double time_of(const std::vector<Chunk>& chunks, std::string_view text) {
    std::string all;
    for (const Chunk& chunk : chunks) {
        all += chunk.bytes;
        if (all.find(text) != std::string::npos)
            return chunk.t;
    }
    return -1.0;
}

// Advance until `text` has appeared (at most `limit` simulated seconds); returns everything.
std::string until_seen(Console& console, std::string_view text, double limit = 600.0) {
    std::string all;
    const double end = console.time() + limit;
    while (all.find(text) == std::string::npos && console.time() < end) {
        console.advance(0.001);
        all += console.take_output();
    }
    return all;
}

}  // namespace

TEST_CASE("help layout: available is the captured G2's, described the reconstructed G2's", "[console][switch][help]") {
    Console g2(options_for(Variant::carryout_g2));
    const std::string captured = send(g2, "?\r");
    CHECK(captured.starts_with("?\r\nAvailable commands:\r\n   a3981         "));
    CHECK(captured.find("\r\n   mot           Motors\r\n") != std::string::npos);
    CHECK(captured.ends_with("\r\n   step          Raw stepper\r\nTRK>"));

    Options reconstructed = options_for(Variant::carryout_g2);
    reconstructed.g2_console = G2Console::reconstructed;
    Console console(reconstructed);
    const std::string help = send(console, "?\r");
    CHECK(help.starts_with("?\r\nEnter <a3981> - "));
    CHECK(help.find("\r\nEnter <mot> - Motors\r\n") != std::string::npos);
    CHECK(help.ends_with("Enter <q> - Quit this menu\r\nhelp [<command>]\r\nTRK>"));
}

TEST_CASE("help layout: every alternative lists the same menu words", "[console][switch][help]") {
    const std::vector<std::string> hal000_words = {"mot", "nvs", "os", "stow", "reboot", "q", "?"};
    struct Case {
        HelpLayout layout;
        bool upper;
        std::string expected;
    };
    const std::vector<Case> cases = {
        {HelpLayout::words, false, "mot\r\nnvs\r\nos\r\nstow\r\nreboot\r\nq\r\n?\r\n"},
        {HelpLayout::one_line, false, "mot nvs os stow reboot q ?\r\n"},
        {HelpLayout::comma_line, false, "mot, nvs, os, stow, reboot, q, ?\r\n"},
        {HelpLayout::one_line, true, "MOT NVS OS STOW REBOOT Q ?\r\n"},
        {HelpLayout::colon_table, false,
         "mot    : Motor\r\nnvs    : Non-volatile storage\r\nos     : OS\r\nstow   : Stow\r\nreboot : Reboot\r\n"
         "q      : Quit this menu\r\n?      : Help\r\n"},
        {HelpLayout::tab_table, true,
         "MOT\tMotor\r\nNVS\tNon-volatile storage\r\nOS\tOS\r\nSTOW\tStow\r\nREBOOT\tReboot\r\nQ\tQuit this "
         "menu\r\n?\tHelp\r\n"},
    };
    for (const Case& c : cases) {
        Options options = options_for(Variant::travler_hal000);
        options.help_layout = c.layout;
        options.help_upper_case = c.upper;
        Console console(options);
        CAPTURE(static_cast<int>(c.layout), c.upper);
        CHECK(send(console, "?\r") == "?\r\n" + c.expected + "TRK>");
        // The listing describes the menu actually in force: MOT> lists its own commands.
        send(console, "mot\r");
        const std::string mot = send(console, "?\r");
        CHECK(mot.find(c.upper ? "G" : "g") != std::string::npos);
        CHECK(mot.find(c.upper ? "NVS" : "nvs") == std::string::npos);
        // Upper case is a listing style only: the shell still takes the lower-case words.
        CHECK(send(console, "q\r") == "q\r\nTRK>");
    }
}

TEST_CASE("help layout: a word list hides menu entries the switches disable", "[console][switch][help]") {
    Options options = options_for(Variant::travler_hal205);
    options.help_layout = HelpLayout::one_line;
    Console without(options);
    CHECK(send(without, "?\r") == "?\r\nmotor ngsearch nvs os stow reboot q ?\r\nTRK>");
    options.hal205_accepts_mot = true;
    Console with(options);
    CHECK(send(with, "?\r") == "?\r\nmotor mot ngsearch nvs os stow reboot q ?\r\nTRK>");
}

TEST_CASE("prompt followed by a space (switch, default none, §6.1)", "[console][switch]") {
    Console plain(options_for(Variant::carryout_g2));
    CHECK(send(plain, "\r") == "\r\nTRK>");
    Options options = options_for(Variant::carryout_g2);
    options.prompt_space = true;
    Console spaced(options);
    CHECK(send(spaced, "\r") == "\r\nTRK> ");
    CHECK(send(spaced, "mot\r") == "mot\r\nMOT> ");
    Options bare = options_for(Variant::travler_hal000);
    bare.prompt_space = true;
    bare.prompt_style = PromptStyle::bare;
    Console travler(bare);
    CHECK(send(travler, "\r") == "\r\n> ");
}

TEST_CASE("line endings LF CR and CR alone (switch)", "[console][switch]") {
    Options options = options_for(Variant::carryout_g2);
    options.line_ending = LineEnding::lfcr;
    Console lfcr(options);
    CHECK(send(lfcr, "mot\r") == "mot\n\rMOT>");
    CHECK(send(lfcr, "a\r") == "a\n\r    Angle[0] = 180.00\n\r    Angle[1] = 45.00\n\rMOT>");
    options.line_ending = LineEnding::cr;
    Console cr(options);
    CHECK(send(cr, "mot\r") == "mot\rMOT>");
}

TEST_CASE("boot: input is accepted right after the last boot line (default), dropped by switch",
          "[console][switch][boot]") {
    Options options = options_for(Variant::travler_hal000);
    options.already_booted = false;
    Console console(options);
    CHECK(until_seen(console, "NoGPS\r\n").ends_with("NoGPS\r\n"));
    CHECK_FALSE(console.booting());
    // travler_init.py writes at once (§3.6).
    CHECK(send(console, "q\r") == "q\r\nTRK>");

    options.boot_input_drop = 0.05;
    Console deaf(options);
    until_seen(deaf, "NoGPS\r\n");
    CHECK(send(deaf, "q\r").empty());
    deaf.advance(0.049);
    CHECK(send(deaf, "\r").empty());
    deaf.advance(0.002);
    CHECK(send(deaf, "\r") == "\r\nTRK>");
    CHECK(deaf.commands() == std::vector<std::string>{"q", "", ""});  // received, not acted on
}

TEST_CASE("boot: the Trav'ler's power-up calibration moves, one reading per switch value", "[console][switch][boot]") {
    struct Reading {
        TravlerBootMoves moves;
        double lowest_az, end_az, end_el;  // mechanical AZ reached on the way, and where the boot leaves the dish
    };
    for (const Reading& r :
         {Reading{TravlerBootMoves::park, 0.0, 0.0, 45.0}, Reading{TravlerBootMoves::home_return, 0.0, 120.0, 30.0},
          Reading{TravlerBootMoves::none, 120.0, 120.0, 30.0}}) {
        INFO(travler_boot_moves_name(r.moves));
        for (Variant variant : {Variant::travler_hal000, Variant::travler_hal205}) {
            Options options = options_for(variant);
            options.already_booted = false;
            options.start_az = 120.0;
            options.start_el = 30.0;
            options.travler_boot_moves = r.moves;
            Console console(options);
            double lowest = console.mechanical_az();
            std::string boot;
            while (boot.find("NoGPS") == std::string::npos && console.time() < 600.0) {
                console.advance(0.01);
                boot += console.take_output();
                lowest = std::min(lowest, console.mechanical_az());
            }
            CHECK(boot == "NoGPS\r\n");
            CHECK(lowest == Approx(r.lowest_az).margin(0.01));
            CHECK(console.mechanical_az() == Approx(r.end_az).margin(0.01));
            CHECK(console.position().el == Approx(r.end_el).margin(0.01));
            // The 2 s before any move is the same in every reading; a reading without moves is ready then.
            if (r.moves == TravlerBootMoves::none)
                CHECK(console.time() == Approx(2.0).margin(0.02));
            else
                CHECK(console.time() > 5.0);
        }
    }
    CHECK(parse_travler_boot_moves("home-return") == TravlerBootMoves::home_return);
    CHECK_FALSE(parse_travler_boot_moves("calibrate"));
}

TEST_CASE("boot: moves that outlast the boot run on while the console answers, pausing between legs",
          "[console][switch][boot]") {
    Options options = options_for(Variant::travler_hal000);
    options.already_booted = false;
    options.start_az = 420.0;  // on the wrap's second branch: displayed 60
    options.start_el = 30.0;
    options.travler_boot_moves = TravlerBootMoves::home_return;
    options.boot_moves_overlap = 1.0;
    options.boot_move_pause = 3.0;
    Console console(options);
    std::string boot;
    while (boot.find("NoGPS") == std::string::npos && console.time() < 60.0) {
        console.advance(0.01);
        boot += console.take_output();
    }
    // The ready line 1 s after the first move started (2 s in), the dish under way to its stop.
    CHECK(console.time() == Approx(3.0).margin(0.02));
    CHECK(console.moving());
    CHECK(console.mechanical_az() < 420.0);
    // The search stop leaves the calibration running; a move commanded now queues behind it.
    send(console, "os\r");
    send(console, "kill Search\r");
    send(console, "q\r");
    send(console, "mot\r");
    send(console, "a 0 150\r");
    double lowest = console.mechanical_az(), still_at_stop = 0.0;
    while (console.mechanical_az() > 0.0 + 1e-9 && console.time() < 200.0)
        console.advance(0.01);
    lowest = std::min(lowest, console.mechanical_az());
    // At its stop the dish stands still for the pause, then goes back up, then to the target.
    const double at_stop = console.time();
    while (console.mechanical_az() < 1e-6 && console.time() < 200.0) {
        console.advance(0.01);
        still_at_stop = console.time() - at_stop;
    }
    CHECK(lowest == Approx(0.0).margin(0.01));
    CHECK(still_at_stop == Approx(3.0).margin(0.02));
    double highest = console.mechanical_az();
    while (console.moving() && console.time() < 400.0) {
        console.advance(0.01);
        highest = std::max(highest, console.mechanical_az());
    }
    CHECK(highest == Approx(420.0).margin(0.01));
    CHECK(console.mechanical_az() == Approx(150.0).margin(0.01));
    CHECK(console.hazards() == 0);
}

TEST_CASE("boot: the Pro's silent boot and the 2003 Carryout's answer while their moves outlast the boot",
          "[console][switch][boot]") {
    for (const Variant variant : {Variant::travler_pro, Variant::carryout2003}) {
        Options options = options_for(variant);
        options.already_booted = false;
        options.start_az = 200.0;
        options.start_el = 50.0;
        options.boot_moves_overlap = 0.5;
        if (variant == Variant::carryout2003)
            options.carryout_search_seconds = 0.0;
        Console console(options);
        while (console.booting() && console.time() < 60.0)
            console.advance(0.01);
        INFO(variant_name(variant));
        CHECK(console.time() == Approx(2.5).margin(0.02));
        CHECK(console.moving());
        CHECK_FALSE(send(console, "\r").empty());  // the shell answers while the dish still moves
        while (console.moving() && console.time() < 200.0)
            console.advance(0.01);
        CHECK(console.mechanical_az() == Approx(0.0).margin(0.01));
    }
}

TEST_CASE("boot: the captured G2 keeps a CR typed after Boot Complete and answers it after TRK>",
          "[console][switch][boot][g2]") {
    Options options = options_for(Variant::carryout_g2);
    options.already_booted = false;
    options.g2_boot_seconds = 4.0;
    Console console(options);
    const std::string boot = until_seen(console, "Boot Complete\r\n");
    CHECK(boot.ends_with("Copyright 2013 - Winegard Company\r\nBoot Complete\r\n\r\n"));
    CHECK(send(console, "\r").empty());  // kept for the shell, not answered yet
    const auto rest = run_for(console, console.time() + 5.0);
    CHECK(joined(rest).ends_with("Enabled LNB ODU 18V\r\nGPS Not Found\r\nTRK>\r\nTRK>"));
    CHECK(time_of(rest, "GPS Not Found") == Approx(4.0).margin(0.03));
}

TEST_CASE("boot: G2 late line after Boot Complete, a CR typed in between is answered after it (reconstructed)",
          "[console][switch][boot][g2]") {
    Options options = options_for(Variant::carryout_g2);
    options.g2_console = G2Console::reconstructed;
    options.already_booted = false;
    options.late_boot_line_delay = 2.0;
    Console console(options);
    std::string boot = until_seen(console, "Boot Complete\r\n");
    CHECK(boot.ends_with("Antenna Facing Front\r\nBoot Complete\r\n"));
    const double complete_at = console.time();
    CHECK(send(console, "\r").empty());  // kept for the shell, not answered yet
    const auto rest = run_for(console, complete_at + 3.0);
    CHECK(joined(rest) == "Loc Startup: IDU NOT Present\r\nTRK>\r\nTRK>");
    CHECK(time_of(rest, "Loc Startup") == Approx(complete_at + 2.0).margin(0.002));

    // Default: the documented order with a short gap.
    Options quick = options_for(Variant::carryout_g2);
    quick.g2_console = G2Console::reconstructed;
    quick.already_booted = false;
    Console fast(quick);
    until_seen(fast, "Boot Complete\r\n");
    const double t0 = fast.time();
    const auto tail = run_for(fast, t0 + 0.2);
    CHECK(joined(tail) == "Loc Startup: IDU NOT Present\r\nTRK>");
    CHECK(time_of(tail, "Loc Startup") == Approx(t0 + 0.05).margin(0.002));
}

TEST_CASE("boot: input typed before the completion line is lost", "[console][switch][boot][g2]") {
    Options options = options_for(Variant::carryout_g2);
    options.already_booted = false;
    Console console(options);
    until_seen(console, "Application is running...\r\n");
    CHECK(send(console, "\r").empty());
    const std::string rest = until_seen(console, "TRK>");
    CHECK(rest.ends_with("Enabled LNB ODU 18V\r\nGPS Not Found\r\nTRK>"));
    console.advance(0.5);
    CHECK(console.take_output().empty());  // the early CR was never answered
}

TEST_CASE("boot: line gap switch spaces the boot lines in simulated time", "[console][switch][boot][g2]") {
    Options options = options_for(Variant::carryout_g2);
    options.already_booted = false;
    options.boot_line_gap = 0.3;
    Console console(options);
    const auto chunks = run_for(console, 2.0);
    const double first = time_of(chunks, "Application Starting");
    const double second = time_of(chunks, "Version 02.02.48");
    const double third = time_of(chunks, "Copyright 2013");
    CHECK(second - first == Approx(0.3).margin(0.002));
    CHECK(third - second == Approx(0.3).margin(0.002));
}

TEST_CASE("line rate: output leaves at 10 bits per byte of the variant's baud (switch)", "[console][switch]") {
    Options options = options_for(Variant::carryout_g2);
    options.pace_at_line_rate = true;
    Console console(options);
    console.feed("os\rid\r");
    const auto chunks = run_for(console, 0.2, 0.0005);
    const std::string all = joined(chunks);
    REQUIRE(all.ends_with("Flash Size:           458752\r\nOS>"));
    // 115200 baud: 11520 bytes per simulated second.
    const double expected = static_cast<double>(all.size()) / 11520.0;
    CHECK(chunks.back().t == Approx(expected).margin(0.001));
    for (const Chunk& chunk : chunks)
        CHECK(chunk.bytes.size() <= 7);  // at most 5.76 bytes per 0.5 ms + carry

    Console unpaced(options_for(Variant::carryout_g2));
    CHECK(send(unpaced, "os\rid\r").size() == all.size());  // same bytes, all at once
}

TEST_CASE("line rate: the boot log of a 57600-baud Trav'ler is paced as well", "[console][switch][boot]") {
    Options options = options_for(Variant::travler_hal205);
    options.already_booted = false;
    options.pace_at_line_rate = true;
    Console console(options);
    std::string boot;
    while (boot.find("NoGPS") == std::string::npos && console.time() < 600.0) {
        console.advance(1e-5);  // a tenth of a byte time
        boot += console.take_output();
    }
    CHECK(boot == "NoGPS");  // the line ending is still on its way
    console.advance(10.0 / 57600.0 * 2 + 1e-6);
    CHECK(console.take_output() == "\r\n");
}

TEST_CASE("idle line: an unsolicited line at a fixed period once booted (switch, default none)", "[console][switch]") {
    Console quiet(options_for(Variant::carryout_g2));
    CHECK(joined(run_for(quiet, 30.0, 0.01)).empty());

    Options options = options_for(Variant::carryout_g2);
    options.idle_line = "Loc Startup: IDU NOT Present";
    options.idle_line_period = 10.0;
    Console console(options);
    const auto chunks = run_for(console, 25.0, 0.01);
    CHECK(joined(chunks) == "Loc Startup: IDU NOT Present\r\nLoc Startup: IDU NOT Present\r\n");
    REQUIRE(chunks.size() == 2);
    CHECK(chunks[0].t == Approx(10.0).margin(0.011));
    CHECK(chunks[1].t == Approx(20.0).margin(0.011));
    // The shell is unaffected: the next command is answered normally.
    CHECK(send(console, "\r") == "\r\nTRK>");
}

TEST_CASE("position replies: decimals, indentation, Trav'ler fields per line (switches)", "[console][switch]") {
    Options options = options_for(Variant::travler_hal000);
    options.position_decimals = 1;
    options.travler_position_layout = TravlerPositionLayout::line_per_axis;
    Console travler(options);
    send(travler, "mot\r");
    CHECK(send(travler, "a\r") == "a\r\nAZ = 180.0\r\nEL = 45.0\r\nSK = 0.0\r\nMOT>");

    Options g2 = options_for(Variant::carryout_g2);
    g2.position_indent = 4;
    g2.position_decimals = 3;
    Console console(g2);
    send(console, "mot\r");
    CHECK(send(console, "a\r") == "a\r\n    Angle[0] = 180.000\r\n    Angle[1] = 45.000\r\nMOT>");
    CHECK(send(console, "a 1 50\r") == "a 1 50\r\n    Angle = 50.000\r\nMOT>");
    // The captured console's own indentation is four spaces; the switch overrides it.
    Options flush = options_for(Variant::carryout_g2);
    flush.position_indent = 0;
    Console unindented(flush);
    send(unindented, "mot\r");
    CHECK(send(unindented, "a\r") == "a\r\nAngle[0] = 180.00\r\nAngle[1] = 45.00\r\nMOT>");
}

TEST_CASE("home report: G2 wrap limits by default, the G2+ status line by switch", "[console][switch][g2]") {
    Options options = options_for(Variant::carryout_g2);
    options.g2_homed = false;
    Console g2(options);
    send(g2, "mot\r");
    CHECK(until_seen(g2, "MOT>") == "");  // nothing pending
    g2.feed("h 0\r");
    CHECK(until_seen(g2, "MOT>", 60.0) ==
          "h 0\r\nMotorHome:0 timeout:8000\r\nHome TwelInch Az\r\nEnd MotorAzStall:part1\r\nAntenna Facing Front\r\n"
          "home:0  wrap_pos:0  wrap_min:-42333  wrap_max:2333\r\nMOT>");

    options.home_report = HomeReport::g2plus_status;
    Console plus(options);
    send(plus, "mot\r");
    plus.feed("h *\r");
    CHECK(until_seen(plus, "MOT>", 60.0).ends_with("\r\nAntenna Facing Front\r\nAZ - Angle: 1 Wrap: 0\r\nMOT>"));
    plus.feed("h 1\r");
    CHECK(until_seen(plus, "MOT>", 60.0) ==
          "h 1\r\nMotorHome:1 timeout:2000\r\nHome TwelInch El   Velocity: 4500\r\nEL Stall Timeout\r\nEl Home Angle: "
          "6500\r\nMOT>");

    // The reconstructed console's one-line reports.
    options.g2_console = G2Console::reconstructed;
    options.home_report = HomeReport::wrap_limits;
    Console reconstructed(options);
    send(reconstructed, "mot\r");
    reconstructed.feed("h *\r");
    CHECK(until_seen(reconstructed, "MOT>", 60.0) == "h *\r\nwrap_min:-42333 wrap_max:2333\r\nMOT>");
}

TEST_CASE("g abort on input: per-variant default (2003 Carryout no, §8.5), overridable",
          "[console][switch][carryout2003]") {
    Console carryout(options_for(Variant::carryout2003));
    send(carryout, "target\rg 300 60\r");
    carryout.advance(0.5);
    send(carryout, "q\r");  // carryout_scan.py's trailing q
    until_seen(carryout, "TRK>", 120.0);
    CHECK(carryout.position().az == Approx(300.0));
    CHECK(carryout.position().el == Approx(60.0));

    Options aborting = options_for(Variant::carryout2003);
    aborting.g_aborts_on_input = true;
    Console stopped(aborting);
    send(stopped, "target\rg 300 60\r");
    stopped.advance(0.5);
    send(stopped, "q\r");
    until_seen(stopped, "TRK>", 120.0);
    CHECK(stopped.position().az < 250.0);

    Options travler = options_for(Variant::travler_hal000);
    travler.g_aborts_on_input = false;
    Console kept(travler);
    send(kept, "mot\rg 200 50 0\r");
    kept.advance(0.5);
    send(kept, "\r");
    until_seen(kept, "\r\nMOT>\r\nMOT>", 120.0);
    CHECK(kept.position().az == Approx(200.0));
}

TEST_CASE("2003 Carryout: the live line period is a switch", "[console][switch][carryout2003]") {
    Options options = options_for(Variant::carryout2003);
    options.carryout_live_line_period = 1.0;
    Console console(options);
    send(console, "target\r");
    console.feed("g 200 40\r");
    const auto chunks = run_for(console, 3.05, 0.01);
    std::vector<double> times;
    for (const Chunk& chunk : chunks)
        if (chunk.bytes.find("el = ") != std::string::npos)
            times.push_back(chunk.t);
    REQUIRE(times.size() >= 3);
    CHECK(times[1] - times[0] == Approx(1.0).margin(0.011));
    CHECK(times[2] - times[1] == Approx(1.0).margin(0.011));
}
