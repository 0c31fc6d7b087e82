// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "base/log.hpp"

#include <array>

namespace birdcage {

const char* to_string(LogLevel level) {
    switch (level) {
        case LogLevel::error:
            return "error";
        case LogLevel::warning:
            return "warning";
        case LogLevel::verbose:
            return "verbose";
        case LogLevel::trace:
            return "trace";
    }
    return "?";
}

std::string escape_bytes(std::string_view bytes) {
    static constexpr std::array<char, 16> hex = {'0', '1', '2', '3', '4', '5', '6', '7',
                                                 '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};
    std::string out;
    out.reserve(bytes.size());
    for (char c : bytes) {
        const auto byte = static_cast<unsigned char>(c);
        switch (c) {
            case '\r':
                out += "\\r";
                break;
            case '\n':
                out += "\\n";
                break;
            case '\t':
                out += "\\t";
                break;
            case '\\':
                out += "\\\\";
                break;
            default:
                if (byte >= 0x20 && byte < 0x7f) {
                    out += c;
                } else {
                    out += "\\x";
                    out += hex[byte >> 4];
                    out += hex[byte & 0x0f];
                }
        }
    }
    return out;
}

void emit(const LogSink& sink, LogLevel level, const std::string& message) {
    if (sink) {
        sink(level, message);
    }
}

}  // namespace birdcage
