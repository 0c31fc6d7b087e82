// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe: maps an unknown dish console (baud, prompt, variant, error text, help, submenus)
// into a JSON report, and `record`s interactive sessions as transcripts (docs/transcripts.md).
// It takes the port for itself first, then finds out where the console is (leaving a known submenu
// with its exit word, stopping at a prompt it cannot name), enters only the menus the firmware facts
// name, and sends every word through the core's hazard rule asking for nothing (docs/firmware.md §15).
//
//   birdcage-probe --port PATH [--baud N] [--variant V] [--fd]
//                  [--deep [--wordlist FILE] [--submenu NAME]...]
//   birdcage-probe record --port PATH --output FILE [--baud N] [--variant V] [--fd] [--force]
//                  [--source TEXT]
#include <algorithm>
#include <array>
#include <chrono>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "birdcage_version.hpp"
#include "cli_args.hpp"
#include "console/detect.hpp"
#include "console/synchroniser.hpp"
#include "firmware/menus.hpp"
#include "firmware/prompt.hpp"
#include "firmware/variants.hpp"
#include "probe/console_io.hpp"
#include "probe/deep.hpp"
#include "probe/json.hpp"
#include "probe/record.hpp"

// tools/probe-words.txt, compiled in (probe_words.cpp is generated from it).
extern const char* const default_probe_words;

namespace {

using namespace std::chrono_literals;
using birdcage::Clock;
using namespace probe;

// docs/firmware.md 6.1: the G2 answers only at 115200; the others are documented at 57600; 9600 is
// pyserial's default (the Pro client) and 19200/38400 are the rest of the usual set.
constexpr std::array<int, 5> candidate_bauds{115200, 57600, 9600, 19200, 38400};
constexpr auto baud_listen = 600ms;              // after a bare CR, for a console to say anything
constexpr const char* nonsense_word = "xyzzyq";  // harmless: no firmware documents it
// A dish probed right after power-on may take minutes to boot (the G2's search, docs/firmware.md 6.2).
constexpr auto sync_budget = 300s;
constexpr int exit_busy = 3;
constexpr int max_menus_left = 4;  // nesting deeper than this is not documented anywhere

void progress(const std::string& what) {
    std::cerr << "birdcage-probe: " << what << '\n';
}

std::optional<int> int_arg(const char* text) {
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || value <= 0)
        return std::nullopt;
    return static_cast<int>(value);
}

// A baud "answers" when a bare CR yields printable text or a prompt.
bool answers(birdcage::Transport& port) {
    port.discard_input();
    if (!port.write("\r", Clock::now() + 1s))
        return false;
    std::string heard;
    const auto deadline = Clock::now() + baud_listen;
    std::array<char, 256> buffer{};
    for (;;) {
        // A prompt with nothing after it settles the question at once.
        const bool prompt_seen = trailing_prompt(heard).has_value();
        const auto wait_until = prompt_seen ? std::min(deadline, Clock::now() + quiet_after_prompt) : deadline;
        const auto got = port.read(buffer.data(), buffer.size(), wait_until);
        if (!got)
            break;
        heard.append(buffer.data(), got.value);
    }
    if (trailing_prompt(heard))
        return true;
    // Text with line endings (a prompt followed by a status line included) at the right rate;
    // line noise at a wrong one.
    const auto printable = std::count_if(heard.begin(), heard.end(),
                                         [](char c) { return (c >= 0x20 && c < 0x7f) || c == '\r' || c == '\n'; });
    return printable >= 2 && printable * 10 >= static_cast<long>(heard.size()) * 8;
}

// ---- where the console is -------------------------------------------------------------------------

struct Location {
    std::string start_prompt;       // the prompt the console showed when the probe arrived
    std::vector<std::string> left;  // submenu prompts left with their exit word on the way to the root
    std::string root_prompt;        // empty when the probe stopped
    std::string stopped;            // why it stopped instead of guessing
};

// From the prompt the console showed to its root: a documented root prompt is the root; a
// documented submenu's prompt is left with that menu's exit word; any other prompt (a bare `>`, a
// word no firmware fact names) is a root only if its `?` listing names documented menus. Anything
// else: stop and say so.
Location locate(Probe& probe) {
    Location where;
    where.start_prompt = probe.prompt;
    for (int hops = 0; hops <= max_menus_left; ++hops) {
        const std::string prompt = probe.prompt;
        const auto word = birdcage::prompt_word(prompt);
        if (prompt.empty() || !word) {
            where.stopped = "the console showed no prompt";
            return where;
        }
        if (birdcage::is_root_prompt_word(*word)) {
            where.root_prompt = prompt;
            return where;
        }
        if (const birdcage::MenuFact* menu = birdcage::menu_with_prompt_word(*word)) {
            const std::string exit(menu->exit_word);
            progress("the console is at " + prompt + " (the `" + std::string(menu->word) +
                     "` menu): leaving it with `" + exit + "` before anything else");
            const auto reply = probe.send(exit);
            if (!reply || !reply->prompt) {
                where.stopped = "no prompt after `" + exit + "` at " + prompt;
                return where;
            }
            where.left.push_back(prompt);
            if (*reply->prompt == prompt) {
                where.stopped = "`" + exit + "` did not leave " + prompt;
                return where;
            }
            continue;
        }
        progress("the console is at " + prompt + ", a prompt the firmware facts do not name: asking `?`");
        const auto reply = probe.send("?");
        if (!reply || !reply->prompt || *reply->prompt != prompt) {
            where.stopped = "no stable prompt after `?` at " + prompt;
            return where;
        }
        const auto listing = parse_help(reply_lines(*reply, "?"));
        const bool names_menus = std::any_of(listing.begin(), listing.end(), [](const HelpEntry& entry) {
            return birdcage::menu_entered_by(entry.name) != nullptr;
        });
        if (names_menus) {
            where.root_prompt = prompt;
            return where;
        }
        where.stopped = "the console is at " + prompt +
                        ", a prompt the firmware facts do not name, and its `?` names no menu: the probe does not "
                        "guess where it is (leave the console at its root prompt and run the probe again)";
        return where;
    }
    where.stopped = "still no root prompt after leaving " + std::to_string(max_menus_left) + " menus";
    return where;
}

// ---- which variant ----------------------------------------------------------------------------------

struct Identification {
    std::string name;  // short name, empty when unsure
    std::string display;
    std::string how;           // "given", "identified", "unsure"
    std::string maybe_inside;  // the identified root is also what this variant shows inside a tunnel
    std::vector<std::string> evidence;
    std::string candidates;
};

// The backend's detector ranks what the console showed (boot lines, the root prompt, the root
// listing); only a clear winner is named.
Identification identify(const std::vector<std::string>& heard, const std::string& root_prompt,
                        const std::vector<std::string>& root_listing, std::optional<birdcage::VariantId> given) {
    Identification id;
    if (given) {
        id.name = birdcage::profile(*given).short_name;
        id.display = birdcage::profile(*given).display_name;
        id.how = "given";
        return id;
    }
    birdcage::ConsoleEvidence evidence{heard, root_prompt, birdcage::parse_help_listing(root_listing)};
    const auto ranking = birdcage::rank_evidence(evidence);
    for (const auto& score : ranking)
        if (score.score > 0)
            id.candidates += (id.candidates.empty() ? "" : ", ") +
                             std::string(birdcage::profile(score.variant).short_name) + " " +
                             std::to_string(score.score);
    if (const auto winner = birdcage::clear_winner(ranking)) {
        id.name = birdcage::profile(winner->variant).short_name;
        id.display = birdcage::profile(winner->variant).display_name;
        id.how = "identified";
        id.evidence = winner->reasons;
        if (const auto inside = birdcage::profile(winner->variant).also_shown_inside)
            id.maybe_inside = birdcage::profile(*inside).short_name;
    } else {
        id.how = "unsure";
    }
    return id;
}

// ---- the report -------------------------------------------------------------------------------------

struct Menu {
    std::string name;
    std::string prompt;
    std::vector<HelpEntry> help;
};

struct DeepOptions {
    bool enabled = false;
    std::string wordlist_path;          // empty: the compiled-in list
    std::vector<std::string> submenus;  // empty: the root and every listed submenu
};

struct Report {
    std::string port;
    int baud = 0;  // 0 on a pty: no line speed applies there
    std::vector<int> bauds_tried;
    Location where;
    Identification variant;
    std::vector<std::string> error_lines;
    std::vector<HelpEntry> root_help;
    std::vector<Menu> menus;
    std::vector<std::pair<std::string, std::string>> not_entered;
    std::string final_prompt;
};

void print_report(const Report& r, const Probe& probe, const DeepReport* deep) {
    std::cout << "{\n  \"format_version\": 2,\n  \"port\": " << json_string(r.port)
              << ",\n  \"line\": " << (r.baud ? "\"serial\"" : "\"pty\"")
              << ",\n  \"baud\": " << (r.baud ? std::to_string(r.baud) : std::string("null"))
              << ",\n  \"bauds_tried\": [";
    for (std::size_t i = 0; i < r.bauds_tried.size(); ++i)
        std::cout << (i ? ", " : "") << r.bauds_tried[i];
    std::cout << "],\n  \"line_ending\": " << json_string(probe.line_ending)
              << ",\n  \"start_prompt\": " << json_string(r.where.start_prompt)
              << ",\n  \"left\": " << json_strings(r.where.left)
              << ",\n  \"stopped\": " << (r.where.stopped.empty() ? std::string("null") : json_string(r.where.stopped))
              << ",\n  \"root_prompt\": " << json_string(r.where.root_prompt) << ",\n  \"variant\": {\"name\": "
              << (r.variant.name.empty() ? std::string("null") : json_string(r.variant.name))
              << ", \"display_name\": " << json_string(r.variant.display) << ", \"how\": " << json_string(r.variant.how)
              << ", \"evidence\": " << json_strings(r.variant.evidence)
              << ", \"candidates\": " << json_string(r.variant.candidates) << ", \"or_inside\": "
              << (r.variant.maybe_inside.empty() ? std::string("null") : json_string(r.variant.maybe_inside)) << "}"
              << ",\n  \"error_probe\": " << json_string(nonsense_word)
              << ",\n  \"error_string\": " << json_string(r.error_lines.empty() ? "" : r.error_lines.front())
              << ",\n  \"root_help\": " << json_help(r.root_help, "  ") << ",\n  \"menus\": [";
    for (std::size_t i = 0; i < r.menus.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"name\": " << json_string(r.menus[i].name)
                  << ", \"prompt\": " << json_string(r.menus[i].prompt)
                  << ", \"help\": " << json_help(r.menus[i].help, "    ") << "}";
    std::cout << (r.menus.empty() ? "" : "\n  ") << "],\n  \"not_entered\": [";
    for (std::size_t i = 0; i < r.not_entered.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"name\": " << json_string(r.not_entered[i].first)
                  << ", \"reason\": " << json_string(r.not_entered[i].second) << "}";
    std::cout << (r.not_entered.empty() ? "" : "\n  ") << "],\n  \"refused\": [";
    for (std::size_t i = 0; i < probe.refused.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"command\": " << json_string(probe.refused[i].first)
                  << ", \"reason\": " << json_string(probe.refused[i].second) << "}";
    std::cout << (probe.refused.empty() ? "" : "\n  ") << "],\n  \"sent\": " << json_strings(probe.sent)
              << ",\n  \"final_prompt\": " << json_string(r.final_prompt);
    if (deep != nullptr)
        std::cout << ",\n  \"deep\": " << json_deep(*deep);
    std::cout << "\n}\n";
}

// Each root listing word the firmware facts name as a menu: entered, its `?` read, left with its
// exit word. Listed commands are never sent: on a real MOT> listing they move the motors.
// Behind a bare `>` root a submenu is told from the root only on a console whose submenus name
// themselves: the probe knows that once it has left one (`MOT>`, then `>`); a word that then
// answers at `>` is no submenu here.
void walk_menus(Probe& probe, Report& report) {
    const auto names_itself = [](const std::string& prompt) {
        return !birdcage::prompt_word(prompt).value_or("").empty();
    };
    const bool root_told_apart = names_itself(report.where.root_prompt) ||
                                 std::any_of(report.where.left.begin(), report.where.left.end(), names_itself);
    for (const auto& entry : report.root_help) {
        if (entry.name == "q" || entry.name == "?" || entry.name == "help")
            continue;
        const birdcage::MenuFact* menu = birdcage::menu_entered_by(entry.name);
        if (menu == nullptr) {
            report.not_entered.emplace_back(entry.name, "not a menu the firmware facts name: never sent");
            continue;
        }
        if (!root_told_apart) {
            report.not_entered.emplace_back(entry.name,
                                            "the root prompt is a bare `>` and no submenu was seen naming itself: "
                                            "the probe could not tell a submenu from the root, so it enters none");
            continue;
        }
        if (probe.prompt != report.where.root_prompt)
            break;  // lost our way; do not wander further
        progress("entering `" + entry.name + "`");
        const auto reply = probe.send(std::string(menu->word));
        if (!reply)
            continue;  // refused: recorded in probe.refused
        if (!reply->prompt) {
            report.where.stopped = "no prompt after entering `" + entry.name + "`: stopped walking the menus";
            break;
        }
        if (*reply->prompt == report.where.root_prompt) {
            report.not_entered.emplace_back(entry.name, "answered at the root prompt: not a submenu here");
            continue;
        }
        probe.menu_of_prompt.emplace(*reply->prompt, std::string(menu->word));
        Menu mapped{entry.name, *reply->prompt, {}};
        if (const auto help = probe.send("?"))
            mapped.help = parse_help(reply_lines(*help, "?"));
        report.menus.push_back(std::move(mapped));
        const auto back = probe.send(std::string(menu->exit_word));
        if (!back || !back->prompt || *back->prompt != report.where.root_prompt) {
            report.where.stopped = "`" + std::string(menu->exit_word) + "` at " + report.menus.back().prompt +
                                   " did not return to " + report.where.root_prompt + ": stopped walking the menus";
            break;
        }
    }
}

int run_probe(const std::string& path, std::optional<int> baud, std::optional<birdcage::VariantId> given, bool force_fd,
              const DeepOptions& deep_options) {
    WordList words;
    if (deep_options.enabled) {
        std::string text = default_probe_words;
        if (!deep_options.wordlist_path.empty()) {
            std::ifstream file(deep_options.wordlist_path);
            if (!file) {
                std::cerr << "birdcage-probe: cannot read " << deep_options.wordlist_path << '\n';
                return 1;
            }
            std::ostringstream contents;
            contents << file.rdbuf();
            text = contents.str();
        }
        words = parse_wordlist(text);
    }
    auto lock = take_port(path);
    if (!lock)
        return exit_busy;

    Report report;
    report.port = path;
    std::unique_ptr<birdcage::Transport> port;
    // A pty (the emulator) passes bytes whatever speed it is set to: one open, and no rate to report.
    const bool pty = birdcage::is_pseudo_terminal(path);
    std::vector<int> candidates =
        baud ? std::vector<int>{*baud} : std::vector<int>(candidate_bauds.begin(), candidate_bauds.end());
    if (pty)
        candidates.resize(1);
    for (const int candidate : candidates) {
        std::string error;
        auto opened = open_port(path, candidate, force_fd, error);
        if (!opened) {
            std::cerr << "birdcage-probe: cannot open " << path << ": " << error << '\n';
            return 1;
        }
        if (pty) {
            progress("listening on a pty: no line speed applies");
        } else {
            report.bauds_tried.push_back(candidate);
            progress("listening at " + std::to_string(candidate) + " baud");
        }
        if (answers(*opened)) {
            port = std::move(opened);
            report.baud = pty ? 0 : candidate;
            break;
        }
    }
    if (!port) {
        std::cerr << "birdcage-probe: no answer " << (pty ? "on the pty" : "at any baud rate") << '\n';
        std::cout << "{\"format_version\": 2, \"port\": " << json_string(path) << ", \"baud\": null}\n";
        return 1;
    }
    // Our own last open is done: from here nobody else opens the port (root excepted).
    if (const auto exclusive = lock->make_exclusive(); !exclusive)
        progress(exclusive.message);

    const Guard guard(given, false);
    Probe probe(*port, guard);
    // The backend's console synchroniser: a booting, noisy or stale console is brought to a
    // confirmed prompt with nothing but line endings (and `?`).
    const birdcage::LogSink to_stderr = [](birdcage::LogLevel level, const std::string& message) {
        if (level == birdcage::LogLevel::error || level == birdcage::LogLevel::warning)
            progress(message);
    };
    const auto& sync_profile = given ? birdcage::profile(*given) : birdcage::probe_profile();
    progress("waiting for a prompt");
    birdcage::ConsoleSynchroniser synchroniser(
        *port,
        birdcage::console_sync_settings(sync_profile,
                                        std::chrono::duration_cast<std::chrono::milliseconds>(sync_budget)),
        to_stderr);
    const auto synced = synchroniser.synchronise();
    probe.prompt = synced.value.prompt;
    if (probe.prompt.empty()) {
        // A prompt with a decoration the synchroniser does not take for one: ask with a bare line.
        if (const auto reply = probe.send(""))
            probe.prompt = reply->prompt.value_or("");
    }
    report.where = locate(probe);
    if (!report.where.root_prompt.empty()) {
        probe.menu_of_prompt.emplace(report.where.root_prompt, "root");
        progress("at the root prompt " + report.where.root_prompt);
        if (const auto nonsense = probe.send(nonsense_word))
            report.error_lines = reply_lines(*nonsense, nonsense_word);
        std::vector<std::string> root_listing;
        if (const auto root_help = probe.send("?"))
            root_listing = reply_lines(*root_help, "?");
        report.root_help = parse_help(root_listing);
        report.variant = identify(synced.value.heard, report.where.root_prompt, root_listing, given);
        progress("variant: " + (report.variant.name.empty()
                                    ? "not identified (" + report.variant.candidates + ")"
                                    : report.variant.display + " (" + report.variant.how + ")"));
        walk_menus(probe, report);
    } else {
        progress("stopped: " + report.where.stopped);
    }

    DeepDiscovery deep(probe, words, report.where.root_prompt);
    deep.report.wordlist = deep_options.wordlist_path.empty() ? "(built in)" : deep_options.wordlist_path;
    for (const auto& [line, why] : words.rejected)
        deep.report.not_tried.emplace_back(line, why);
    if (deep_options.enabled && !report.where.root_prompt.empty() && probe.prompt == report.where.root_prompt) {
        auto wanted = [&](const std::string& name) {
            return deep_options.submenus.empty() ||
                   std::find(deep_options.submenus.begin(), deep_options.submenus.end(), name) !=
                       deep_options.submenus.end();
        };
        bool going = true;
        if (wanted("root")) {
            DeepMenu root{"root", report.where.root_prompt, {}, 0, {}, {}};
            going = deep.run_menu(root, "", report.root_help);
        }
        std::vector<std::string> to_enter;
        for (const auto& menu : report.menus)
            if (wanted(menu.name))
                to_enter.push_back(menu.name);
        // A named submenu that `?` does not list (found by an earlier deep run) is entered too, if
        // the firmware facts name it.
        for (const auto& name : deep_options.submenus)
            if (name != "root" && std::find(to_enter.begin(), to_enter.end(), name) == to_enter.end())
                to_enter.push_back(name);
        for (const auto& name : to_enter) {
            if (!going)
                break;
            const auto listed =
                std::find_if(report.menus.begin(), report.menus.end(), [&](const Menu& m) { return m.name == name; });
            DeepMenu menu{name, "", {}, 0, {}, {}};
            going = deep.run_menu(menu, name, listed == report.menus.end() ? std::vector<HelpEntry>{} : listed->help);
        }
    } else if (deep_options.enabled) {
        deep.report.stopped = "no root prompt to start from";
    }
    report.final_prompt = probe.prompt;
    print_report(report, probe, deep_options.enabled ? &deep.report : nullptr);
    progress(report.where.root_prompt.empty() ? "done: the console's place is unknown (see \"stopped\")" : "done");
    return !report.where.root_prompt.empty() ? 0 : 1;
}

const char* const help_text =
    R"(Usage: birdcage-probe --port PATH [--baud N] [--variant V] [--fd]
                      [--deep [--wordlist FILE] [--submenu NAME]...]
       birdcage-probe record --port PATH --output FILE [--baud N] [--variant V] [--fd] [--force] [--source TEXT]

Maps an unknown Winegard dish console (baud rate, prompt, variant, error text, help listing,
submenus) and prints a JSON report on stdout, progress on stderr; with `record`, a pass-through
terminal that tees the session into a transcript (docs/transcripts.md) for the emulator and the
regression tests.

The probe takes the port for itself first: it refuses a port another program has open (rotctld
included), a UUCP lock file in /run/lock names, or another program has flock()ed, and holds it
exclusively while it runs. It then finds out where the console is: at a submenu prompt it knows
(`MOT>`, where rotctld leaves a G2) it leaves with `q` before anything else; at a prompt it
cannot name it stops and says so. It enters only the menus docs/firmware.md names, never sends a
listed command, and sends no word the hazard rule (docs/firmware.md section 15) names: nothing that moves,
releases, streams, changes state, writes NVS or reboots.

  --port PATH         serial device or pty (e.g. /dev/ttyUSB0)
  --baud N            line speed (default: probe tries 115200 57600 9600 19200 38400;
                      record uses the variant's, or 115200; a pty has none: not tried)
  --variant hal000|hal205|pro|carryout2003|g2
                      judge hazards by this firmware's rules (default: every variant's, the strictest)
  --fd                open PATH as a plain file descriptor, not through libserialport
  --force             record: send even what the hazard rule refuses
  --deep              also try candidate command words in each menu and report those the
                      firmware accepts although `?` does not list them (see below)
  --wordlist FILE     --deep: candidate words, one a line, `#` comments (default: the built-in
                      list, every command word docs/firmware.md names)
  --submenu NAME      --deep: probe only this menu (repeatable; `root` is the root prompt); a
                      menu docs/firmware.md names but `?` does not list is entered anyway
  --output FILE       record: the transcript to write
  --source TEXT       record: the transcript's Source header
  --help              this text
  --version           the program's version

Deep discovery learns each menu's answer to a word that cannot exist, then sends each
candidate word alone and reports it only when the console answers it twice the same way and
differently from that (or the prompt changes: a submenu, left again with `q`). A word goes out
only after the previous one's prompt came back. It never sends arguments (a list line with two
words is refused) and never sends a word the hazard rule names in any menu of any variant
(reported under "not_tried"). An unknown word can still do something nobody has documented:
run it with the dish free to move. If a word leaves no prompt within 3 s the probe stops trying
and says so.

Exit status: 0 the console's root was found (probe) or the session was recorded, 1 no console,
a console whose place the probe could not tell, or an I/O error, 2 usage error, 3 the port is busy.
)";

// A usage error: one line on stderr, exit status 2.
int usage_error(const std::string& message) {
    std::cerr << "birdcage-probe: " << message << " (see --help)\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    bool record = false, force = false, force_fd = false;
    DeepOptions deep;
    std::string port, output, source = "recorded with birdcage-probe record";
    std::optional<int> baud;
    std::optional<birdcage::VariantId> variant;
    for (int i = 1; i < argc; ++i) {
        std::string_view arg = argv[i];
        if (arg == "--help" || arg == "-h") {
            std::cout << help_text;
            return 0;
        }
        if (arg == "--version") {
            std::cout << "birdcage-probe " BIRDCAGE_VERSION "\n";
            return 0;
        }
    }
    birdcage::cli::ArgCursor args(argc, argv);
    while (args.next()) {
        const std::string& arg = args.flag();
        const bool inline_value = args.has_inline_value();
        const bool takes_value = arg == "--port" || arg == "--output" || arg == "--source" || arg == "--baud" ||
                                 arg == "--variant" || arg == "--wordlist" || arg == "--submenu";
        if (args.position() == 1 && arg == "record") {
            record = true;
        } else if (takes_value) {
            const auto text = args.value();
            if (!text)
                return usage_error(arg + " needs a value");
            if (arg == "--port")
                port = *text;
            else if (arg == "--output")
                output = *text;
            else if (arg == "--source")
                source = *text;
            else if (arg == "--wordlist")
                deep.wordlist_path = *text;
            else if (arg == "--submenu")
                deep.submenus.push_back(*text);
            else if (arg == "--baud") {
                baud = int_arg(text->c_str());
                if (!baud)
                    return usage_error("--baud: expected a positive whole number, got '" + *text + "'");
            } else {
                variant = birdcage::variant_from_name(*text);
                if (!variant)
                    return usage_error("--variant: expected hal000|hal205|pro|carryout2003|g2, got '" + *text + "'");
            }
        } else if (arg == "--force" || arg == "--fd" || arg == "--deep") {
            if (inline_value)
                return usage_error(arg + " takes no value");
            (arg == "--force" ? force : arg == "--fd" ? force_fd : deep.enabled) = true;
        } else {
            return usage_error("unknown argument '" + arg + "'");
        }
    }
    if (port.empty())
        return usage_error("--port is required");
    if (record && output.empty())
        return usage_error("record needs --output FILE");
    if (record && deep.enabled)
        return usage_error("--deep is for the probe, not record");
    if (!record && force)
        return usage_error("--force is for record: the probe never sends what the hazard rule refuses");
    if (!deep.enabled && (!deep.wordlist_path.empty() || !deep.submenus.empty()))
        return usage_error("--wordlist and --submenu need --deep");
    if (record) {
        const auto& profile =
            variant ? birdcage::profile(*variant) : birdcage::profile(birdcage::VariantId::carryout_g2);
        return run_record(port, baud.value_or(variant ? profile.baud : 115200), profile, variant, force_fd, force,
                          output, source);
    }
    return run_probe(port, baud, variant, force_fd, deep);
}
