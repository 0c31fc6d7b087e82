// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The few JSON shapes birdcage-probe's report needs.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "probe/help_parser.hpp"

namespace probe {

inline std::string json_string(std::string_view text) {
    std::string out = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (byte < 0x20 || byte >= 0x7f) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\u%04x", byte);
            out += hex;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

inline std::string json_strings(const std::vector<std::string>& items) {
    std::string out = "[";
    for (std::size_t i = 0; i < items.size(); ++i)
        out += (i ? ", " : "") + json_string(items[i]);
    return out + "]";
}

inline std::string json_help(const std::vector<HelpEntry>& entries, const std::string& indent) {
    std::string out = "[";
    for (std::size_t i = 0; i < entries.size(); ++i)
        out += (i ? "," : "") + std::string("\n") + indent + "  {\"name\": " + json_string(entries[i].name) +
               ", \"description\": " + json_string(entries[i].description) + "}";
    return out + (entries.empty() ? "]" : "\n" + indent + "]");
}

}  // namespace probe
