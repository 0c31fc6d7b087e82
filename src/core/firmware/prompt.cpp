// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "firmware/prompt.hpp"

#include "firmware/words.hpp"

namespace birdcage {
namespace {

bool is_prompt_word_char(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}
bool is_decoration_after_char(char c) {
    return std::string_view("$#:%>~").find(c) != std::string_view::npos;
}
bool is_letter_or_digit(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
}

// A longer run before the word is a line of output that ends in a prompt-like word, not a tag.
constexpr std::size_t max_decoration_before = 12;
constexpr std::size_t max_prompt_word = 16;
constexpr std::size_t max_decoration_after = 2;

}  // namespace

std::size_t leading_prompt_length(std::string_view text, std::string_view* documented) {
    const std::size_t close = text.find('>');
    if (close == std::string_view::npos) {
        return 0;
    }
    std::size_t word = close;
    while (word > 0 && close - word < max_prompt_word && is_prompt_word_char(text[word - 1])) {
        --word;
    }
    const std::string_view before = text.substr(0, word);
    // Help lines such as `Enter <a3981> - ...` hold a `<` before their `>`; a tag ends apart from
    // the prompt's word, so `mot>` (an echo, a listing word) is no prompt.
    if (before.size() > max_decoration_before || before.find('<') != std::string_view::npos ||
        (!before.empty() && is_letter_or_digit(before.back()))) {
        return 0;
    }
    for (char c : before) {
        if (!is_text_byte(static_cast<unsigned char>(c))) {
            return 0;
        }
    }
    std::size_t end = close + 1;
    while (end < text.size() && end - close - 1 < max_decoration_after && is_decoration_after_char(text[end])) {
        ++end;
    }
    if (documented) {
        *documented = text.substr(word, close + 1 - word);
    }
    return end;
}

std::optional<PromptShape> prompt_shape(std::string_view text) {
    std::string_view documented;
    const std::size_t length = leading_prompt_length(text, &documented);
    if (length == 0) {
        return std::nullopt;
    }
    const std::string_view rest = text.substr(length);
    if (!rest.empty() && rest != " ") {
        return std::nullopt;
    }
    return PromptShape{documented, text.substr(0, length)};
}

bool looks_like_prompt(std::string_view text) {
    return prompt_shape(text).has_value();
}

std::string prompt_text(std::string_view text) {
    const auto shape = prompt_shape(text);
    return shape ? std::string(shape->documented) : std::string();
}

std::optional<std::string> prompt_word(std::string_view text) {
    const auto shape = prompt_shape(text);
    if (!shape) {
        return std::nullopt;
    }
    return std::string(shape->documented.substr(0, shape->documented.size() - 1));
}

}  // namespace birdcage
