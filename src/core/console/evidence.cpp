// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/evidence.hpp"

#include <algorithm>
#include <cctype>
#include <utility>

#include "base/log.hpp"

namespace birdcage {
namespace {

constexpr int description_divisor = 3;  // a word only in a description counts a third

std::string lower(std::string_view text) {
    std::string out(text);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return out;
}

bool is_word_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '?';
}

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

// A firmware whose shell dies on `q` at its root (the G2, docs/firmware.md 6.5): its clues are
// warnings against `q`, whatever else the console looks like.
bool q_at_root_kills(VariantId id) {
    return profile(id).has(quirk_q_at_root_kills_shell);
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
    static const std::set<std::string> common{"q",   "?",     "help", "a",   "g",   "reboot", "stow",    "dvb",
                                              "mot", "motor", "os",   "nvs", "odu", "target", "ngsearch"};
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
    std::string word;  // lower case
    LetterCase shape = LetterCase::none;
    bool bracketed = false;  // `<mot>`, `[mot]`, `(mot)`, `'mot'`...: a command by its looks
    bool command = false;
};

enum class Boundary { line_start, list, description };

// Tokens between two separators; `after` is the separator before them.
struct Phrase {
    Boundary after = Boundary::line_start;
    std::vector<ListingToken> tokens;
    // Words the ranking scores (`help:` may be a label; `mot:` is a command).
    int scoring() const {
        return static_cast<int>(
            std::count_if(tokens.begin(), tokens.end(), [](const ListingToken& t) { return is_clue_word(t.word); }));
    }
    int known() const {
        return static_cast<int>(std::count_if(tokens.begin(), tokens.end(),
                                              [](const ListingToken& t) { return is_known_command(t.word); }));
    }
};

bool is_opener(char c) {
    return c == '<' || c == '[' || c == '(' || c == '{' || c == '\'' || c == '"' || c == '`';
}
bool is_closer(char c) {
    return c == '>' || c == ']' || c == ')' || c == '}' || c == '\'' || c == '"' || c == '`';
}

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
            cut(Boundary::list);  // columns
            while (i + 1 < line.size() && line[i + 1] == ' ') {
                ++i;
            }
        } else if (c == ':' || c == '=' ||
                   (c == '-' &&
                    (i == 0 || !is_word_char(line[i - 1]) || i + 1 == line.size() || !is_word_char(line[i + 1])))) {
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

bool has_letters(const ListingToken& t) {
    return t.shape != LetterCase::none;
}

// Marks the command tokens of one line. Returns whether the line ended inside a description.
bool mark_line(std::vector<Phrase>& phrases, bool continues_description) {
    if (continues_description) {
        return true;  // a wrapped description: mentions only (bracketed words excepted)
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
                continue;  // numbering
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
}  // namespace

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

bool is_g2_root_shape(std::string_view prompt) {
    const auto rows = all_profiles();
    return std::any_of(rows.begin(), rows.end(), [&](const FirmwareProfile& row) {
        return row.has(quirk_q_at_root_kills_shell) && !row.root_prompt.empty() &&
               lower(prompt) == lower(row.root_prompt);
    });
}

bool names_a_g2_only_command(const HelpListing& help) {
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && q_at_root_kills(clue.variant) &&
               help.commands.count(lower(clue.text)) > 0;
    });
}

bool g2_command_heard(const std::vector<std::string>& lines) {
    const HelpListing heard = parse_help_listing(lines);
    const auto all = detection_clues();
    return std::any_of(all.begin(), all.end(), [&](const DetectionClue& clue) {
        return clue.source == ClueSource::help_command && q_at_root_kills(clue.variant) &&
               heard.words.count(lower(clue.text)) > 0;
    });
}

// Detection refuses its one `q` at a root (detect.cpp) on the faintest sign of a G2. A false alarm
// only costs the Pro check (the 75 deg cap then stays).
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

ProbeAnswer position_answer(const std::vector<std::string>& lines) {
    for (const std::string& original : lines) {
        const std::string line = lower(original);
        if (line.find("angle[") != std::string::npos && line.find('=') != std::string::npos) {
            return ProbeAnswer::g2_position;
        }
        const auto az = line.find("az");
        if (az != std::string::npos && line.find('=', az) != std::string::npos &&
            line.find("el", az) != std::string::npos) {
            return ProbeAnswer::travler_position;
        }
    }
    return ProbeAnswer::nothing;
}

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
    const LetterCase usual = lower_count > upper_count   ? LetterCase::lower
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
    std::stable_sort(ranking.begin(), ranking.end(),
                     [](const VariantScore& a, const VariantScore& b) { return a.score > b.score; });
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

}  // namespace birdcage
