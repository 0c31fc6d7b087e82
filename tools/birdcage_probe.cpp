// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe: maps an unknown dish console (baud, prompt, error text, help, submenus) into a
// JSON report, and `record`s interactive sessions as transcripts (docs/transcripts.md). The predecessor's
// console-probe, rewritten on the core's transports, prompt rule and hazard guard.
// Over 500 lines: one standalone tool (its argument parsing, the probe walk, the JSON report and the
// interactive recorder); each piece is small and only this tool uses it.
//
//   birdcage-probe --port PATH [--baud N] [--variant V] [--fd] [--force]
//                  [--deep [--wordlist FILE] [--submenu NAME]...]
//   birdcage-probe record --port PATH --output FILE [--baud N] [--variant V] [--fd] [--force]
//                  [--source TEXT]
#include <algorithm>
#include <array>
#include <cctype>
#include <set>
#include <sstream>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <poll.h>
#include <string>
#include <string_view>
#include <termios.h>
#include <unistd.h>
#include <vector>

#include "birdcage/console/framer.hpp"
#include "birdcage/firmware/protocol.hpp"
#include "birdcage/console/synchroniser.hpp"
#include "birdcage/console/transport.hpp"
#include "birdcage/firmware/variants.hpp"
#include "birdcage_sim/transcript.hpp"
#include "birdcage_version.hpp"
#include "cli_args.hpp"

// tools/probe-words.txt, compiled in (probe_words.cpp is generated from it).
extern const char* const default_probe_words;

namespace {

using namespace std::chrono_literals;
using birdcage::Clock;

// docs/firmware.md 6.1: the G2 answers only at 115200; the others are documented at 57600; 9600 is
// pyserial's default (the Pro client) and 19200/38400 are the rest of the usual set.
constexpr std::array<int, 5> candidate_bauds{115200, 57600, 9600, 19200, 38400};
constexpr auto baud_listen = 600ms;      // after a bare CR, for a console to say anything
constexpr auto reply_timeout = 3000ms;   // one command's reply, up to its prompt
constexpr auto quiet_after_prompt = 80ms;  // a prompt only counts if nothing follows it
constexpr const char* nonsense_word = "xyzzyq";  // harmless: no firmware documents it
// A dish probed right after power-on may take minutes to boot (the G2's search, docs/firmware.md 6.2).
constexpr auto sync_budget = 300s;

std::optional<int> int_arg(const char* text)
{
    char* end = nullptr;
    const long value = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || value <= 0) return std::nullopt;
    return static_cast<int>(value);
}

// ---- transports -------------------------------------------------------------------------------

bool is_pty(const std::string& path)
{
    std::error_code error;
    const auto resolved = std::filesystem::canonical(path, error);
    return (error ? path : resolved.string()).rfind("/dev/pts/", 0) == 0;
}

// libserialport cannot open ptys (codebases.md 3): ptys (or --fd) get FdTransport; real ports try
// libserialport first and fall back to a plain fd.
std::unique_ptr<birdcage::Transport> open_port(const std::string& path, int baud, bool force_fd, std::string& error)
{
    if (!force_fd && !is_pty(path)) {
        auto serial = birdcage::SerialPortTransport::open(path, baud);
        if (serial) return std::move(serial.value);
        error = serial.status.message;
    }
    auto fd = birdcage::FdTransport::open(path, baud);
    if (fd) return std::move(fd.value);
    error += (error.empty() ? "" : "; ") + fd.status.message;
    return nullptr;
}

// ---- console reading --------------------------------------------------------------------------

std::string last_line(std::string_view text)
{
    const std::size_t end = text.find_last_of("\r\n");
    return std::string(end == std::string_view::npos ? text : text.substr(end + 1));
}

// The prompt rule is the core's: only the unterminated text after the last line ending, and only
// if the whole of it is `WORD>` — so `help [<command>]` and `Enter <a3981> - ...` never count.
std::optional<std::string> trailing_prompt(std::string_view text)
{
    std::string line = last_line(text);
    if (!birdcage::looks_like_prompt(line)) return std::nullopt;
    while (!line.empty() && line.back() == ' ') line.pop_back();
    return line;
}

struct Reply {
    std::string raw;
    std::optional<std::string> prompt;
};

Reply read_reply(birdcage::Transport& port, std::chrono::milliseconds timeout)
{
    Reply reply;
    const auto deadline = Clock::now() + timeout;
    std::array<char, 512> buffer{};
    for (;;) {
        const bool prompt_seen = trailing_prompt(reply.raw).has_value();
        const auto wait_until = prompt_seen ? std::min(deadline, Clock::now() + quiet_after_prompt) : deadline;
        const auto got = port.read(buffer.data(), buffer.size(), wait_until);
        if (!got) break;
        reply.raw.append(buffer.data(), got.value);
    }
    reply.prompt = trailing_prompt(reply.raw);
    return reply;
}

// Reply lines without the echo of `command`, the prompt and empty lines.
std::vector<std::string> reply_lines(const Reply& reply, std::string_view command)
{
    std::vector<std::string> lines;
    std::string text = reply.raw;
    if (reply.prompt) text.resize(text.size() - last_line(text).size());
    std::size_t start = 0;
    bool echo_skipped = command.empty();
    while (start <= text.size()) {
        const std::size_t end = text.find_first_of("\r\n", start);
        std::string line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
        start = end == std::string::npos ? text.size() + 1 : end + 1;
        if (line.empty()) continue;
        if (!echo_skipped && (line == command || line.ends_with(">" + std::string(command)))) {
            echo_skipped = true;
            continue;
        }
        lines.push_back(line);
    }
    return lines;
}

// ---- help parsing -----------------------------------------------------------------------------

struct HelpEntry {
    std::string name;
    std::string description;
};

// Help formats seen on these consoles (docs/firmware.md §6.3): `Enter <cmd> - Description`;
// `cmd - Description`; `cmd  Description` (two or more spaces). Usage lines such as
// `help [<command>]` and placeholder words are not commands.
std::optional<HelpEntry> parse_help_line(std::string_view line)
{
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    // A usage line such as `help [<command>]` fails the one-word test below; a description may
    // show optional arguments (`Enter <mv> - Max velocity [<motor> <v>]`).
    if (line.empty()) return std::nullopt;
    HelpEntry entry;
    if (line.rfind("Enter <", 0) == 0) {
        const std::size_t close = line.find('>');
        if (close == std::string_view::npos) return std::nullopt;
        entry.name = std::string(line.substr(7, close - 7));
        const std::size_t dash = line.find(" - ", close);
        if (dash != std::string_view::npos) entry.description = std::string(line.substr(dash + 3));
    } else {
        std::size_t split = line.find(" - ");
        std::size_t skip = 3;
        if (split == std::string_view::npos) {
            split = line.find("  ");
            skip = 2;
        }
        if (split == std::string_view::npos) return std::nullopt;
        entry.name = std::string(line.substr(0, split));
        std::string_view rest = line.substr(split + skip);
        while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
        entry.description = std::string(rest);
    }
    static constexpr std::array<std::string_view, 5> placeholders{"command", "value", "index", "cmd", "n"};
    const bool word = !entry.name.empty() && std::all_of(entry.name.begin(), entry.name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '?';
    });
    if (!word || std::find(placeholders.begin(), placeholders.end(), entry.name) != placeholders.end()) return std::nullopt;
    return entry;
}

std::vector<HelpEntry> parse_help(const std::vector<std::string>& lines)
{
    std::vector<HelpEntry> entries;
    for (const auto& line : lines)
        if (auto entry = parse_help_line(line)) entries.push_back(std::move(*entry));
    return entries;
}

// ---- JSON ---------------------------------------------------------------------------------------

std::string json_string(std::string_view text)
{
    std::string out = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (byte < 0x20 || byte >= 0x7f) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\u%04x", byte);
            out += hex;
        } else out += c;
    }
    return out + "\"";
}

std::string json_strings(const std::vector<std::string>& items)
{
    std::string out = "[";
    for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + json_string(items[i]);
    return out + "]";
}

std::string json_help(const std::vector<HelpEntry>& entries, const std::string& indent)
{
    std::string out = "[";
    for (std::size_t i = 0; i < entries.size(); ++i)
        out += (i ? "," : "") + std::string("\n") + indent + "  {\"name\": " + json_string(entries[i].name) +
               ", \"description\": " + json_string(entries[i].description) + "}";
    return out + (entries.empty() ? "]" : "\n" + indent + "]");
}

// ---- the hazard guard ---------------------------------------------------------------------------

// The core's guard (protocol.hpp hazard_check) is the deny list. Without --variant it judges with
// the G2's rules, the strictest: they include `q` at the root prompt.
class Guard {
public:
    Guard(const birdcage::FirmwareProfile& profile, bool force) : profile_(profile), force_(force) {}

    // Empty when the command may go out; otherwise why not.
    std::string refusal(std::string_view command, std::string_view prompt) const
    {
        if (force_) return {};
        const std::string menu = birdcage::menu_for_prompt(profile_, prompt);
        const birdcage::HazardContext context{menu, false, false};
        const auto verdict = birdcage::hazard_check(profile_, command, context);
        return verdict ? std::string() : verdict.message;
    }

private:
    const birdcage::FirmwareProfile& profile_;
    bool force_;
};

// ---- probe --------------------------------------------------------------------------------------

struct Menu {
    std::string name;
    std::string prompt;
    std::vector<HelpEntry> help;
};

struct Probe {
    Probe(birdcage::Transport& transport, const Guard& hazard_guard) : port(transport), guard(hazard_guard) {}

    birdcage::Transport& port;
    const Guard& guard;
    std::string line_ending = "\r";
    std::string prompt;  // the prompt the console showed last
    std::vector<std::pair<std::string, std::string>> refused;

    std::optional<Reply> send(const std::string& command)
    {
        if (const std::string why = guard.refusal(command, prompt); !why.empty()) {
            refused.emplace_back(command, why);
            return std::nullopt;
        }
        port.discard_input();
        if (!port.write(command + line_ending, Clock::now() + reply_timeout)) return std::nullopt;
        Reply reply = read_reply(port, reply_timeout);
        if (reply.prompt) prompt = *reply.prompt;
        return reply;
    }
};

// ---- deep discovery -----------------------------------------------------------------------------

// A word list: one word a line, `#` comments. A line with more than one word is kept out: deep
// discovery never sends arguments.
struct WordList {
    std::vector<std::string> words;
    std::vector<std::pair<std::string, std::string>> rejected;
};

WordList parse_wordlist(const std::string& text)
{
    WordList list;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        if (const std::size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream fields(line);
        std::string word, extra;
        if (!(fields >> word)) continue;
        if (fields >> extra) {
            list.rejected.emplace_back(line, "more than one word: deep discovery never sends arguments");
            continue;
        }
        if (std::find(list.words.begin(), list.words.end(), word) == list.words.end()) list.words.push_back(word);
    }
    return list;
}

// Beyond the hazard guard: words docs/firmware.md says start motion (g, h, the scans, the wrap
// and position registers, energise/release), stream with no prompt until interrupted (agc, lnbv,
// snr, nid, ADC m) or change the dish's state (LNB supply, tuning, killing a task, `s` which saves
// or stops depending on the menu). Bare, most of them would act with defaults nobody documents,
// so deep discovery never sends them, in any menu. `q` and `?` are the probe's own navigation.
std::string never_bare_reason(std::string_view word)
{
    static constexpr std::array<std::string_view, 10> motion{"g", "h", "e", "r", "azscan", "azscanwxp", "motorboth",
                                                             "sw", "w", "sp"};
    static constexpr std::array<std::string_view, 5> streaming{"agc", "lnbv", "snr", "nid", "m"};
    static constexpr std::array<std::string_view, 4> state{"lnbdc", "t", "kill", "s"};
    auto in = [&](const auto& set) { return std::find(set.begin(), set.end(), word) != set.end(); };
    if (word == "q" || word == "?" || word == "help") return "the probe's own navigation word";
    if (in(motion)) return "starts or may start motion (docs/firmware.md 2, 6.3)";
    if (in(streaming)) return "streams without a prompt until interrupted (docs/firmware.md 6.5)";
    if (in(state)) return "changes the dish's state (docs/firmware.md 2, 6.3)";
    return {};
}

// Reply lines with every whole-word occurrence of `word` replaced by <word>, so that an error text
// which repeats the word (`Unknown command: xyzzyq`) compares equal for every word.
std::vector<std::string> normalised_reply(const Reply& reply, const std::string& word)
{
    auto lines = reply_lines(reply, word);
    auto is_word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; };
    for (auto& line : lines) {
        std::string out;
        std::size_t i = 0;
        while (i < line.size()) {
            const bool starts = line.compare(i, word.size(), word) == 0 && (i == 0 || !is_word_char(line[i - 1])) &&
                                (i + word.size() == line.size() || !is_word_char(line[i + word.size()]));
            if (starts) {
                out += "<word>";
                i += word.size();
            } else {
                out += line[i++];
            }
        }
        line = std::move(out);
    }
    return lines;
}

struct DeepFinding {
    std::string word;
    std::vector<std::string> reply;
    std::string prompt;  // set when the word changed the prompt (a submenu)
};

struct DeepMenu {
    std::string name;
    std::string prompt;
    std::vector<std::string> unknown_reply;
    std::size_t tried = 0;
    std::vector<DeepFinding> accepted;
    std::string note;  // why the menu was not (fully) probed
};

struct DeepReport {
    std::string wordlist;
    std::vector<DeepMenu> menus;
    std::vector<std::pair<std::string, std::string>> not_tried;
    std::string stopped;
};

constexpr std::array<const char*, 2> unknown_probes{"xyzzyq", "zqvxjw"};  // no firmware documents either

class DeepDiscovery {
public:
    DeepDiscovery(Probe& probe, const WordList& words, std::string root_prompt)
        : probe_(probe), words_(words), root_prompt_(std::move(root_prompt))
    {
    }

    // One menu, entered from the root with `enter` (empty for the root itself); returns false
    // when the console was lost and nothing more may be sent.
    bool run_menu(DeepMenu& menu, const std::string& enter, const std::vector<HelpEntry>& listed)
    {
        if (!enter.empty()) {
            const std::size_t refusals = probe_.refused.size();
            const auto reply = probe_.send(enter);
            if (!reply) {
                const bool refused = probe_.refused.size() > refusals;
                menu.note = "not entered: " + (refused ? probe_.refused.back().second : std::string("write failed"));
                report.menus.push_back(menu);
                return refused;
            }
            if (!reply->prompt) return stop("no prompt after entering " + enter);
            if (*reply->prompt == root_prompt_) {
                menu.note = "not a submenu: " + enter + " left the console at " + root_prompt_;
                report.menus.push_back(menu);
                return true;
            }
        }
        menu.prompt = probe_.prompt;
        if (!learn_unknown_reply(menu)) return leave(menu, enter);
        progress(menu, "probing");
        for (const auto& word : words_.words) {
            const bool known = std::any_of(listed.begin(), listed.end(), [&](const HelpEntry& entry) {
                return entry.name == word || lower(entry.name) == word;
            });
            if (known) continue;
            if (const std::string why = never_bare_reason(word); !why.empty()) {
                note_not_tried(word, why);
                continue;
            }
            const std::size_t refusals = probe_.refused.size();
            const auto reply = probe_.send(word);
            if (!reply) {
                if (probe_.refused.size() > refusals) continue;  // the hazard guard said no
                return stop("write failed");
            }
            ++menu.tried;
            if (!reply->prompt) return stop("no prompt within the reply timeout after `" + word + "` at " + menu.prompt);
            DeepFinding finding{word, reply_lines(*reply, word), {}};
            if (*reply->prompt != menu.prompt) {
                finding.prompt = *reply->prompt;
                menu.accepted.push_back(finding);
                progress(menu, "`" + word + "` leads to " + finding.prompt);
                if (!return_to(menu, enter)) return stop("could not return to " + menu.prompt + " after `" + word + "`");
                continue;
            }
            if (normalised_reply(*reply, word) == menu.unknown_reply) continue;
            menu.accepted.push_back(finding);
            progress(menu, "accepts `" + word + "`");
        }
        progress(menu, std::to_string(menu.tried) + " tried, " + std::to_string(menu.accepted.size()) + " accepted");
        return leave(menu, enter);
    }

    DeepReport report;

private:
    static std::string lower(std::string text)
    {
        for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return text;
    }

    void progress(const DeepMenu& menu, const std::string& what) const
    {
        std::cerr << "birdcage-probe: deep: " << menu.prompt << ' ' << what << '\n';
    }

    void note_not_tried(const std::string& word, const std::string& why)
    {
        const bool seen = std::any_of(report.not_tried.begin(), report.not_tried.end(), [&](const auto& entry) {
            return entry.first == word;
        });
        if (!seen) report.not_tried.emplace_back(word, why);
    }

    bool stop(const std::string& why)
    {
        report.stopped = why;
        std::cerr << "birdcage-probe: deep: stopped: " << why << '\n';
        return false;
    }

    // The menu's answer to a word that cannot exist, asked twice with different words: a menu
    // that answers them differently (the G2's NVS> reads the next index) cannot be probed.
    bool learn_unknown_reply(DeepMenu& menu)
    {
        std::vector<std::vector<std::string>> replies;
        for (const char* nonsense : unknown_probes) {
            const auto reply = probe_.send(nonsense);
            if (!reply || !reply->prompt || *reply->prompt != menu.prompt) {
                menu.note = std::string("no stable prompt after the unknown word ") + nonsense;
                return false;
            }
            replies.push_back(normalised_reply(*reply, nonsense));
        }
        if (replies[0] != replies[1]) {
            menu.note = "answers two unknown words differently; no unknown-command reply to compare with";
            return false;
        }
        menu.unknown_reply = replies[0];
        return true;
    }

    // Back to the menu's prompt after a word that changed it.
    bool return_to(const DeepMenu& menu, const std::string& enter)
    {
        if (probe_.prompt != root_prompt_) probe_.send("q");
        if (probe_.prompt == menu.prompt) return true;
        if (enter.empty() || probe_.prompt != root_prompt_) return false;
        probe_.send(enter);
        return probe_.prompt == menu.prompt;
    }

    bool leave(DeepMenu& menu, const std::string& enter)
    {
        report.menus.push_back(menu);
        if (enter.empty()) return true;
        probe_.send("q");
        if (probe_.prompt == root_prompt_) return true;
        return stop("`q` at " + menu.prompt + " did not return to " + root_prompt_);
    }

    Probe& probe_;
    const WordList& words_;
    std::string root_prompt_;
};

std::string json_deep(const DeepReport& deep)
{
    std::string out = "{\n    \"wordlist\": " + json_string(deep.wordlist) + ",\n    \"menus\": [";
    for (std::size_t i = 0; i < deep.menus.size(); ++i) {
        const DeepMenu& menu = deep.menus[i];
        out += std::string(i ? "," : "") + "\n      {\"menu\": " + json_string(menu.name) + ", \"prompt\": " +
               json_string(menu.prompt) + ", \"unknown_reply\": " + json_strings(menu.unknown_reply) +
               ", \"tried\": " + std::to_string(menu.tried) + ", \"note\": " + json_string(menu.note) + ", \"accepted\": [";
        for (std::size_t j = 0; j < menu.accepted.size(); ++j) {
            const DeepFinding& found = menu.accepted[j];
            out += std::string(j ? "," : "") + "\n        {\"word\": " + json_string(found.word) +
                   ", \"reply\": " + json_strings(found.reply) +
                   (found.prompt.empty() ? std::string() : ", \"prompt\": " + json_string(found.prompt)) + "}";
        }
        out += std::string(menu.accepted.empty() ? "" : "\n      ") + "]}";
    }
    out += std::string(deep.menus.empty() ? "" : "\n    ") + "],\n    \"not_tried\": [";
    for (std::size_t i = 0; i < deep.not_tried.size(); ++i)
        out += std::string(i ? "," : "") + "\n      {\"word\": " + json_string(deep.not_tried[i].first) +
               ", \"reason\": " + json_string(deep.not_tried[i].second) + "}";
    out += std::string(deep.not_tried.empty() ? "" : "\n    ") + "],\n    \"stopped\": " +
           (deep.stopped.empty() ? std::string("null") : json_string(deep.stopped)) + "\n  }";
    return out;
}

struct DeepOptions {
    bool enabled = false;
    std::string wordlist_path;         // empty: the compiled-in list
    std::vector<std::string> submenus;  // empty: the root and every listed submenu
};

// A baud "answers" when a bare CR yields printable text or a prompt.
bool answers(birdcage::Transport& port)
{
    port.discard_input();
    if (!port.write("\r", Clock::now() + 1s)) return false;
    std::string heard;
    const auto deadline = Clock::now() + baud_listen;
    std::array<char, 256> buffer{};
    while (auto got = port.read(buffer.data(), buffer.size(), deadline)) heard.append(buffer.data(), got.value);
    if (trailing_prompt(heard)) return true;
    const auto printable = std::count_if(heard.begin(), heard.end(), [](char c) {
        return (c >= 0x20 && c < 0x7f);
    });
    return printable >= 2 && printable * 10 >= static_cast<long>(heard.size()) * 8;
}

int run_probe(const std::string& path, std::optional<int> baud, const birdcage::FirmwareProfile& profile,
              const birdcage::FirmwareProfile& sync_profile, bool force_fd, bool force, const DeepOptions& deep_options)
{
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
    std::unique_ptr<birdcage::Transport> port;
    std::vector<int> tried;
    int found_baud = 0;
    for (const int candidate : baud ? std::vector<int>{*baud} : std::vector<int>(candidate_bauds.begin(), candidate_bauds.end())) {
        std::string error;
        auto opened = open_port(path, candidate, force_fd, error);
        if (!opened) {
            std::cerr << "birdcage-probe: cannot open " << path << ": " << error << '\n';
            return 1;
        }
        tried.push_back(candidate);
        if (answers(*opened)) {
            port = std::move(opened);
            found_baud = candidate;
            break;
        }
    }
    if (!port) {
        std::cerr << "birdcage-probe: no answer at any baud rate\n";
        std::cout << "{\"format_version\": 1, \"port\": " << json_string(path) << ", \"baud\": null}\n";
        return 1;
    }

    const Guard guard(profile, force);
    Probe probe(*port, guard);
    // The one console synchroniser of the backend's open paths: a booting, noisy or stale console
    // is brought to a confirmed prompt before anything but line endings (and `?`) is sent. Without
    // --variant the console is judged as auto-detect does, from no assumption about its prompts.
    const birdcage::LogSink to_stderr = [](birdcage::LogLevel level, const std::string& message) {
        if (level == birdcage::LogLevel::error || level == birdcage::LogLevel::warning)
            std::cerr << "birdcage-probe: " << message << '\n';
    };
    birdcage::ConsoleSynchroniser synchroniser(
        *port, birdcage::console_sync_settings(sync_profile, std::chrono::duration_cast<std::chrono::milliseconds>(sync_budget)),
        to_stderr);
    const auto synced = synchroniser.synchronise();
    if (!synced) std::cerr << "birdcage-probe: the console did not come into sync: " << synced.status.message << '\n';
    probe.prompt = synced.value.prompt;
    const std::string root_prompt = probe.prompt;

    const auto nonsense = probe.send(nonsense_word);
    const auto error_lines = nonsense ? reply_lines(*nonsense, nonsense_word) : std::vector<std::string>{};

    const auto root_help_reply = probe.send("?");
    const auto root_help = root_help_reply ? parse_help(reply_lines(*root_help_reply, "?")) : std::vector<HelpEntry>{};

    std::vector<Menu> menus;
    std::vector<std::pair<std::string, std::vector<std::string>>> commands;
    for (const auto& entry : root_help) {
        if (entry.name == "q" || entry.name == "?" || entry.name == "help") continue;  // never `q` at the root
        if (probe.prompt != root_prompt) break;  // lost our way; do not wander further
        const auto reply = probe.send(entry.name);
        if (!reply) continue;  // refused: recorded in probe.refused
        if (!reply->prompt || *reply->prompt == root_prompt) {
            commands.emplace_back(entry.name, reply_lines(*reply, entry.name));
            continue;
        }
        Menu menu{entry.name, *reply->prompt, {}};
        if (const auto help = probe.send("?")) menu.help = parse_help(reply_lines(*help, "?"));
        probe.send("q");  // leaves the submenu; the guard would refuse it at the root
        menus.push_back(std::move(menu));
    }

    // Deep discovery needs the hazard guard: --force does not reach it.
    const Guard deep_guard(profile, false);
    Probe deep_probe(*port, deep_guard);
    deep_probe.prompt = probe.prompt;
    DeepDiscovery deep(deep_probe, words, root_prompt);
    deep.report.wordlist = deep_options.wordlist_path.empty() ? "(built in)" : deep_options.wordlist_path;
    for (const auto& [line, why] : words.rejected) deep.report.not_tried.emplace_back(line, why);
    if (deep_options.enabled && !root_prompt.empty() && deep_probe.prompt == root_prompt) {
        auto wanted = [&](const std::string& name) {
            return deep_options.submenus.empty() ||
                   std::find(deep_options.submenus.begin(), deep_options.submenus.end(), name) != deep_options.submenus.end();
        };
        bool going = true;
        if (wanted("root")) {
            DeepMenu root{"root", root_prompt, {}, 0, {}, {}};
            going = deep.run_menu(root, "", root_help);
        }
        std::vector<std::string> to_enter;
        for (const auto& menu : menus)
            if (wanted(menu.name)) to_enter.push_back(menu.name);
        // A named submenu that `?` does not list (found by an earlier deep run) is entered too.
        for (const auto& name : deep_options.submenus)
            if (name != "root" && std::find(to_enter.begin(), to_enter.end(), name) == to_enter.end()) to_enter.push_back(name);
        for (const auto& name : to_enter) {
            if (!going) break;
            const auto listed = std::find_if(menus.begin(), menus.end(), [&](const Menu& menu) { return menu.name == name; });
            DeepMenu menu{name, "", {}, 0, {}, {}};
            going = deep.run_menu(menu, name, listed == menus.end() ? std::vector<HelpEntry>{} : listed->help);
        }
        probe.prompt = deep_probe.prompt;
        for (const auto& refusal : deep_probe.refused)
            if (std::find(probe.refused.begin(), probe.refused.end(), refusal) == probe.refused.end())
                probe.refused.push_back(refusal);
    } else if (deep_options.enabled) {
        deep.report.stopped = "no root prompt to start from";
    }

    std::cout << "{\n  \"format_version\": 1,\n  \"port\": " << json_string(path) << ",\n  \"baud\": " << found_baud
              << ",\n  \"bauds_tried\": [";
    for (std::size_t i = 0; i < tried.size(); ++i) std::cout << (i ? ", " : "") << tried[i];
    std::cout << "],\n  \"line_ending\": " << json_string(probe.line_ending)
              << ",\n  \"root_prompt\": " << json_string(root_prompt)
              << ",\n  \"error_probe\": " << json_string(nonsense_word)
              << ",\n  \"error_string\": " << json_string(error_lines.empty() ? "" : error_lines.front())
              << ",\n  \"root_help\": " << json_help(root_help, "  ") << ",\n  \"menus\": [";
    for (std::size_t i = 0; i < menus.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"name\": " << json_string(menus[i].name)
                  << ", \"prompt\": " << json_string(menus[i].prompt) << ", \"help\": " << json_help(menus[i].help, "    ")
                  << "}";
    std::cout << (menus.empty() ? "" : "\n  ") << "],\n  \"commands\": [";
    for (std::size_t i = 0; i < commands.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"name\": " << json_string(commands[i].first)
                  << ", \"reply\": " << json_strings(commands[i].second) << "}";
    std::cout << (commands.empty() ? "" : "\n  ") << "],\n  \"refused\": [";
    for (std::size_t i = 0; i < probe.refused.size(); ++i)
        std::cout << (i ? "," : "") << "\n    {\"command\": " << json_string(probe.refused[i].first)
                  << ", \"reason\": " << json_string(probe.refused[i].second) << "}";
    std::cout << (probe.refused.empty() ? "" : "\n  ") << "],\n  \"final_prompt\": " << json_string(probe.prompt);
    if (deep_options.enabled) std::cout << ",\n  \"deep\": " << json_deep(deep.report);
    std::cout << "\n}\n";
    return synced && !root_prompt.empty() ? 0 : 1;
}

// ---- record -------------------------------------------------------------------------------------

// Raw mode while recording from a terminal, restored on every exit path.
class RawTerminal {
public:
    RawTerminal()
    {
        if (!::isatty(STDIN_FILENO) || ::tcgetattr(STDIN_FILENO, &saved_) != 0) return;
        termios raw = saved_;
        ::cfmakeraw(&raw);
        raw.c_oflag |= OPOST | ONLCR;  // keep our own messages readable
        active_ = ::tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0;
    }
    ~RawTerminal()
    {
        if (active_) ::tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
    }
    RawTerminal(const RawTerminal&) = delete;
    RawTerminal& operator=(const RawTerminal&) = delete;
    bool active() const { return active_; }

private:
    termios saved_{};
    bool active_ = false;
};

int run_record(const std::string& path, int baud, const birdcage::FirmwareProfile& profile, bool force_fd, bool force,
               const std::string& output, const std::string& source)
{
    std::string error;
    auto port = open_port(path, baud, force_fd, error);
    if (!port) {
        std::cerr << "birdcage-probe: cannot open " << path << ": " << error << '\n';
        return 1;
    }
    std::ofstream file(output, std::ios::binary);
    if (!file) {
        std::cerr << "birdcage-probe: cannot write " << output << '\n';
        return 1;
    }
    birdcage::sim::TranscriptRecorder transcript({{"Variant", std::string(profile.short_name)},
                                                  {"Firmware", "(fill in: the version the dish reports)"},
                                                  {"Serial", std::to_string(baud) + " 8N1"},
                                                  {"Source", source},
                                                  {"Notes", "(fill in: what the dish was doing, what you typed and why)"}});
    const auto start = Clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

    const Guard guard(profile, force);
    const RawTerminal terminal;
    std::cerr << "birdcage-probe: recording " << path << " to " << output
              << (terminal.active() ? " (Ctrl-] to stop)" : "") << "\r\n";
    std::string typed;   // input not yet sent; lines go out whole, after the guard has seen them
    std::string heard;   // dish output, for the prompt the guard judges against
    // Piped input arrives all at once: each line waits for the reply to the previous one (its
    // prompt, or reply_timeout), so the guard judges it in the menu the dish is really in.
    std::optional<Clock::time_point> awaiting_reply_until;
    bool input_open = true;
    std::optional<Clock::time_point> closing_at;
    std::array<char, 512> buffer{};
    for (;;) {
        if (input_open) {
            pollfd stdin_poll{STDIN_FILENO, POLLIN, 0};
            if (::poll(&stdin_poll, 1, 10) > 0) {
                const ssize_t count = ::read(STDIN_FILENO, buffer.data(), buffer.size());
                if (count <= 0) input_open = false;
                const std::string_view bytes(buffer.data(), count > 0 ? static_cast<std::size_t>(count) : 0);
                if (const std::size_t stop = bytes.find('\x1d'); stop != std::string_view::npos) {  // Ctrl-]
                    input_open = false;
                    typed.clear();  // a half-typed line is dropped, not sent
                    closing_at = Clock::now();
                } else {
                    typed.append(bytes);
                }
            }
        }
        if (awaiting_reply_until && Clock::now() >= *awaiting_reply_until) awaiting_reply_until.reset();
        const std::size_t line_end = typed.find_first_of("\r\n");
        if (!awaiting_reply_until && line_end != std::string::npos) {
            const std::string line = typed.substr(0, line_end);
            const bool crlf = typed[line_end] == '\r' && line_end + 1 < typed.size() && typed[line_end + 1] == '\n';
            typed.erase(0, line_end + (crlf ? 2 : 1));
            const auto prompt = trailing_prompt(heard);
            if (const std::string why = guard.refusal(line, prompt.value_or("")); !why.empty()) {
                std::cerr << "\r\nbirdcage-probe: not sent: " << why << " (--force sends it)\r\n";
                transcript.comment("refused by birdcage-probe: " + birdcage::sim::escape_chunk(line) + " (" + why + ")");
            } else {
                const std::string wire = line + std::string(profile.line_ending);
                transcript.add(birdcage::sim::Direction::host_to_dish, wire, seconds());
                heard.clear();
                awaiting_reply_until = Clock::now() + reply_timeout;
                if (!port->write(wire, Clock::now() + 2s)) {
                    std::cerr << "birdcage-probe: write failed\r\n";
                    break;
                }
            }
        }
        if (!input_open && !closing_at && typed.find_first_of("\r\n") == std::string::npos && !awaiting_reply_until)
            closing_at = Clock::now() + 300ms;  // the dish may still be talking
        const auto got = port->read(buffer.data(), buffer.size(), Clock::now() + 10ms);
        if (got) {
            const std::string_view bytes(buffer.data(), got.value);
            transcript.add(birdcage::sim::Direction::dish_to_host, bytes, seconds());
            heard.append(bytes);
            if (heard.size() > 4096) heard.erase(0, heard.size() - 4096);
            std::cout.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
            std::cout.flush();
            if (trailing_prompt(heard)) awaiting_reply_until.reset();
            if (closing_at) closing_at = std::max(*closing_at, Clock::now() + 300ms);
        } else if (got.status.code != birdcage::Errc::timeout) {
            std::cerr << "\r\nbirdcage-probe: " << got.status.message << "\r\n";
            break;
        }
        if (closing_at && Clock::now() >= *closing_at) break;
    }
    file << transcript.text();
    std::cerr << "\r\nbirdcage-probe: wrote " << output << "\r\n";
    return 0;
}

const char* const help_text =
    R"(Usage: birdcage-probe --port PATH [--baud N] [--variant V] [--fd] [--force]
                      [--deep [--wordlist FILE] [--submenu NAME]...]
       birdcage-probe record --port PATH --output FILE [--baud N] [--variant V] [--fd] [--force] [--source TEXT]

Maps an unknown Winegard dish console (baud rate, prompt, error text, help listing, submenus) and
prints a JSON report on stdout; with `record`, a pass-through terminal that tees the session into
a transcript (docs/transcripts.md) for the emulator and the regression tests. Never sends a command
docs/firmware.md lists as a hazard (such as `q` at the G2's root prompt) unless --force is given.

  --port PATH         serial device or pty (e.g. /dev/ttyUSB0)
  --baud N            line speed (default: probe tries 115200 57600 9600 19200 38400;
                      record uses the variant's, or 115200)
  --variant hal000|hal205|pro|carryout2003|g2
                      judge hazards by this firmware's rules (default: the G2's, the strictest)
  --fd                open PATH as a plain file descriptor, not through libserialport
  --force             send even the documented hazards (never during --deep)
  --deep              also try candidate command words in each menu and report those the
                      firmware accepts although `?` does not list them (see below)
  --wordlist FILE     --deep: candidate words, one a line, `#` comments (default: the built-in
                      list, every command word docs/firmware.md names)
  --submenu NAME      --deep: probe only this menu (repeatable; `root` is the root prompt); a
                      name `?` does not list is entered anyway
  --output FILE       record: the transcript to write
  --source TEXT       record: the transcript's Source header
  --help              this text
  --version           the program's version

Deep discovery learns each menu's answer to a word that cannot exist, then sends each
candidate word alone and counts it as accepted when the answer differs (or the prompt changes:
a submenu, left again with `q`). A word goes out only after the previous one's prompt came
back. It never sends arguments (a list line with two words is refused), never sends a word the
hazard guard refuses, whatever --force says, and never sends the words docs/firmware.md says
start motion, stream until interrupted or change state (g h e r azscan azscanwxp motorboth
sw w sp agc lnbv snr nid m lnbdc t kill s). An unknown word can still do something nobody
has documented: run it with the dish free to move. If a word leaves no prompt within 3 s
the probe stops trying and says so. Progress goes to stderr, findings to the report's "deep".

Exit status: 0 a console was found (probe) or the session was recorded, 1 no console or an I/O
error, 2 usage error.
)";

// A usage error: one line on stderr, exit status 2.
int usage_error(const std::string& message)
{
    std::cerr << "birdcage-probe: " << message << " (see --help)\n";
    return 2;
}

}  // namespace

int main(int argc, char** argv)
{
    bool record = false, force = false, force_fd = false;
    DeepOptions deep;
    std::string port, output, source = "recorded with birdcage-probe record";
    std::optional<int> baud;
    birdcage::VariantId variant = birdcage::VariantId::carryout_g2;
    bool variant_given = false;
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
            if (!text) return usage_error(arg + " needs a value");
            if (arg == "--port") port = *text;
            else if (arg == "--output") output = *text;
            else if (arg == "--source") source = *text;
            else if (arg == "--wordlist") deep.wordlist_path = *text;
            else if (arg == "--submenu") deep.submenus.push_back(*text);
            else if (arg == "--baud") {
                baud = int_arg(text->c_str());
                if (!baud) return usage_error("--baud: expected a positive whole number, got '" + *text + "'");
            } else {
                const auto parsed = birdcage::variant_from_name(*text);
                if (!parsed) return usage_error("--variant: expected hal000|hal205|pro|carryout2003|g2, got '" + *text + "'");
                variant = *parsed;
                variant_given = true;
            }
        } else if (arg == "--force" || arg == "--fd" || arg == "--deep") {
            if (inline_value) return usage_error(arg + " takes no value");
            (arg == "--force" ? force : arg == "--fd" ? force_fd : deep.enabled) = true;
        } else {
            return usage_error("unknown argument '" + arg + "'");
        }
    }
    if (port.empty()) return usage_error("--port is required");
    if (record && output.empty()) return usage_error("record needs --output FILE");
    if (record && deep.enabled) return usage_error("--deep is for the probe, not record");
    if (!deep.enabled && (!deep.wordlist_path.empty() || !deep.submenus.empty()))
        return usage_error("--wordlist and --submenu need --deep");
    const auto& profile = birdcage::profile(variant);
    if (record) return run_record(port, baud.value_or(variant_given ? profile.baud : 115200), profile, force_fd, force, output, source);
    return run_probe(port, baud, profile, variant_given ? profile : birdcage::probe_profile(), force_fd, force, deep);
}
