// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The first-contact matrix: every variant × how rotctld meets the dish (already up;
// started 0, 5 or 15 simulated seconds into its boot; the dish reboots mid-pass) × a reading of the
// firmware's open questions (the emulator's defaults and two alternative profiles) × the model
// (the variant's own, or auto-detect 90100). Through the stock /usr/bin/rotctld with the backend
// preloaded. Every cell: rotctld opens the dish, `P` moves it to the target, `p` reports it, and
// the emulator counted no hazard.
//
// Each cell is its own Catch2 test case, registered from the tables below, so that ctest runs
// them in parallel and names a failing cell exactly (label `matrix`).
#include "harness.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

using namespace std::chrono_literals;
using birdcage::sim::Emulator;
using birdcage::sim::Options;
using birdcage::sim::Variant;

namespace {

constexpr int kAutoDetectModel = 90100;

// The dish must be within this of the target, and so must what `p` says (two printed decimals
// plus the predictive deadband on the G2).
constexpr double kTolerance = 0.1;

struct Profile {
    std::string name;
    std::function<void(Options&)> apply;
};

struct VariantRow {
    Variant variant;
    const char* name;
    int own_model;
    // What get_info names when 90100 identified this variant.
    const char* detected_as;
    // Auto-detect: the rate the user passes with -s (the README tells G2 users -s 115200).
    int baud;
    // Fast enough that the slowest boot (the 2003 Carryout's 10-15 min, search included) costs
    // seconds, slow enough that a reboot reliably lands in the middle of a move.
    double time_scale;
};

const std::vector<VariantRow> kVariants = {
    {Variant::travler_hal000, "hal000", 90101, "HAL 0.0.00", 57600, 50.0},
    {Variant::travler_hal205, "hal205", 90102, "HAL 2.05", 57600, 50.0},
    {Variant::travler_pro, "pro", 90103, "Trav'ler Pro", 57600, 50.0},
    {Variant::carryout2003, "carryout2003", 90104, "Carryout HAL 1.00.065", 57600, 100.0},
    {Variant::carryout_g2, "g2", 90105, "Carryout G2", 115200, 10.0},
};

enum class Meeting { dish_up, boot_0s, boot_5s, boot_15s, reboot_mid_pass };

struct MeetingRow {
    Meeting meeting;
    const char* name;
    double into_boot = 0.0;  // simulated seconds of boot before rotctld starts
};

const std::vector<MeetingRow> kMeetings = {
    {Meeting::dish_up, "dish up"},
    {Meeting::boot_0s, "rotctld 0 s into boot", 0.0},
    {Meeting::boot_5s, "rotctld 5 s into boot", 5.0},
    {Meeting::boot_15s, "rotctld 15 s into boot", 15.0},
    {Meeting::reboot_mid_pass, "reboot mid-pass"},
};

using birdcage::sim::HelpLayout;

// Spread the non-default help layouts over the variants so that every layout meets the backend.
const std::vector<HelpLayout> kOtherHelpLayouts = {HelpLayout::words, HelpLayout::one_line, HelpLayout::comma_line,
                                                   HelpLayout::colon_table, HelpLayout::tab_table};

HelpLayout other_help_layout(const VariantRow& v, int which) {
    const auto index = static_cast<std::size_t>(&v - kVariants.data());
    return kOtherHelpLayouts[(2 * index + static_cast<std::size_t>(which)) % kOtherHelpLayouts.size()];
}

// Timings that compete with the backend's own windows (its quiet gap and reply windows are real
// time, because the line is) are stated in real seconds and scaled into the emulator's simulated
// ones; otherwise at 50x a one-second gap on the console would shrink to 20 ms.
double real_seconds(const Options& o, double seconds) {
    return seconds * o.time_scale;
}

// Two alternative readings of docs/firmware.md' open questions (sim/README.md, "Switches").
// Together they flip every switch that bears on first contact; a switch a variant does not have
// is simply ignored by the emulator for that variant. Left out on purpose: g2_homed and
// g2_boot_homes (an unhomed G2 refuses moves until `R 1` by design, tested in test_verbs.cpp),
// and the replay options. The terse profile meets the G2's reconstructed console (the pre-capture
// one), the others its captured console.
std::vector<Profile> profiles_for(const VariantRow& v) {
    const bool g_aborts_by_default = v.variant != Variant::carryout2003;
    const HelpLayout terse_help = other_help_layout(v, 0);
    const HelpLayout chatty_help = other_help_layout(v, 1);
    return {
        {"defaults", [](Options&) {}},
        // A quiet, minimal console: no echo, LF, silent on unknown commands, `>` prompts followed
        // by a space, bare upper-case help words, boot lines 0.3 s apart and the late one 0.3 s
        // after the completion line, every binary switch flipped.
        {"terse",
         [g_aborts_by_default, terse_help](Options& o) {
             o.echo = false;
             o.line_ending = birdcage::sim::LineEnding::lf;
             o.unknown_command_reply = "";
             o.out_of_range = birdcage::sim::OutOfRange::reject;
             o.move_ack = birdcage::sim::MoveAck::after_motion;
             o.answer_position_while_moving = false;
             o.az_report = birdcage::sim::AzReport::mechanical;
             o.g_aborts_on_input = !g_aborts_by_default;
             o.g2_root_q = birdcage::sim::G2RootQ::harmless;
             o.g2_console = birdcage::sim::G2Console::reconstructed;  // the pre-capture G2 console
             o.home_report = birdcage::sim::HomeReport::g2plus_status;
             o.prompt_style = birdcage::sim::PromptStyle::bare;
             o.prompt_space = true;
             o.hal205_boot_marker = birdcage::sim::BootMarker::no_lnb_voltage;
             o.hal205_accepts_mot = true;
             o.pro_q_at_odu_root_returns_to_idu = true;
             o.carryout_live_line_period = 1.0;
             o.az_mapping = birdcage::sim::AzMapping::literal;
             o.position_decimals = 1;
             o.travler_position_layout = birdcage::sim::TravlerPositionLayout::line_per_axis;
             o.help_layout = terse_help;
             o.help_upper_case = true;
             o.boot_line_gap = real_seconds(o, 0.3);
             o.pace_at_line_rate = true;
             o.late_boot_line_delay = real_seconds(o, 0.3);
         }},
        // A talkative console: CR-only line endings, an unknown-command text with `>` in it,
        // another help layout, indented three-decimal positions, an unsolicited status line every
        // 2 s, boot lines in one burst with the late line 1 s after, the invented 50 ms deaf window
        // after boot, output paced at the line rate, a firmware wrap manager with its wrap at north.
        {"chatty",
         [chatty_help](Options& o) {
             o.line_ending = birdcage::sim::LineEnding::cr;
             o.unknown_command_reply = "Error: bad command -> type ? for help";
             o.help_layout = chatty_help;
             o.position_decimals = 3;
             o.position_indent = 4;
             o.az_mapping = birdcage::sim::AzMapping::wrap_manager;
             o.az_wrap_point = 0.0;
             // INVENTED text: a known boot line here would be reboot evidence, another question.
             o.idle_line = "Status: tracker idle";
             o.idle_line_period = real_seconds(o, 2.0);
             o.boot_line_gap = 0.0;
             o.late_boot_line_delay = real_seconds(o, 1.0);
             o.boot_input_drop = real_seconds(o, 0.05);
             o.pace_at_line_rate = true;
             o.carryout_live_line_period = 0.1;
             o.rssi_floor = 500.0;
         }},
    };
}

struct Target {
    double az, el;
};

std::string last_lines(const std::string& text, std::size_t count) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
    }
    std::ostringstream out;
    for (std::size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i) {
        out << "  | " << lines[i] << '\n';
    }
    return out.str();
}

std::string last_commands(const Emulator& dish, std::size_t count) {
    const std::vector<std::string> commands = dish.received_commands();
    std::ostringstream out;
    for (std::size_t i = commands.size() > count ? commands.size() - count : 0; i < commands.size(); ++i) {
        out << '"' << commands[i] << "\" ";
    }
    return out.str();
}

std::string where(Emulator& dish) {
    const birdcage::sim::Pose p = dish.true_position();
    std::ostringstream out;
    out << "dish at az " << p.az << " el " << p.el << (dish.moving() ? " (moving)" : " (at rest)") << ", sim time "
        << dish.sim_time() << " s, hazards " << dish.hazards_received() << ", shell "
        << (dish.shell_alive() ? "alive" : "DEAD") << "; last commands: " << last_commands(dish, 12);
    return out.str();
}

// A client during a pass re-sends its target; until rotctld accepts one (it may answer an error
// while the backend re-initialises a rebooted dish) this keeps sending it.
bool command_accepted(e2e::RotctldConnection& client, const Target& t, std::chrono::milliseconds within,
                      std::string& last_reply) {
    std::ostringstream command;
    command << "P " << t.az << ' ' << t.el;
    return e2e::wait_until(
        [&] {
            last_reply = client.ask(command.str(), 1);
            return last_reply == "RPRT 0\n";
        },
        within);
}

// The dish reaches the target and `p` says so.
void reaches_and_reports(e2e::Rig& rig, e2e::RotctldConnection& client, const Target& t,
                         std::chrono::milliseconds within) {
    const bool settled = e2e::wait_until([&] { return e2e::settled_at(rig.dish(), t.az, t.el, kTolerance); }, within);
    INFO("target az " << t.az << " el " << t.el << "; " << where(rig.dish()));
    INFO("rotctld log, last lines:\n" << last_lines(rig.rotctld_log_text(), 30));
    REQUIRE(settled);
    e2e::RotctldConnection::Position reported;
    const bool reports = e2e::wait_until(
        [&] {
            reported = client.get_position();
            return reported.ok && e2e::angle_between(reported.az, t.az) <= kTolerance &&
                   std::fabs(reported.el - t.el) <= kTolerance;
        },
        10s);
    INFO("p: " << (reported.ok ? std::to_string(reported.az) + " " + std::to_string(reported.el) : reported.error));
    REQUIRE(reports);
}

void run_cell(const VariantRow& v, const MeetingRow& m, const Profile& profile, int model) {
    Options o = e2e::dish_options(v.variant, 100.0, 30.0, v.time_scale);
    o.already_booted = m.meeting == Meeting::dish_up || m.meeting == Meeting::reboot_mid_pass;
    profile.apply(o);
    // The 2003 Carryout's TV search cannot be stopped from the console, prints nothing and leaves
    // no trace a backend could read (docs/firmware.md 8.2): the README tells users to wait for it to
    // end. The matrix meets a unit whose search is off (all DIP switches up, 8.2); opening one
    // that is still searching is the open case listed in the closing note.
    if (v.variant == Variant::carryout2003)
        o.carryout_search_seconds = 0.0;

    std::vector<std::string> args = {"-C", "time_scale=" + std::to_string(v.time_scale)};
    if (model == kAutoDetectModel) {
        args.insert(args.end(), {"-s", std::to_string(v.baud)});
    }
    const double into_boot = m.into_boot;
    auto start_into_boot = [into_boot](Emulator& dish) {
        if (into_boot > 0.0) {
            REQUIRE(e2e::wait_until([&] { return dish.sim_time() >= into_boot; }, 30s));
        }
    };

    std::unique_ptr<e2e::Rig> rig;
    try {
        rig = std::make_unique<e2e::Rig>(o, model, args, start_into_boot);
    } catch (const std::exception& e) {
        FAIL("rotctld did not open the dish; its log, last lines:\n" << last_lines(e.what(), 30));
    }
    e2e::RotctldConnection client(rig->port());

    if (model == kAutoDetectModel) {
        const std::string info = client.ask("_", 1);
        INFO("get_info: " << info);
        CHECK(info.find(v.detected_as) != std::string::npos);
    }

    // Room for the slowest recovery: a rebooting 2003 Carryout boots and searches for ~620
    // simulated seconds before it listens again (6 s here).
    const auto move_time = 30s;
    std::string reply;
    if (m.meeting != Meeting::reboot_mid_pass) {
        const Target t{150.0, 40.0};
        const bool accepted = command_accepted(client, t, 1s, reply);
        INFO("P reply: " << reply << "; " << where(rig->dish()));
        REQUIRE(accepted);
        reaches_and_reports(*rig, client, t, move_time);
    } else {
        // A few targets, then a long slew the dish loses power during, then more targets. Each is
        // more than the predictor's 20-degree restart gate from the one before, so every target
        // is a pointing of its own and the dish must end exactly on it in every pointing mode
        // (a sparse list of nearby targets would be extrapolated as a satellite's motion).
        for (const Target& t : {Target{130.0, 32.0}, Target{165.0, 40.0}}) {
            REQUIRE(command_accepted(client, t, 1s, reply));
            reaches_and_reports(*rig, client, t, move_time);
        }
        const Target slew{260.0, 55.0};
        REQUIRE(command_accepted(client, slew, 1s, reply));
        const bool mid_move = e2e::wait_until(
            [&] {
                const birdcage::sim::Pose p = rig->dish().true_position();
                return rig->dish().moving() && e2e::sky_angle(p.az, p.el, slew.az, slew.el) > 30.0;
            },
            10s);
        INFO(where(rig->dish()));
        REQUIRE(mid_move);
        rig->dish().power_cycle();
        INFO("power cycled at sim time " << rig->dish().sim_time() << " s");
        for (const Target& t : {Target{200.0, 50.0}, Target{160.0, 35.0}}) {
            const bool accepted = command_accepted(client, t, move_time, reply);
            INFO("P reply: " << reply << "; " << where(rig->dish()) << "\nrotctld log, last lines:\n"
                             << last_lines(rig->rotctld_log_text(), 30));
            REQUIRE(accepted);
            reaches_and_reports(*rig, client, t, move_time);
        }
    }
    INFO(where(rig->dish()));
    CHECK(rig->dish().hazards_received() == 0);
    CHECK(rig->dish().shell_alive());
    CHECK(rig->rotctld_running());
}

class Cell : public Catch::ITestInvoker {
public:
    Cell(const VariantRow& v, const MeetingRow& m, Profile p, int model)
        : variant_(v), meeting_(m), profile_(std::move(p)), model_(model) {}
    void invoke() const override { run_cell(variant_, meeting_, profile_, model_); }

private:
    const VariantRow& variant_;
    const MeetingRow& meeting_;
    Profile profile_;
    int model_;
};

// Cells that fail today: bugs the matrix found and that are not fixed yet, each with its reason.
// Hidden from ctest — a known failure is not a flaky one — but they run by hand:
// `test_first_contact "[open]"`. None today; a new one is added here only together with a note
// in docs/development.md's first-contact matrix paragraph.
struct OpenCell {
    Variant variant;
    std::string_view meeting, profile, why;
};
const std::array<OpenCell, 0> kOpenCells{};

bool is_open(const VariantRow& v, const MeetingRow& m, const Profile& p) {
    return std::any_of(std::begin(kOpenCells), std::end(kOpenCells), [&](const OpenCell& c) {
        return c.variant == v.variant && c.meeting == m.name && c.profile == p.name;
    });
}

// Names avoid the characters a Catch2 test spec treats specially (`,` `[` `]` `*` `\`), since
// ctest runs each cell by its name.
struct Registrar {
    Registrar() {
        for (const VariantRow& v : kVariants) {
            for (const MeetingRow& m : kMeetings) {
                for (const Profile& p : profiles_for(v)) {
                    for (const int model : {v.own_model, kAutoDetectModel}) {
                        std::ostringstream name;
                        name << v.name << " / " << m.name << " / " << p.name << " / "
                             << (model == kAutoDetectModel ? "auto 90100" : "own " + std::to_string(model));
                        const std::string tags =
                            std::string("[e2e][matrix][") + v.name + "]" + (is_open(v, m, p) ? "[.][open]" : "");
                        // The registry copies the name and tags and owns the invoker.
                        Catch::AutoReg(new Cell(v, m, p, model), CATCH_INTERNAL_LINEINFO, Catch::StringRef(),
                                       Catch::NameAndTags{name.str(), tags});
                    }
                }
            }
        }
    }
};

const Registrar registrar;

}  // namespace
