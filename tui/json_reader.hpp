// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Reads the JSON birdcage-track prints (docs/sky.md): objects, arrays, strings, numbers, true,
// false, null. Enough for one program's machine interface, not a general library.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace birdcage::tui {

struct Json {
    enum class Type { null, boolean, number, string, array, object } type = Type::null;
    bool boolean = false;
    double number = 0;
    std::string text;
    std::vector<Json> items;
    std::vector<std::pair<std::string, Json>> members;

    // The member named `key` of an object; nullptr when absent (or this is no object).
    const Json* find(std::string_view key) const;
    // A member's value; nullopt (or `fallback`) when it is absent or of another type.
    std::optional<double> number_at(std::string_view key) const;
    std::string text_at(std::string_view key, std::string fallback = {}) const;
    bool is_null() const { return type == Type::null; }
};

// nullopt (and where it stopped, in `why`) for text that is not one JSON value.
std::optional<Json> parse_json(std::string_view text, std::string* why = nullptr);

}  // namespace birdcage::tui
