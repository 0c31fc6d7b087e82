// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "probe/deep.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <iostream>
#include <sstream>

#include "firmware/hazards.hpp"
#include "firmware/menus.hpp"
#include "probe/json.hpp"

namespace probe {
namespace {

constexpr std::array<const char*, 2> unknown_probes{"xyzzyq", "zqvxjw"};  // no firmware documents either

std::string lower(std::string text) {
    for (char& c : text)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return text;
}

// Reply lines with every whole-word occurrence of `word` replaced by <word>, so that an error text
// which repeats the word (`Unknown command: xyzzyq`) compares equal for every word.
std::vector<std::string> normalised_reply(const Reply& reply, const std::string& word) {
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

}  // namespace

WordList parse_wordlist(const std::string& text) {
    WordList list;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line)) {
        if (const std::size_t hash = line.find('#'); hash != std::string::npos)
            line.resize(hash);
        std::istringstream fields(line);
        std::string word, extra;
        if (!(fields >> word))
            continue;
        if (fields >> extra) {
            list.rejected.emplace_back(line, "more than one word: deep discovery never sends arguments");
            continue;
        }
        if (std::find(list.words.begin(), list.words.end(), word) == list.words.end())
            list.words.push_back(word);
    }
    return list;
}

std::string never_bare_reason(const std::string& word) {
    if (word == "q" || word == "?" || word == "help")
        return "the probe's own navigation word";
    // Unknown variant, unknown menu: the word is judged by every menu's and variant's rules, so a
    // word that engages the motors in MOT> is not tried in DVB> either.
    const auto ruling = birdcage::classify_command(std::nullopt, "", word);
    if (ruling.hazard())
        return std::string(birdcage::hazard_kind_name(ruling.kind)) + ": " + std::string(ruling.reason) +
               " (the hazard rule, docs/firmware.md 15)";
    return {};
}

DeepDiscovery::DeepDiscovery(Probe& probe, const WordList& words, std::string root_prompt)
    : probe_(probe), words_(words), root_prompt_(std::move(root_prompt)) {}

bool DeepDiscovery::run_menu(DeepMenu& menu, const std::string& enter, const std::vector<HelpEntry>& listed) {
    if (!enter.empty()) {
        if (birdcage::menu_entered_by(enter) == nullptr) {
            menu.note = "not entered: the firmware facts name no menu `" + enter + "`";
            report.menus.push_back(menu);
            return true;
        }
        const std::size_t refusals = probe_.refused.size();
        const auto reply = probe_.send(enter);
        if (!reply) {
            const bool refused = probe_.refused.size() > refusals;
            menu.note = "not entered: " + (refused ? probe_.refused.back().second : std::string("write failed"));
            report.menus.push_back(menu);
            return refused;
        }
        if (!reply->prompt)
            return stop("no prompt after entering " + enter);
        if (*reply->prompt == root_prompt_) {
            menu.note = "not a submenu: " + enter + " left the console at " + root_prompt_;
            report.menus.push_back(menu);
            return true;
        }
        probe_.menu_of_prompt.emplace(*reply->prompt, enter);
    }
    menu.prompt = probe_.prompt;
    if (!learn_unknown_reply(menu))
        return leave(menu, enter);
    progress(menu, "probing");
    for (const auto& word : words_.words) {
        const bool known = std::any_of(listed.begin(), listed.end(), [&](const HelpEntry& entry) {
            return entry.name == word || lower(entry.name) == word;
        });
        if (known)
            continue;
        if (const std::string why = never_bare_reason(word); !why.empty()) {
            note_not_tried(word, why);
            continue;
        }
        // From the root only documented menus are entered: any other word that changed the
        // prompt would leave the probe somewhere it cannot name.
        const std::size_t refusals = probe_.refused.size();
        const auto reply = probe_.send(word);
        if (!reply) {
            if (probe_.refused.size() > refusals)
                continue;  // the hazard rule said no
            return stop("write failed");
        }
        ++menu.tried;
        if (!reply->prompt)
            return stop("no prompt within the reply timeout after `" + word + "` at " + menu.prompt);
        DeepFinding finding{word, reply_lines(*reply, word), {}};
        if (*reply->prompt != menu.prompt) {
            finding.prompt = *reply->prompt;
            const bool documented = birdcage::menu_entered_by(word) != nullptr && enter.empty();
            if (documented)
                probe_.menu_of_prompt.emplace(finding.prompt, word);
            menu.accepted.push_back(finding);
            progress(menu, "`" + word + "` leads to " + finding.prompt);
            if (!return_to(menu, enter))
                return stop("could not return to " + menu.prompt + " after `" + word + "`");
            continue;
        }
        const auto answer = normalised_reply(*reply, word);
        if (answer == menu.unknown_reply)
            continue;
        // Positively accepted only if the console answers the same again: a line that arrived by
        // itself (boot output, a status line) is not the word's answer.
        const auto again = probe_.send(word);
        if (!again || !again->prompt || *again->prompt != menu.prompt)
            return stop("lost the prompt repeating `" + word + "`");
        if (normalised_reply(*again, word) != answer) {
            progress(menu, "`" + word + "` answered differently when repeated: not reported");
            continue;
        }
        menu.accepted.push_back(finding);
        progress(menu, "accepts `" + word + "`");
    }
    progress(menu, std::to_string(menu.tried) + " tried, " + std::to_string(menu.accepted.size()) + " accepted");
    return leave(menu, enter);
}

void DeepDiscovery::progress(const DeepMenu& menu, const std::string& what) const {
    std::cerr << "birdcage-probe: deep: " << menu.prompt << ' ' << what << '\n';
}

void DeepDiscovery::note_not_tried(const std::string& word, const std::string& why) {
    const bool seen = std::any_of(report.not_tried.begin(), report.not_tried.end(),
                                  [&](const auto& entry) { return entry.first == word; });
    if (!seen)
        report.not_tried.emplace_back(word, why);
}

bool DeepDiscovery::stop(const std::string& why) {
    report.stopped = why;
    std::cerr << "birdcage-probe: deep: stopped: " << why << '\n';
    return false;
}

// The menu's answer to a word that cannot exist, asked twice with different words: a menu that
// answers them differently (the G2's NVS> reads the next index) cannot be probed.
bool DeepDiscovery::learn_unknown_reply(DeepMenu& menu) {
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

// Back to the menu's prompt after a word that changed it: `q` only where the console's menu is
// known (the hazard rule refuses it elsewhere).
bool DeepDiscovery::return_to(const DeepMenu& menu, const std::string& enter) {
    if (probe_.prompt != root_prompt_)
        probe_.send("q");
    if (probe_.prompt == menu.prompt)
        return true;
    if (enter.empty() || probe_.prompt != root_prompt_)
        return false;
    probe_.send(enter);
    return probe_.prompt == menu.prompt;
}

bool DeepDiscovery::leave(DeepMenu& menu, const std::string& enter) {
    report.menus.push_back(menu);
    if (enter.empty())
        return true;
    probe_.send("q");
    if (probe_.prompt == root_prompt_)
        return true;
    return stop("`q` at " + menu.prompt + " did not return to " + root_prompt_);
}

std::string json_deep(const DeepReport& deep) {
    std::string out = "{\n    \"wordlist\": " + json_string(deep.wordlist) + ",\n    \"menus\": [";
    for (std::size_t i = 0; i < deep.menus.size(); ++i) {
        const DeepMenu& menu = deep.menus[i];
        out += std::string(i ? "," : "") + "\n      {\"menu\": " + json_string(menu.name) +
               ", \"prompt\": " + json_string(menu.prompt) +
               ", \"unknown_reply\": " + json_strings(menu.unknown_reply) +
               ", \"tried\": " + std::to_string(menu.tried) + ", \"note\": " + json_string(menu.note) +
               ", \"accepted\": [";
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
    out += std::string(deep.not_tried.empty() ? "" : "\n    ") +
           "],\n    \"stopped\": " + (deep.stopped.empty() ? std::string("null") : json_string(deep.stopped)) + "\n  }";
    return out;
}

}  // namespace probe
