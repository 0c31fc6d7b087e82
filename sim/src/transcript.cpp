// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage_sim/transcript.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace birdcage::sim {
namespace {

[[noreturn]] void fail(std::size_t line_number, const std::string& what) {
    throw TranscriptError("line " + std::to_string(line_number) + ": " + what);
}

int hex_value(char c) {
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t'))
        text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
        text.remove_suffix(1);
    return text;
}

constexpr double max_delay_ms = 24.0 * 3600.0 * 1000.0;

// `@+120ms`, `@+0.5ms`, `@+2s`; returns milliseconds.
std::optional<double> parse_delay(std::string_view token) {
    if (token.substr(0, 2) != "@+")
        return std::nullopt;
    token.remove_prefix(2);
    double scale = 0.0;
    if (token.size() > 2 && token.substr(token.size() - 2) == "ms") {
        scale = 1.0;
        token.remove_suffix(2);
    } else if (token.size() > 1 && token.back() == 's') {
        scale = 1000.0;
        token.remove_suffix(1);
    } else {
        return std::nullopt;
    }
    const std::string number(token);
    char* end = nullptr;
    const double value = std::strtod(number.c_str(), &end);
    if (number.empty() || end != number.c_str() + number.size() || !std::isfinite(value) || value < 0.0)
        return std::nullopt;
    // No console pauses for a day between two chunks; a larger number is a typo, and it would not
    // print back as the same number.
    if (value * scale > max_delay_ms)
        return std::nullopt;
    return value * scale;
}

std::string format_delay(double ms) {
    char text[48];
    if (ms == std::floor(ms))
        std::snprintf(text, sizeof text, "@+%.0fms", ms);
    else
        std::snprintf(text, sizeof text, "@+%.1fms", ms);
    return text;
}

}  // namespace

std::optional<std::string> Transcript::header(std::string_view key) const {
    for (const auto& [name, value] : headers)
        if (name == key)
            return value;
    return std::nullopt;
}

std::string escape_chunk(std::string_view bytes) {
    std::string text;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const char c = bytes[i];
        const auto byte = static_cast<unsigned char>(c);
        const bool edge_space = c == ' ' && (i == 0 || i + 1 == bytes.size());
        if (c == '\r')
            text += "\\r";
        else if (c == '\n')
            text += "\\n";
        else if (c == '\t')
            text += "\\t";
        else if (c == '\\')
            text += "\\\\";
        else if (byte < 0x20 || byte >= 0x7f || edge_space) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", byte);
            text += hex;
        } else
            text += c;
    }
    return text;
}

std::string unescape_chunk(std::string_view text) {
    std::string bytes;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\') {
            bytes += text[i];
            continue;
        }
        if (++i == text.size())
            throw TranscriptError("escape at end of chunk");
        switch (text[i]) {
            case 'r':
                bytes += '\r';
                break;
            case 'n':
                bytes += '\n';
                break;
            case 't':
                bytes += '\t';
                break;
            case '0':
                bytes += '\0';
                break;
            case 'e':
                bytes += '\x1b';
                break;
            case '\\':
                bytes += '\\';
                break;
            case 'x': {
                const int high = i + 1 < text.size() ? hex_value(text[i + 1]) : -1;
                const int low = i + 2 < text.size() ? hex_value(text[i + 2]) : -1;
                if (high < 0 || low < 0)
                    throw TranscriptError("\\x needs two hex digits");
                bytes += static_cast<char>(high * 16 + low);
                i += 2;
                break;
            }
            default:
                throw TranscriptError(std::string("unknown escape \\") + text[i]);
        }
    }
    return bytes;
}

std::string format_entry(const TranscriptEntry& entry) {
    std::string line(1, entry.direction == Direction::host_to_dish ? '>' : '<');
    if (entry.reconstructed)
        line += '~';
    line += ' ';
    if (entry.delay_ms > 0.0)
        line += format_delay(entry.delay_ms) + ' ';
    std::string bytes = escape_chunk(entry.bytes);
    // Chunk bytes that begin like a timing token would be read back as one.
    if (bytes.rfind("@+", 0) == 0)
        bytes.replace(0, 1, "\\x40");
    line += bytes;
    return line;
}

Transcript parse_transcript(std::string_view text) {
    Transcript transcript;
    std::size_t line_number = 0;
    while (!text.empty()) {
        const std::size_t end = text.find('\n');
        std::string_view line = text.substr(0, end);
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
        ++line_number;
        line = trim(line);
        if (line.empty())
            continue;
        if (line.front() == '#') {
            // Headers come before the first chunk; later `#` lines are annotations.
            if (!transcript.entries.empty())
                continue;
            const std::string_view body = trim(line.substr(1));
            const std::size_t colon = body.find(':');
            if (colon == std::string_view::npos || colon == 0 ||
                body.substr(0, colon).find(' ') != std::string_view::npos)
                continue;
            transcript.headers.emplace_back(std::string(body.substr(0, colon)),
                                            std::string(trim(body.substr(colon + 1))));
            continue;
        }
        TranscriptEntry entry;
        entry.line_number = line_number;
        if (line.front() == '>')
            entry.direction = Direction::host_to_dish;
        else if (line.front() == '<')
            entry.direction = Direction::dish_to_host;
        else
            fail(line_number, "expected `>`, `<` or `#`, got \"" + std::string(line.substr(0, 20)) + "\"");
        line.remove_prefix(1);
        if (!line.empty() && line.front() == '~') {
            entry.reconstructed = true;
            line.remove_prefix(1);
        }
        if (line.empty() || line.front() != ' ')
            fail(line_number, "a space must follow the direction");
        line = trim(line);
        if (line.substr(0, 2) == "@+") {
            const std::size_t space = line.find(' ');
            const auto delay = parse_delay(line.substr(0, space));
            if (!delay)
                fail(line_number, "bad timing \"" + std::string(line.substr(0, space)) + "\" (want @+<n>ms or @+<n>s)");
            entry.delay_ms = *delay;
            line.remove_prefix(space == std::string_view::npos ? line.size() : space + 1);
        }
        try {
            entry.bytes = unescape_chunk(line);
        } catch (const TranscriptError& error) {
            fail(line_number, error.what());
        }
        if (entry.bytes.empty())
            fail(line_number, "empty chunk");
        transcript.entries.push_back(std::move(entry));
    }
    return transcript;
}

Transcript load_transcript(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file)
        throw TranscriptError("cannot open transcript " + path);
    std::ostringstream contents;
    contents << file.rdbuf();
    try {
        return parse_transcript(contents.str());
    } catch (const TranscriptError& error) {
        throw TranscriptError(path + ": " + error.what());
    }
}

TranscriptRecorder::TranscriptRecorder(std::vector<std::pair<std::string, std::string>> headers) {
    for (const auto& [key, value] : headers)
        text_ += "# " + key + ": " + value + "\n";
}

void TranscriptRecorder::add(Direction direction, std::string_view bytes, double seconds, bool reconstructed) {
    if (bytes.empty())
        return;
    TranscriptEntry entry{direction, std::string(bytes)};
    entry.reconstructed = reconstructed;
    if (last_seconds_)
        entry.delay_ms = std::round((seconds - *last_seconds_) * 10000.0) / 10.0;
    last_seconds_ = seconds;
    text_ += format_entry(entry) + "\n";
}

void TranscriptRecorder::comment(std::string_view text) {
    text_ += "# ";
    text_ += text;
    text_ += '\n';
}

}  // namespace birdcage::sim
