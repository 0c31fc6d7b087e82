// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/raw_output.hpp"

#include "base/log.hpp"
#include "console/framer.hpp"

namespace birdcage {

bool is_text_line(std::size_t text_bytes, std::size_t noise_bytes) {
    return text_bytes > 0 && noise_bytes * 4 <= text_bytes;
}

std::size_t prompt_before_noise(std::string_view line) {
    const std::size_t length = leading_prompt_length(line);
    if (length == 0) {
        return 0;
    }
    std::size_t text = 0;
    std::size_t noise = 0;
    for (char c : line.substr(length)) {
        ++(is_text_byte(static_cast<unsigned char>(c)) ? text : noise);
    }
    return noise > 0 && !is_text_line(text, noise) ? length : 0;
}

std::vector<std::string> printable_lines(std::string_view raw) {
    std::vector<std::string> lines;
    std::string line;
    std::size_t noise = 0;
    auto finish = [&] {
        if (line.find_first_not_of(" \t") != std::string::npos && is_text_line(line.size(), noise)) {
            lines.push_back(line);
        }
        line.clear();
        noise = 0;
    };
    for (char c : raw) {
        if (is_line_end(c)) {
            finish();
        } else if (is_text_byte(static_cast<unsigned char>(c))) {
            line += c;
        } else {
            ++noise;
        }
    }
    finish();
    return lines;
}

std::string trailing_prompt(std::string_view output) {
    // Line endings and noise after the prompt (an idle RS-485 bus keeps producing bytes) do not
    // hide it; noise inside its line does.
    std::size_t end = output.size();
    while (end > 0 && (is_line_end(output[end - 1]) || !is_text_byte(static_cast<unsigned char>(output[end - 1])))) {
        --end;
    }
    std::size_t begin = end;
    while (begin > 0 && !is_line_end(output[begin - 1])) {
        --begin;
    }
    const std::string_view line = output.substr(begin, end - begin);
    // prompt_text() also rejects any noise byte: a prompt is printable text only.
    return prompt_text(line);
}

std::string quoted_tail(std::string_view output, std::size_t count) {
    std::vector<std::string_view> lines;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= output.size(); ++i) {
        if (i == output.size() || is_line_end(output[i])) {
            if (i > start) {
                lines.push_back(output.substr(start, i - start));
            }
            start = i + 1;
        }
    }
    const std::size_t first = lines.size() > count ? lines.size() - count : 0;
    std::string text;
    for (std::size_t i = first; i < lines.size(); ++i) {
        text += (text.empty() ? "\"" : ", \"") + escape_bytes(lines[i]) + "\"";
    }
    return text;
}

bool looks_like_wrong_baud(std::string_view raw) {
    std::size_t noise = 0;
    std::size_t line_ends = 0;
    for (char c : raw) {
        if (is_line_end(c)) {
            ++line_ends;
        } else if (!is_text_byte(static_cast<unsigned char>(c))) {
            ++noise;
        }
    }
    if (raw.size() < 8) {
        return false;
    }
    // At the wrong rate most frames decode to bytes outside ASCII; the few that decode as text
    // never form lines ending in a prompt.
    if (noise * 10 >= raw.size() * 3) {
        return true;
    }
    return raw.size() >= 48 && line_ends == 0 && trailing_prompt(raw).empty();
}

}  // namespace birdcage
