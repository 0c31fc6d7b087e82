// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Auto-detection. What `q` may do: it is the documented way out of a submenu everywhere, and
// terminates the G2's shell at its root (docs/firmware.md 6.5). So it is sent only where a submenu was
// positively recognised: a prompt confirmed on two consecutive pokes, the `?` reply ending on that
// same prompt, not the G2 root shape `TRK>`, and a listing that names no root command of any variant.
// One deliberate exception keeps the Trav'ler Pro recognisable: a listing positively recognised as
// the HAL 0.0.00 root (which a Pro's ODU console also shows) at a confirmed prompt, with no trace of
// the G2 beyond the shared `TRK>` shape (no G2 command in the listing or its descriptions, no G2
// boot line), gets one `q` to see whether it leads to the Pro's IDU console. It is no new risk: the
// HAL 0.0.00 initialisation itself starts with the clients' `q` at the root (docs/firmware.md 2, 3.6).
// Before any `q` the console must have stayed quiet: output arriving then voids what was recognised.
#include "birdcage/console/detect.hpp"

#include <algorithm>
#include <cctype>
#include <optional>
#include <utility>

#include "birdcage/console/session.hpp"
#include "birdcage/console/synchroniser.hpp"

namespace birdcage {
namespace {

using namespace std::chrono_literals;

constexpr auto help_timeout = 3000ms;
constexpr auto resync_budget = 5000ms;     // after a `q`: the console is up, only the menu changed
constexpr int max_levels = 4;              // deepest menu nesting seen: Pro IDU > ODU > mot
constexpr int winning_score = 4;
constexpr int winning_margin = 3;
constexpr int description_divisor = 3;     // a word only in a description counts a third

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

bool is_word_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '?'; }

std::vector<std::string> words_of(std::string_view text) {
    std::vector<std::string> words;
    std::string word;
    for (char c : text) {
        if (is_word_char(c)) {
            word += c;
        } else if (!word.empty()) {
            words.push_back(std::exchange(word, {}));
        }
    }
    if (!word.empty()) {
        words.push_back(word);
    }
    return words;
}

// A line that pairs a command with a description: a dash, colon or equals sign, or columns.
bool is_described(std::string_view line) {
    return line.find(" - ") != std::string_view::npos || line.find(':') != std::string_view::npos ||
           line.find('=') != std::string_view::npos || line.find('\t') != std::string_view::npos ||
           line.find("  ") != std::string_view::npos;
}

std::string trimmed(std::string_view text) {
    const auto first = text.find_first_not_of(' ');
    if (first == std::string_view::npos) {
        return {};
    }
    const auto last = text.find_last_not_of(' ');
    return std::string(text.substr(first, last - first + 1));
}

std::string variant_name(VariantId id) { return std::string(profile(id).short_name); }

std::string summary(const std::vector<VariantScore>& ranking) {
    std::string text;
    for (const auto& entry : ranking) {
        if (entry.score == 0) {
            continue;
        }
        text += (text.empty() ? "" : "; ") + variant_name(entry.variant) + " " + std::to_string(entry.score);
        std::string reasons;
        for (const auto& reason : entry.reasons) {
            reasons += (reasons.empty() ? "" : ", ") + reason;
        }
        text += " (" + reasons + ")";
    }
    return text.empty() ? std::string("no evidence for any variant") : text;
}

std::string listing_text(const HelpListing& help) {
    std::string text;
    for (const auto& w : help.commands) {
        text += (text.empty() ? "" : " ") + w;
    }
    return text.empty() ? std::string("(nothing)") : text;
}

// A firmware whose shell dies on `q` at its root (the G2, docs/firmware.md 6.5): its clues are
// warnings against `q`, whatever else the console looks like.
bool q_at_root_kills(VariantId id) { return profile(id).has(quirk_q_at_root_kills_shell); }

// The evidence for firmware whose root `q` kills its shell.
int q_killer_score(const std::vector<VariantScore>& ranking) {
    int score = 0;
    for (const auto& entry : ranking) {
        if (q_at_root_kills(entry.variant)) {
            score += entry.score;
        }
    }
    return score;
}

bool names_a_root_command(const HelpListing& help) {
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && help.commands.count(std::string(clue.text)) > 0;
    });
}

// The root prompt of a firmware whose root `q` kills its shell (`TRK>`): other firmware may share the shape.
bool is_g2_root_shape(std::string_view prompt) {
    const auto rows = all_profiles();
    return std::any_of(rows.begin(), rows.end(), [&](const FirmwareProfile& row) {
        return row.has(quirk_q_at_root_kills_shell) && !row.root_prompt.empty() && lower(prompt) == lower(row.root_prompt);
    });
}

// A command of the G2's root listing that no other firmware lists (the G2's listing clues).
bool names_a_g2_only_command(const HelpListing& help) {
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && q_at_root_kills(clue.variant) &&
               help.commands.count(lower(clue.text)) > 0;
    });
}

// A G2-only command named anywhere in what the console printed (listings, descriptions, stray
// lines): a console that ever showed one may be a G2, whatever its latest listing says.
bool g2_command_heard(const std::vector<std::string>& lines) {
    const HelpListing heard = parse_help_listing(lines);
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && q_at_root_kills(clue.variant) &&
               heard.words.count(lower(clue.text)) > 0;
    });
}

// Any G2 clue (a boot line, a G2-only command or prompt; not the shared `TRK>` shape) anywhere in
// the raw output, even run into noise or a prompt: the exception `q` below is refused on the
// faintest sign of a G2. A false alarm only costs the Pro check (the 75 deg cap then stays).
bool g2_text_in(std::string_view raw) {
    const std::string text = lower(raw);
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return q_at_root_kills(clue.variant) && !is_g2_root_shape(clue.text) &&
               text.find(lower(clue.text)) != std::string::npos;
    });
}

// The one root where detection may send `q`: a listing that positively shows a Trav'ler (or Pro
// ODU) root, mot, os and nvs, with no G2-only command. There `q` is the upstream Trav'ler
// clients' own harmless idiom, sent first at whatever prompt (docs/firmware.md 2, 3.6); it kills
// only the G2's shell, and a G2 root always lists G2-only commands (docs/firmware.md 6.3).
bool shows_travler_root(const HelpListing& help) {
    return help.commands.count("mot") > 0 && help.commands.count("os") > 0 && help.commands.count("nvs") > 0 &&
           !names_a_g2_only_command(help);
}

}  // namespace

HelpListing parse_help_listing(const std::vector<std::string>& lines) {
    HelpListing listing;
    for (const std::string& original : lines) {
        const std::string line = lower(original);
        const auto all = words_of(line);
        listing.words.insert(all.begin(), all.end());
        if (all.empty()) {
            continue;
        }
        // `Enter <cmd> - Description` (6.3), once per line or many on one line.
        bool entered = false;
        for (std::size_t at = line.find("enter <"); at != std::string::npos; at = line.find("enter <", at + 1)) {
            const auto close = line.find('>', at);
            if (close == std::string::npos) {
                break;
            }
            const auto inside = words_of(std::string_view(line).substr(at + 7, close - at - 7));
            if (!inside.empty()) {
                listing.commands.insert(inside.front());
                entered = true;
            }
        }
        if (entered) {
            continue;
        }
        if (!is_described(line)) {
            listing.commands.insert(all.begin(), all.end());   // `mot os nvs`, `mot, os, nvs`
            continue;
        }
        // Described entries, one per line or separated by , ; | on one line: each entry's first word.
        std::size_t start = 0;
        for (std::size_t i = 0; i <= line.size(); ++i) {
            if (i == line.size() || line[i] == ',' || line[i] == ';' || line[i] == '|') {
                const auto entry = words_of(std::string_view(line).substr(start, i - start));
                if (!entry.empty()) {
                    listing.commands.insert(entry.front());
                }
                start = i + 1;
            }
        }
    }
    return listing;
}

std::vector<VariantScore> rank_evidence(const ConsoleEvidence& evidence) {
    std::vector<VariantScore> ranking;
    for (const FirmwareProfile& row : all_profiles()) {
        ranking.push_back({row.id, 0, {}});
    }
    auto entry_for = [&](VariantId id) -> VariantScore& {
        return *std::find_if(ranking.begin(), ranking.end(), [&](const VariantScore& s) { return s.variant == id; });
    };
    const std::string prompt = lower(evidence.prompt);
    for (const DetectionClue& clue : detection_clues()) {
        const std::string text = lower(clue.text);
        VariantScore& entry = entry_for(clue.variant);
        switch (clue.source) {
        case ClueSource::boot_line:
            for (const auto& line : evidence.lines) {
                if (lower(line).find(text) != std::string::npos) {
                    entry.score += clue.weight;
                    entry.reasons.push_back("boot line \"" + escape_bytes(line) + "\"");
                    break;
                }
            }
            break;
        case ClueSource::prompt:
            if (!prompt.empty() && prompt == text) {
                entry.score += clue.weight;
                entry.reasons.push_back("prompt " + evidence.prompt);
            }
            break;
        case ClueSource::help_command:
            if (evidence.help.commands.count(text) > 0) {
                entry.score += clue.weight;
                entry.reasons.push_back("? lists " + text);
            } else if (evidence.help.words.count(text) > 0 && clue.weight / description_divisor > 0) {
                entry.score += clue.weight / description_divisor;
                entry.reasons.push_back("? mentions " + text);
            }
            break;
        }
    }
    std::stable_sort(ranking.begin(), ranking.end(), [](const VariantScore& a, const VariantScore& b) { return a.score > b.score; });
    return ranking;
}

std::optional<VariantScore> clear_winner(const std::vector<VariantScore>& ranking) {
    if (ranking.empty() || ranking.front().score < winning_score) {
        return std::nullopt;
    }
    const int second = ranking.size() > 1 ? ranking[1].score : 0;
    if (ranking.front().score - second < winning_margin) {
        return std::nullopt;
    }
    return ranking.front();
}

Result<Detection> detect_variant(Transport& transport, const LogSink& log, std::chrono::milliseconds boot_timeout) {
    ConsoleSession session(transport, probe_profile(), log);
    const std::string force_hint =
        "force one with -C variant=<hal000|hal205|pro|carryout2003|g2> or use that variant's own model";

    auto synced = session.synchronise(console_sync_settings(probe_profile(), boot_timeout));
    if (!synced) {
        return {{}, Status{synced.status.code, "auto-detect: " + synced.status.message + "; " + force_hint}};
    }
    ConsoleEvidence evidence;
    evidence.lines = synced.value.heard;
    evidence.prompt = synced.value.prompt;
    std::vector<std::string> help_lines = synced.value.probe_reply;
    bool reply_on_same_prompt = true;

    auto read_help = [&]() -> Status {
        auto help = session.transact("?", help_timeout);
        if (!help && help.status.code != Errc::timeout) {
            return help.status;
        }
        help_lines = help.value.lines;
        evidence.lines.insert(evidence.lines.end(), help.value.lines.begin(), help.value.lines.end());
        // The session keeps boot lines out of a reply; they are evidence all the same.
        if (!session.last_boot_line().empty()) {
            evidence.lines.push_back(session.last_boot_line());
        }
        reply_on_same_prompt = trimmed(help.value.prompt) == evidence.prompt;
        return Status::ok();
    };
    // `q`, then the console must come into sync again before anything is concluded. `menu` tells
    // the hazard guard where the caller recognised the console to be. A G2-only command in the
    // listing, or anywhere in the output, at the G2 root shape keeps the guard's own verdict
    // (root: `q` refused), whatever the caller concluded.
    auto leave_menu = [&](const std::string& menu) -> Status {
        if (auto heard = session.listen(probe_profile().quiet_gap); !heard.value.lines.empty() || !heard.value.prompt.empty()) {
            return Status{Errc::protocol, "auto-detect: the console printed more (\"" +
                                              escape_bytes(heard.value.lines.empty() ? heard.value.prompt : heard.value.lines.back()) +
                                              "\") while its menu was being left; not sending q"};
        }
        if (!(is_g2_root_shape(evidence.prompt) && (names_a_g2_only_command(evidence.help) || g2_command_heard(evidence.lines)))) {
            session.set_menu(menu);   // recognised by the caller (see the rules at the top)
        }
        if (auto q = session.transact("q", help_timeout); !q && q.status.code != Errc::timeout) {
            return q.status;
        }
        auto again = session.synchronise(console_sync_settings(probe_profile(), resync_budget));
        if (!again) {
            return again.status;
        }
        evidence.lines.insert(evidence.lines.end(), again.value.heard.begin(), again.value.heard.end());
        evidence.prompt = again.value.prompt;
        help_lines = again.value.probe_reply;
        reply_on_same_prompt = true;
        return Status::ok();
    };

    std::vector<VariantScore> ranking;
    for (int level = 0; level < max_levels; ++level) {
        if (help_lines.empty()) {
            if (Status read = read_help(); !read) {
                return {{}, read};
            }
        }
        evidence.help = parse_help_listing(help_lines);
        ranking = rank_evidence(evidence);
        emit(log, LogLevel::verbose, "auto-detect: prompt \"" + evidence.prompt + "\", ? lists " +
                                         listing_text(evidence.help) + "; scores: " + summary(ranking));
        if (const auto winner = clear_winner(ranking)) {
            Detection d;
            d.variant = winner->variant;
            d.evidence = "auto-detected: " + summary({*winner});
            // The `TRK>` shape alone is no trace: the HAL 0.0.00 init sends `q` at its root anyway.
            const bool no_trace_of_g2 = q_killer_score(ranking) <= (is_g2_root_shape(evidence.prompt) ? 1 : 0);
            if (const auto outer = profile(winner->variant).also_shown_inside) {
                // The only `q` at a root, even one shaped like the G2's `TRK>`: allowed because the
                // listing positively shows a Trav'ler/ODU root (shows_travler_root), where `q` is
                // the upstream clients' harmless idiom (docs/firmware.md 2), and nothing else hints
                // at a G2. It tells a Pro left in its ODU console from a HAL 0.0.00.
                if (no_trace_of_g2 && shows_travler_root(evidence.help) && !g2_command_heard(evidence.lines) &&
                    !session.reboot_seen() && !g2_text_in(session.recent_output()) && !evidence.prompt.empty() &&
                    reply_on_same_prompt) {
                    if (Status left = leave_menu("travler root"); !left) {
                        return {{}, left};
                    }
                    if (Status read = read_help(); !read) {
                        return {{}, read};
                    }
                    evidence.help = parse_help_listing(help_lines);
                    const auto after = clear_winner(rank_evidence(evidence));
                    if (after && after->variant == *outer) {
                        d.variant = *outer;
                        d.evidence += "; q from there led to the IDU console (? lists odu): a " +
                                      std::string(profile(*outer).display_name);
                    } else {
                        d.maybe_inside = *outer;
                    }
                } else {
                    d.maybe_inside = *outer;
                }
                if (d.maybe_inside) {
                    const FirmwareProfile& inside = profile(*outer);
                    d.evidence += " (a " + std::string(inside.display_name) +
                                  " left inside its ODU console looks the same; elevation kept <= " +
                                  std::to_string(static_cast<int>(inside.el_max)) + ")";
                }
            }
            emit(log, LogLevel::verbose, d.evidence);
            return {d, Status::ok()};
        }
        const bool submenu = !evidence.prompt.empty() && reply_on_same_prompt && !is_g2_root_shape(evidence.prompt) &&
                             !evidence.help.commands.empty() && !names_a_root_command(evidence.help);
        if (!submenu) {
            break;
        }
        emit(log, LogLevel::verbose, "auto-detect: " + evidence.prompt + " is a submenu (its ? names no root command); leaving it with q");
        if (Status left = leave_menu("submenu"); !left) {
            return {{}, left};
        }
    }
    return {{}, Status{Errc::protocol, "auto-detect: not sure which firmware this is (prompt \"" + evidence.prompt +
                                           "\", ? lists " + listing_text(evidence.help) + "; scores: " + summary(ranking) +
                                           "); " + force_hint}};
}

}  // namespace birdcage
