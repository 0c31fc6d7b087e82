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
#include "console/detect.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "console/session.hpp"
#include "console/synchroniser.hpp"

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

// ---- The `?` listing tokeniser ----
// Command words are found as tokens wherever they stand, not by parsing a layout: a listing may
// be one command a line, one line with a label then the words, numbered, bracketed, in columns,
// with any separators, upper case, with or without descriptions, wrapped (docs/firmware.md 2, 14:
// only the G2's layout is documented). Each token gets a role from what surrounds it: a command
// (full weight in the ranking) or a mention inside descriptive text (a third).

enum class LetterCase { none, lower, upper, capitalised, mixed };

LetterCase letter_case(std::string_view word) {
    bool lower_seen = false, upper_seen = false, first_upper = false, first_letter = true, rest_upper = false;
    for (char c : word) {
        const auto u = static_cast<unsigned char>(c);
        if (!std::isalpha(u)) {
            continue;
        }
        const bool upper = std::isupper(u) != 0;
        (upper ? upper_seen : lower_seen) = true;
        if (first_letter) {
            first_upper = upper;
            first_letter = false;
        } else if (upper) {
            rest_upper = true;
        }
    }
    if (!lower_seen && !upper_seen) {
        return LetterCase::none;
    }
    if (!upper_seen) {
        return LetterCase::lower;
    }
    if (!lower_seen) {
        return LetterCase::upper;
    }
    return first_upper && !rest_upper ? LetterCase::capitalised : LetterCase::mixed;
}

// The words a shell lists that the ranking looks for, plus those every shell lists: a phrase
// made mostly of them is a run of commands, not prose.
bool is_known_command(const std::string& word) {
    static const std::set<std::string> common{"q", "?", "help", "a", "g", "reboot", "stow", "dvb", "mot", "motor",
                                              "os", "nvs", "odu", "target", "ngsearch"};
    if (common.count(word) > 0) {
        return true;
    }
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && lower(clue.text) == word;
    });
}

bool is_clue_word(const std::string& word) {
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && lower(clue.text) == word;
    });
}

struct ListingToken {
    std::string word;   // lower case
    LetterCase shape = LetterCase::none;
    bool bracketed = false;   // `<mot>`, `[mot]`, `(mot)`, `'mot'`...: a command by its looks
    bool command = false;
};

enum class Boundary { line_start, list, description };

// Tokens between two separators; `after` is the separator before them.
struct Phrase {
    Boundary after = Boundary::line_start;
    std::vector<ListingToken> tokens;
    // Words the ranking scores (`help:` may be a label; `mot:` is a command).
    int scoring() const {
        return static_cast<int>(std::count_if(tokens.begin(), tokens.end(), [](const ListingToken& t) { return is_clue_word(t.word); }));
    }
    int known() const {
        return static_cast<int>(std::count_if(tokens.begin(), tokens.end(),
                                              [](const ListingToken& t) { return is_known_command(t.word); }));
    }
};

bool is_opener(char c) { return c == '<' || c == '[' || c == '(' || c == '{' || c == '\'' || c == '"' || c == '`'; }
bool is_closer(char c) { return c == '>' || c == ']' || c == ')' || c == '}' || c == '\'' || c == '"' || c == '`'; }

std::vector<Phrase> phrases_of(std::string_view line) {
    std::vector<Phrase> phrases(1);
    auto cut = [&](Boundary boundary) {
        if (!phrases.back().tokens.empty()) {
            phrases.push_back({});
        }
        // A separator before any word of the line (a bullet, a rule) leaves it at its start.
        if (phrases.size() > 1) {
            phrases.back().after = boundary;
        }
    };
    std::size_t i = 0;
    while (i < line.size()) {
        const char c = line[i];
        if (is_word_char(c)) {
            std::size_t end = i;
            while (end < line.size() && is_word_char(line[end])) {
                ++end;
            }
            const std::string_view text = line.substr(i, end - i);
            ListingToken token{lower(text), letter_case(text)};
            token.bracketed = i > 0 && is_opener(line[i - 1]) && end < line.size() && is_closer(line[end]);
            phrases.back().tokens.push_back(std::move(token));
            i = end;
            continue;
        }
        if (c == ',' || c == ';' || c == '|' || c == '\t') {
            cut(Boundary::list);
        } else if (c == ' ' && i + 1 < line.size() && line[i + 1] == ' ') {
            cut(Boundary::list);   // columns
            while (i + 1 < line.size() && line[i + 1] == ' ') {
                ++i;
            }
        } else if (c == ':' || c == '=' ||
                   (c == '-' && (i == 0 || !is_word_char(line[i - 1]) || i + 1 == line.size() || !is_word_char(line[i + 1])))) {
            cut(Boundary::description);
        }
        ++i;
    }
    if (phrases.back().tokens.empty() && phrases.size() > 1) {
        phrases.pop_back();
    }
    return phrases;
}

std::size_t indentation(std::string_view line) {
    std::size_t n = 0;
    while (n < line.size() && (line[n] == ' ' || line[n] == '\t')) {
        ++n;
    }
    return n;
}

bool has_letters(const ListingToken& t) { return t.shape != LetterCase::none; }

// Marks the command tokens of one line. Returns whether the line ended inside a description.
bool mark_line(std::vector<Phrase>& phrases, bool continues_description) {
    if (continues_description) {
        return true;   // a wrapped description: mentions only (bracketed words excepted)
    }
    bool in_description = false;
    bool entry_has_command = false;
    bool label_list = false;
    for (std::size_t p = 0; p < phrases.size(); ++p) {
        Phrase& phrase = phrases[p];
        if (phrase.after == Boundary::description && !label_list) {
            // `Commands: mot os nvs` (a label, then the words) or `mot : Motor menu` (a command,
            // then its description): a label is words no shell lists, followed by mostly commands.
            int rest_known = 0, rest_tokens = 0;
            for (std::size_t r = p; r < phrases.size(); ++r) {
                rest_known += phrases[r].known();
                rest_tokens += static_cast<int>(phrases[r].tokens.size());
            }
            bool before_unknown = p > 0;
            for (std::size_t b = 0; b < p; ++b) {
                before_unknown = before_unknown && phrases[b].scoring() == 0 &&
                                 std::none_of(phrases[b].tokens.begin(), phrases[b].tokens.end(),
                                              [](const ListingToken& t) { return t.bracketed; });
            }
            if (before_unknown && rest_known >= 2 && 2 * rest_known >= rest_tokens) {
                label_list = true;
                for (std::size_t b = 0; b < p; ++b) {
                    for (auto& t : phrases[b].tokens) {
                        t.command = false;
                    }
                }
                in_description = false;
            } else if (entry_has_command) {
                in_description = true;
            }
        } else if (phrase.after == Boundary::list || phrase.after == Boundary::line_start) {
            in_description = false;
            entry_has_command = false;
        }
        if (in_description) {
            continue;
        }
        // An entry's head: its first word is in a command's place; the words after it too when
        // the phrase is a run of commands (`mot os nvs`), not prose (`go to target`).
        const int size = static_cast<int>(phrase.tokens.size());
        const bool prose = size >= 3 && 2 * phrase.known() < size;
        bool first = true;
        for (auto& t : phrase.tokens) {
            if (!has_letters(t) && t.word != "?") {
                continue;   // numbering
            }
            if (first) {
                t.command = !prose;
                first = false;
            } else {
                t.command = 2 * phrase.known() >= size;
            }
            entry_has_command = entry_has_command || t.command;
        }
    }
    return in_description;
}


// ---- Probes ----

// What a position query drew, by the documented reply formats (docs/firmware.md 3.3, 6.3).
ProbeAnswer position_answer(const std::vector<std::string>& lines) {
    for (const std::string& original : lines) {
        const std::string line = lower(original);
        if (line.find("angle[") != std::string::npos && line.find('=') != std::string::npos) {
            return ProbeAnswer::g2_position;
        }
        const auto az = line.find("az");
        if (az != std::string::npos && line.find('=', az) != std::string::npos && line.find("el", az) != std::string::npos) {
            return ProbeAnswer::travler_position;
        }
    }
    return ProbeAnswer::nothing;
}

std::string answer_name(ProbeAnswer answer) {
    switch (answer) {
    case ProbeAnswer::any: return "anything";
    case ProbeAnswer::nothing: return "no position";
    case ProbeAnswer::travler_position: return "a Trav'ler position (AZ = ...)";
    case ProbeAnswer::g2_position: return "a G2 position (Angle[0] = ...)";
    }
    return "?";
}

ProbeAnswer expected_answer(const DetectionProbe& probe, VariantId id) {
    for (const auto& e : probe.expected) {
        if (e.variant == id) {
            return e.answer;
        }
    }
    return ProbeAnswer::any;
}

// The variants a probe can still tell apart: some of them expect different definite answers.
bool probe_discriminates(const DetectionProbe& probe, const std::vector<VariantId>& candidates) {
    std::set<ProbeAnswer> definite;
    bool some_any = false;
    for (VariantId id : candidates) {
        const ProbeAnswer a = expected_answer(probe, id);
        if (a == ProbeAnswer::any) {
            some_any = true;
        } else {
            definite.insert(a);
        }
    }
    return definite.size() > 1 || (definite.size() == 1 && some_any);
}

std::string names_of(const std::vector<VariantId>& ids) {
    std::string text;
    for (VariantId id : ids) {
        text += (text.empty() ? "" : ", ") + variant_name(id);
    }
    return text.empty() ? std::string("none") : text;
}

std::string first_line(const std::vector<std::string>& lines) {
    return lines.empty() ? std::string("nothing") : "\"" + escape_bytes(lines.front()) + "\"";
}

}  // namespace

HelpListing parse_help_listing(const std::vector<std::string>& lines) {
    std::vector<std::vector<Phrase>> parsed;
    std::size_t baseline = std::string::npos;
    for (const std::string& line : lines) {
        if (!words_of(line).empty()) {
            baseline = std::min(baseline, indentation(line));
        }
    }
    bool previous_described = false;
    for (const std::string& line : lines) {
        // A prompt line, decorated or not (`ODU TRK>`), that reached the listing is no part of it.
        const auto last = line.find_last_not_of(" \t");
        if (last != std::string::npos && line[last] == '>' && line.find('<') == std::string::npos) {
            continue;
        }
        auto phrases = phrases_of(line);
        const bool has_words = !words_of(line).empty();
        const bool wrapped = has_words && previous_described && indentation(line) > baseline;
        const bool ends_described = mark_line(phrases, wrapped);
        if (has_words) {
            previous_described = ends_described;
        }
        parsed.push_back(std::move(phrases));
    }
    // Commands share one case (the shell takes them as typed): where most command words are lower
    // (or upper) case, a word in another case stands in a description (`mot<TAB>Motor`).
    int lower_count = 0, upper_count = 0;
    for (const auto& phrases : parsed) {
        for (const auto& phrase : phrases) {
            for (const auto& t : phrase.tokens) {
                if (t.command && is_known_command(t.word)) {
                    lower_count += t.shape == LetterCase::lower;
                    upper_count += t.shape == LetterCase::upper && t.word.size() > 1;
                }
            }
        }
    }
    const LetterCase usual = lower_count > upper_count ? LetterCase::lower
                             : upper_count > lower_count ? LetterCase::upper
                                                         : LetterCase::none;
    HelpListing listing;
    for (const auto& phrases : parsed) {
        for (const auto& phrase : phrases) {
            for (const auto& t : phrase.tokens) {
                listing.words.insert(t.word);
                const bool other_case = usual != LetterCase::none && has_letters(t) && t.shape != usual &&
                                        !(t.word.size() == 1 && usual == LetterCase::upper);
                if (t.bracketed || (t.command && !other_case)) {
                    listing.commands.insert(t.word);
                }
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


    // After a probe command: if the console now sits in a menu (a position answered, or a prompt
    // other than the root's, confirmed on two pokes), leave it with `q` as every variant does
    // (docs/firmware.md 2) -- never at the G2 root shape.
    auto back_to_root = [&](std::string_view menu, ProbeAnswer answer, const std::string& prompt_seen,
                            const std::string& root_prompt) -> Status {
        if (answer == ProbeAnswer::nothing && (prompt_seen.empty() || prompt_seen == root_prompt)) {
            return Status::ok();
        }
        auto here = session.synchronise(console_sync_settings(probe_profile(), resync_budget));
        if (!here) {
            return here.status;
        }
        evidence.lines.insert(evidence.lines.end(), here.value.heard.begin(), here.value.heard.end());
        const std::string now = here.value.prompt;
        const bool in_menu = answer != ProbeAnswer::nothing || (!now.empty() && now != root_prompt);
        if (!in_menu || is_g2_root_shape(now)) {
            evidence.prompt = now;
            return Status::ok();
        }
        evidence.prompt = now;
        emit(log, LogLevel::verbose, "auto-detect probe: leaving " + std::string(menu) + " (prompt \"" + now + "\") with q");
        return leave_menu(std::string(menu));
    };
    // One probe step: `command`, then the position query; what came back.
    struct Asked {
        ProbeAnswer answer = ProbeAnswer::nothing;
        std::vector<std::string> lines;
        std::string prompt;
    };
    auto ask = [&](std::string_view command) -> Result<Asked> {
        Asked asked;
        for (std::string_view step : {command, std::string_view("a")}) {
            if (step.empty()) {
                continue;
            }
            auto reply = session.transact(step, help_timeout);
            if (!reply && reply.status.code != Errc::timeout && reply.status.code != Errc::protocol) {
                return {asked, reply.status};
            }
            asked.lines.insert(asked.lines.end(), reply.value.lines.begin(), reply.value.lines.end());
            asked.prompt = trimmed(reply.value.prompt);
        }
        asked.answer = position_answer(asked.lines);
        return {asked, Status::ok()};
    };
    std::string probe_log;   // each probe and its answer, for the evidence and the failure message
    // Where the evidence leaves more than one variant: the probes of detection_probes(), most
    // telling first, each ruling out the variants whose documented answer differs.
    auto probe = [&](const std::vector<VariantScore>& scores) -> Result<std::optional<Detection>> {
        std::vector<VariantId> candidates;
        const int top = scores.empty() ? 0 : scores.front().score;
        for (const auto& entry : scores) {
            if (top < winning_score || entry.score > top - winning_margin) {
                candidates.push_back(entry.variant);
            }
        }
        std::map<VariantId, int> matched;   // definite expectations met, per candidate
        const std::string root_prompt = evidence.prompt;
        emit(log, LogLevel::verbose, "auto-detect: the evidence does not decide between " + names_of(candidates) +
                                         "; probing with commands that are harmless on every variant");
        for (const DetectionProbe& row : detection_probes()) {
            if (candidates.size() < 2) {
                break;
            }
            if (!probe_discriminates(row, candidates)) {
                continue;
            }
            auto asked = ask(row.enter);
            if (!asked) {
                return {std::nullopt, asked.status};
            }
            std::vector<VariantId> kept, ruled_out;
            for (VariantId id : candidates) {
                const ProbeAnswer expected = expected_answer(row, id);
                if (expected == ProbeAnswer::any || expected == asked.value.answer) {
                    kept.push_back(id);
                    matched[id] += expected == ProbeAnswer::any ? 0 : 1;
                } else {
                    ruled_out.push_back(id);
                }
            }
            const std::string entry = "\"" + std::string(row.enter) + "\" then \"a\" drew " + answer_name(asked.value.answer) +
                                      " (" + first_line(asked.value.lines) + ")";
            probe_log += (probe_log.empty() ? "" : "; ") + entry;
            emit(log, LogLevel::verbose, "auto-detect probe: " + entry + "; rules out " + names_of(ruled_out) +
                                             "; still possible: " + names_of(kept));
            candidates = std::move(kept);
            if (Status back = back_to_root(row.enter, asked.value.answer, asked.value.prompt, root_prompt); !back) {
                return {std::nullopt, back};
            }
        }
        // The candidate whose definite answers matched most, then the one with most evidence.
        auto score_of = [&](VariantId id) {
            const auto it = std::find_if(scores.begin(), scores.end(), [&](const VariantScore& e) { return e.variant == id; });
            return it == scores.end() ? 0 : it->score;
        };
        std::stable_sort(candidates.begin(), candidates.end(), [&](VariantId a, VariantId b) {
            return std::make_pair(matched[a], score_of(a)) > std::make_pair(matched[b], score_of(b));
        });
        if (candidates.empty() || (candidates.size() > 1 && matched[candidates[0]] == matched[candidates[1]] &&
                                   score_of(candidates[0]) == score_of(candidates[1]))) {
            return {std::nullopt, Status::ok()};
        }
        Detection d;
        d.variant = candidates.front();
        d.evidence = "auto-detected by probing: " + probe_log + " -> " + std::string(profile(d.variant).display_name) +
                     "; scores before probing: " + summary(scores);
        if (const auto outer = profile(d.variant).also_shown_inside) {
            d.maybe_inside = *outer;
            const FirmwareProfile& inside = profile(*outer);
            d.evidence += " (a " + std::string(inside.display_name) + " left inside its ODU console looks the same; elevation kept <= " +
                          std::to_string(static_cast<int>(inside.el_max)) + ")";
        }
        emit(log, LogLevel::verbose, d.evidence);
        return {d, Status::ok()};
    };
    bool probed = false;
    bool asked_here = false;
    std::set<std::string> left_menus;   // prompt and listing of each menu left with `q`
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
        // A `q` that led back to the same prompt and listing showed this is the root after all.
        const bool left_before = !left_menus.insert(evidence.prompt + "\n" + listing_text(evidence.help)).second;
        const bool submenu = !evidence.prompt.empty() && reply_on_same_prompt && !is_g2_root_shape(evidence.prompt) &&
                             !evidence.help.commands.empty() && !names_a_root_command(evidence.help) && !left_before;
        if (!submenu) {
            if (probed) {
                break;
            }
            // Already inside a motor menu whose listing names a root command (a title, say)? The
            // menu probes below only mean something from the root.
            if (!asked_here) {
                asked_here = true;
                auto here = ask("");
                if (!here) {
                    return {{}, here.status};
                }
                emit(log, LogLevel::verbose, "auto-detect probe: \"a\" at " +
                                                 (evidence.prompt.empty() ? std::string("the prompt-less console") : evidence.prompt) +
                                                 " drew " + answer_name(here.value.answer) + " (" + first_line(here.value.lines) + ")");
                if (here.value.answer != ProbeAnswer::nothing) {
                    if (Status back = back_to_root("motor menu", here.value.answer, here.value.prompt, evidence.prompt); !back) {
                        return {{}, back};
                    }
                    help_lines.clear();
                    continue;
                }
            }
            probed = true;
            auto found = probe(ranking);
            if (!found) {
                return {{}, Status{found.status.code, "auto-detect: while probing: " + found.status.message + "; " + force_hint}};
            }
            if (found.value) {
                return {*found.value, Status::ok()};
            }
            break;
        }
        emit(log, LogLevel::verbose, "auto-detect: " + evidence.prompt + " is a submenu (its ? names no root command); leaving it with q");
        if (Status left = leave_menu("submenu"); !left) {
            return {{}, left};
        }
    }
    return {{}, Status{Errc::protocol, "auto-detect: not sure which firmware this is (prompt \"" + evidence.prompt +
                                           "\", ? lists " + listing_text(evidence.help) + "; scores: " + summary(ranking) +
                                           ")" + (probe_log.empty() ? std::string() : "; probes: " + probe_log) + "; " + force_hint}};
}

}  // namespace birdcage
