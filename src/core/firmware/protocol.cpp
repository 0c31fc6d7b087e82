// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "firmware/protocol.hpp"

#include "firmware/words.hpp"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

namespace birdcage {
namespace {

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}
bool is_digit(char c) {
    return c >= '0' && c <= '9';
}
bool is_alnum(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0;
}

std::string join_lines(Span<const std::string> lines) {
    std::string text;
    for (const auto& line : lines) {
        text += line;
        text += '\n';
    }
    return text;
}

// A decimal number `[+-]?digits[.digits]` starting at `pos` (after optional blanks). No exponent,
// no inf/nan: the console never prints them, so they can only be line noise.
std::optional<double> number_at(std::string_view text, std::size_t pos, std::size_t* end = nullptr) {
    while (pos < text.size() && is_space(text[pos])) {
        ++pos;
    }
    std::size_t i = pos;
    bool negative = false;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
        negative = text[i] == '-';
        ++i;
    }
    const std::size_t digits_start = i;
    while (i < text.size() && is_digit(text[i])) {
        ++i;
    }
    if (i == digits_start) {
        return std::nullopt;
    }
    if (i + 1 < text.size() && text[i] == '.' && is_digit(text[i + 1])) {
        ++i;
        while (i < text.size() && is_digit(text[i])) {
            ++i;
        }
    }
    if (i < text.size() && (is_alnum(text[i]) || text[i] == '.')) {
        return std::nullopt;  // "1e5", "1.2.3", "12abc": not a console number
    }
    double value = 0;
    const auto [ptr, ec] =
        std::from_chars(text.data() + digits_start, text.data() + i, value, std::chars_format::fixed);
    if (ec != std::errc{} || ptr != text.data() + i) {
        return std::nullopt;
    }
    if (end != nullptr) {
        *end = i;
    }
    return negative ? -value : value;
}

// The number after `<key> <blanks> = <blanks>`, for the first occurrence of `key` that starts a word.
std::optional<double> field_value(std::string_view text, std::string_view key) {
    for (std::size_t at = text.find(key); at != std::string_view::npos; at = text.find(key, at + 1)) {
        if (at > 0 && is_alnum(text[at - 1])) {
            continue;
        }
        std::size_t i = at + key.size();
        while (i < text.size() && is_space(text[i])) {
            ++i;
        }
        if (i >= text.size() || text[i] != '=') {
            continue;
        }
        if (auto value = number_at(text, i + 1)) {
            return value;
        }
    }
    return std::nullopt;
}

std::optional<int> integer_word(std::string_view word) {
    int value = 0;
    const auto [ptr, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
    if (ec != std::errc{} || ptr != word.data() + word.size()) {
        return std::nullopt;
    }
    return value;
}

// The number right after `key` (no '=' involved), e.g. "Reads:10" or "avg: 412".
std::optional<int> integer_after(std::string_view text, std::string_view key) {
    const std::size_t at = text.find(key);
    if (at == std::string_view::npos) {
        return std::nullopt;
    }
    std::size_t i = at + key.size();
    while (i < text.size() && text[i] == ' ') {
        ++i;
    }
    const std::size_t start = i;
    if (i < text.size() && text[i] == '-') {
        ++i;
    }
    while (i < text.size() && is_digit(text[i])) {
        ++i;
    }
    return integer_word(text.substr(start, i - start));
}

// Uncalibrated G2 axes report INT_MAX (2147483647), in degrees or centidegrees; no real angle is
// anywhere near a million degrees.
constexpr double unhomed_threshold = 1.0e6;
constexpr std::string_view int_max_text = "2147483647";

Status parse_error(std::string what, Span<const std::string> lines) {
    std::string shown;
    for (const auto& line : lines) {
        if (!shown.empty()) {
            shown += " | ";
        }
        shown += line;
    }
    return Status{Errc::protocol, what + " in reply \"" + shown + "\""};
}

}  // namespace

std::string format_degrees(double degrees) {
    double rounded = std::round(degrees * 100.0) / 100.0;
    if (rounded == 0.0) {
        rounded = 0.0;  // -0.0 compares equal to 0.0; this assignment drops the sign
    }
    std::array<char, 64> buffer{};
    const auto [ptr, ec] =
        std::to_chars(buffer.data(), buffer.data() + buffer.size(), rounded, std::chars_format::fixed, 2);
    if (ec != std::errc{}) {
        return "0.00";
    }
    return std::string(buffer.data(), ptr);
}

std::string build_axis_move(Axis axis, double degrees) {
    return "a " + std::to_string(static_cast<int>(axis)) + " " + format_degrees(degrees);
}

std::string build_combined_move(AzEl target) {
    return "g " + format_degrees(target.az) + " " + format_degrees(target.el);
}

std::string build_nvs_dump(int index) {
    return "d " + std::to_string(index);
}

std::string build_rssi(int samples) {
    return "rssi " + std::to_string(samples);
}

Result<AzEl> parse_travler_position(Span<const std::string> lines) {
    const std::string text = join_lines(lines);
    const auto az = field_value(text, "AZ");
    const auto el = field_value(text, "EL");
    if (!az || !el) {
        return {{}, parse_error("no AZ/EL fields", lines)};
    }
    return {{*az, *el}, Status::ok()};
}

Result<AzEl> parse_g2_position(Span<const std::string> lines) {
    const std::string text = join_lines(lines);
    const auto az = field_value(text, "Angle[0]");
    const auto el = field_value(text, "Angle[1]");
    const bool sentinel = text.find(int_max_text) != std::string::npos || (az && std::fabs(*az) >= unhomed_threshold) ||
                          (el && std::fabs(*el) >= unhomed_threshold);
    if (sentinel) {
        return {{}, Status{Errc::not_homed, "the dish reports uncalibrated axes (INT_MAX); home them with h 0 / h 1"}};
    }
    if (!az || !el) {
        return {{}, parse_error("no Angle[0]/Angle[1] fields", lines)};
    }
    return {{*az, *el}, Status::ok()};
}

Result<double> parse_g2_move_ack(Span<const std::string> lines) {
    const std::string text = join_lines(lines);
    if (text.find(int_max_text) != std::string::npos) {
        return {0.0, Status{Errc::not_homed, "the dish reports an uncalibrated axis (INT_MAX)"}};
    }
    const auto value = field_value(text, "Angle");
    if (!value) {
        return {0.0, parse_error("no \"Angle = \" acknowledgement", lines)};
    }
    return {*value, Status::ok()};
}

Result<AzEl> parse_carryout_live(Span<const std::string> lines) {
    for (auto line = lines.rbegin(); line != lines.rend(); ++line) {
        const auto words = split_words(*line);
        for (std::size_t k = 1; k < words.size(); ++k) {
            if (words[k] != "el") {
                continue;
            }
            std::size_t el_at = k + 1;
            if (el_at < words.size() && words[el_at] == "=") {
                ++el_at;
            }
            if (el_at >= words.size()) {
                continue;
            }
            const auto az = integer_word(words[k - 1]);
            const auto el = integer_word(words[el_at]);
            if (az && el) {
                return {{*az / 100.0, *el / 100.0}, Status::ok()};
            }
        }
    }
    return {{}, parse_error("no live \"<az>   el = <el>\" sample", lines)};
}

Result<AzEl> parse_position(const FirmwareProfile& profile, Span<const std::string> lines) {
    switch (profile.position_format) {
        case PositionFormat::travler_az_el_sk:
            return parse_travler_position(lines);
        case PositionFormat::g2_angle_index:
            return parse_g2_position(lines);
        case PositionFormat::carryout_live:
            return parse_carryout_live(lines);
    }
    return {{}, Status{Errc::unsupported, "unknown position format"}};
}

std::optional<NvsEntry> parse_g2_nvs_line(std::string_view line) {
    std::size_t i = 0;
    while (i < line.size() && line[i] == ' ') {
        ++i;
    }
    const std::size_t index_start = i;
    while (i < line.size() && is_digit(line[i])) {
        ++i;
    }
    if (i == index_start || i >= line.size() || line[i] != ')') {
        return std::nullopt;
    }
    NvsEntry entry;
    entry.index = *integer_word(line.substr(index_start, i - index_start));
    const auto words = split_words(line.substr(i + 1));
    if (words.size() < 4) {
        return std::nullopt;
    }
    const std::size_t name_words = words.size() - 3;
    for (std::size_t w = 0; w < name_words; ++w) {
        if (w > 0) {
            entry.name += ' ';
        }
        entry.name += words[w];
    }
    entry.current = words[name_words];
    entry.saved = words[name_words + 1];
    entry.default_value = words[name_words + 2];
    return entry;
}

Result<RssiReading> parse_g2_rssi(Span<const std::string> lines) {
    const std::string text = join_lines(lines);
    const auto reads = integer_after(text, "Reads:");
    const auto average = integer_after(text, "avg:");
    const auto current = integer_after(text, "cur:");
    if (!reads || !average || !current) {
        return {{}, parse_error("no Reads:/avg:/cur: fields", lines)};
    }
    return {{*reads, *average, *current}, Status::ok()};
}

Result<LnbSupply> parse_g2_lnb_polarity(Span<const std::string> lines) {
    for (const std::string& line : lines) {
        const std::size_t row = line.find("LNB Polarity");
        if (row == std::string::npos) {
            continue;
        }
        // The current value is the first voltage after the name; the default column (`---`) none.
        const std::string_view values = std::string_view(line).substr(row + std::string_view("LNB Polarity").size());
        const std::size_t v13 = values.find("13V");
        const std::size_t v18 = values.find("18V");
        if (v13 == std::string_view::npos && v18 == std::string_view::npos) {
            break;
        }
        return {v13 < v18 ? LnbSupply::odu_13v : LnbSupply::stb_18v, Status::ok()};
    }
    return {{}, parse_error("no LNB Polarity row naming 13V or 18V", lines)};
}

std::string menu_for_prompt(const FirmwareProfile& profile, std::string_view prompt) {
    while (!prompt.empty() && prompt.back() == ' ') {
        prompt.remove_suffix(1);
    }
    if (prompt.empty()) {
        return {};
    }
    if (!profile.root_prompt.empty() && prompt == profile.root_prompt) {
        return "root";
    }
    if (prompt == "EE>") {
        return "eeprom";  // the G2's eeprom submenu prompt is not its command name
    }
    std::string menu;
    for (char c : prompt.substr(0, prompt.size() - 1)) {
        menu += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return menu.empty() ? std::string("root") : menu;
}

Status hazard_check(const FirmwareProfile& profile, std::string_view command, const HazardContext& context) {
    const std::optional<VariantId> variant =
        &profile == &probe_profile() ? std::nullopt : std::optional<VariantId>(profile.id);
    const HazardRequests requests = context.requests | (context.allow_nvs_write ? request_nvs_write : request_nothing);
    const HazardRuling ruling = judge_command(variant, context.menu, command, requests);
    if (ruling.hazard()) {
        return Status{Errc::hazard, "refused \"" + std::string(command) + "\": `" + std::string(ruling.word) + "` " +
                                        std::string(hazard_kind_name(ruling.kind)) + ": " + std::string(ruling.reason)};
    }
    const HazardRuling asked = classify_command(variant, context.menu, command);
    if (asked.granted_by == request_move && context.axes_unhomed) {  // homing is what unhomed axes need
        return Status{Errc::not_homed, "refused \"" + std::string(command) + "\": the axes are not homed"};
    }
    return Status::ok();
}

}  // namespace birdcage
