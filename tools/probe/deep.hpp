// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-probe --deep: candidate words tried bare in each menu, a word reported only when the
// console positively accepted it (twice the same answer, unlike its answer to a word that cannot
// exist), never a word the hazard rule names in any menu of any variant.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "probe/console_io.hpp"
#include "probe/help_parser.hpp"

namespace probe {

// A word list: one word a line, `#` comments. A line with more than one word is kept out: deep
// discovery never sends arguments.
struct WordList {
    std::vector<std::string> words;
    std::vector<std::pair<std::string, std::string>> rejected;
};
WordList parse_wordlist(const std::string& text);

// Why deep discovery never sends `word` bare, in any menu; empty when it may.
std::string never_bare_reason(const std::string& word);

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

class DeepDiscovery {
public:
    DeepDiscovery(Probe& probe, const WordList& words, std::string root_prompt);
    // One menu, entered from the root with `enter` (empty for the root itself); false when the
    // console was lost and nothing more may be sent.
    bool run_menu(DeepMenu& menu, const std::string& enter, const std::vector<HelpEntry>& listed);

    DeepReport report;

private:
    void progress(const DeepMenu& menu, const std::string& what) const;
    void note_not_tried(const std::string& word, const std::string& why);
    bool stop(const std::string& why);
    bool learn_unknown_reply(DeepMenu& menu);
    bool return_to(const DeepMenu& menu, const std::string& enter);
    bool leave(DeepMenu& menu, const std::string& enter);

    Probe& probe_;
    const WordList& words_;
    std::string root_prompt_;
};

std::string json_deep(const DeepReport& deep);

}  // namespace probe
