// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "probe/help_parser.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include "console/detect.hpp"

namespace probe {
namespace {

bool is_command_word(std::string_view word) {
    static constexpr std::array<std::string_view, 5> placeholders{"command", "value", "index", "cmd", "n"};
    return !word.empty() && std::find(placeholders.begin(), placeholders.end(), word) == placeholders.end() &&
           std::all_of(word.begin(), word.end(),
                       [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '?'; });
}

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool is_word_char(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '?';
}

}  // namespace

namespace {

struct Row {
    HelpEntry entry;
    bool spaces_only = false;  // word and description apart by blanks alone (a row, or a line of columns)
};

bool is_blank(char c) {
    return c == ' ' || c == '\t';
}

void skip_blanks(std::string_view& text) {
    while (!text.empty() && is_blank(text.front()))
        text.remove_prefix(1);
}

// Bullets and numbers before the word, in any combination: `- `, `* `, `1. `, `1) `, `1: `,
// `[1] `, `(1) `, `#1 `.
void skip_bullet(std::string_view& text) {
    for (int pass = 0; pass < 3; ++pass) {
        if (text.size() >= 2 && (text[0] == '-' || text[0] == '*' || text[0] == '+') && is_blank(text[1])) {
            text.remove_prefix(2);
            skip_blanks(text);
            continue;
        }
        std::size_t i = (text.size() > 1 && (text[0] == '[' || text[0] == '(' || text[0] == '#')) ? 1 : 0;
        const std::size_t digits = i;
        while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) != 0)
            ++i;
        if (i == digits)
            return;
        if (i < text.size() && (text[i] == '.' || text[i] == ')' || text[i] == ']' || text[i] == ':'))
            ++i;
        if (i < text.size() && !is_blank(text[i]))
            return;
        text.remove_prefix(i);
        skip_blanks(text);
    }
}

std::optional<Row> parse_row(std::string_view line, bool loose = false) {
    while (!line.empty() && (line.back() == '\r' || line.back() == '\n' || is_blank(line.back())))
        line.remove_suffix(1);
    skip_blanks(line);
    if (line.empty())
        return std::nullopt;
    Row row;
    if (line.rfind("Enter <", 0) == 0) {
        const std::size_t close = line.find('>');
        if (close == std::string_view::npos)
            return std::nullopt;
        row.entry.name = std::string(line.substr(7, close - 7));
        const std::size_t dash = line.find(" - ", close);
        if (dash != std::string_view::npos)
            row.entry.description = std::string(line.substr(dash + 3));
        if (!is_command_word(row.entry.name))
            return std::nullopt;
        return row;
    }
    skip_bullet(line);
    if (line.size() > 6 &&
        (line.rfind("Enter ", 0) == 0 || line.rfind("ENTER ", 0) == 0 || line.rfind("enter ", 0) == 0)) {
        line.remove_prefix(6);  // `Enter MOT -- ...`: the word comes after
        skip_blanks(line);
    }
    // The word, maybe in brackets: `mot`, `(mot)`, `<mot>`, `[mot]`.
    const char open = line.empty() ? '\0' : line.front();
    const char close = open == '(' ? ')' : open == '<' ? '>' : open == '[' ? ']' : '\0';
    if (close != '\0')
        line.remove_prefix(1);
    std::size_t end = 0;
    while (end < line.size() && is_word_char(line[end]))
        ++end;
    row.entry.name = std::string(line.substr(0, end));
    line.remove_prefix(end);
    if (close != '\0') {
        if (line.empty() || line.front() != close)
            return std::nullopt;
        line.remove_prefix(1);
    }
    if (!is_command_word(row.entry.name))
        return std::nullopt;
    // The separator: a symbol (`-`, `--`, `:`, `=`, `...`) with blanks around it, or two or more
    // blanks, or a tab. One blank before a word is prose (`Available commands:`).
    std::size_t blanks = 0;
    while (blanks < line.size() && is_blank(line[blanks]))
        ++blanks;
    std::size_t symbols = blanks;
    while (symbols < line.size() &&
           (line[symbols] == '-' || line[symbols] == ':' || line[symbols] == '=' || line[symbols] == '.'))
        ++symbols;
    const bool symbol = symbols > blanks;
    if (line.empty())
        return std::nullopt;  // a lone word is no row (a layout the detector reads)
    if (symbol) {
        if (symbols < line.size() && !is_blank(line[symbols]))
            return std::nullopt;  // `a-b`, `1.5`
    } else if (blanks < 2 && !(blanks == 1 && line[0] == '\t')) {
        // One blank: prose, unless the whole listing is laid out so (`mot Motor`, see parse_help).
        const bool text_follows = blanks == 1 && std::isalnum(static_cast<unsigned char>(line[1])) != 0;
        if (!loose || !text_follows || std::isalpha(static_cast<unsigned char>(row.entry.name[0])) == 0)
            return std::nullopt;
    }
    row.spaces_only = !symbol;
    line.remove_prefix(symbols);
    skip_blanks(line);
    if (line.empty())
        return std::nullopt;  // a title such as `COMMANDS ---`
    row.entry.description = std::string(line);
    return row;
}

}  // namespace

std::optional<HelpEntry> parse_help_line(std::string_view line) {
    auto row = parse_row(line);
    if (!row)
        return std::nullopt;
    return std::move(row->entry);
}

std::vector<HelpEntry> parse_help(const std::vector<std::string>& lines) {
    std::vector<HelpEntry> entries;
    auto known = [&](std::string_view word) {
        return std::any_of(entries.begin(), entries.end(),
                           [&](const HelpEntry& e) { return lower(e.name) == lower(word); });
    };
    bool columns = false;
    for (const auto& line : lines) {
        auto row = parse_row(line);
        if (!row)
            continue;
        // A line of columns: blanks apart, and what would be the description is more words
        // padded apart, or a single word.
        const std::string& rest = row->entry.description;
        if ((row->spaces_only && rest.find(' ') == std::string::npos) || rest.find("  ") != std::string::npos)
            columns = true;
        if (!known(row->entry.name))
            entries.push_back(std::move(row->entry));
    }
    // A listing of rows (the real G2's, the old `Enter <cmd> - ...`) is read from its rows alone:
    // their descriptions hold words (`Motor Life Test`, `[motor] [pos]`) that are no commands.
    // Other layouts (all words on one line, columns, numbered or bracketed words) are read by the
    // backend detector's layout-agnostic reader, which gives lower-case words in no order: they
    // are kept in the order the listing shows them.
    if (entries.size() >= 2 && !columns)
        return entries;
    // Rows with one blank between word and description (`mot Motor`) when nothing else is rows.
    if (entries.empty()) {
        std::vector<HelpEntry> loose;
        for (const auto& line : lines)
            if (auto row = parse_row(line, true); row && !row->spaces_only)
                continue;  // a symbol: not this layout
            else if (row)
                loose.push_back(std::move(row->entry));
        const auto text_lines = std::count_if(lines.begin(), lines.end(), [](const std::string& l) {
            return l.find_first_not_of(" \t\r\n") != std::string::npos;
        });
        if (loose.size() >= 3 && loose.size() * 5 >= static_cast<std::size_t>(text_lines) * 3) {
            for (auto& entry : loose)
                if (!known(entry.name))
                    entries.push_back(std::move(entry));
            return entries;
        }
    }
    const auto commands = birdcage::parse_help_listing(lines).commands;
    std::vector<std::string> in_order;
    for (const auto& line : lines) {
        const std::string text = lower(line);
        std::size_t i = 0;
        while (i < text.size()) {
            while (i < text.size() && !is_word_char(text[i]))
                ++i;
            const std::size_t start = i;
            while (i < text.size() && is_word_char(text[i]))
                ++i;
            const std::string word = text.substr(start, i - start);
            if (!word.empty() && commands.count(word) != 0 &&
                std::find(in_order.begin(), in_order.end(), word) == in_order.end())
                in_order.push_back(word);
        }
    }
    for (const std::string& word : commands)
        if (std::find(in_order.begin(), in_order.end(), word) == in_order.end())
            in_order.push_back(word);
    for (const std::string& word : in_order)  // `help [<command>]` is the listing's own usage line
        if (!known(word) && is_command_word(word) && word != "help")
            entries.push_back({word, {}});
    return entries;
}

}  // namespace probe
