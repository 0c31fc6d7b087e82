// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "rotctl_protocol.hpp"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <sstream>

namespace birdcage::rotctl {

namespace {

struct Known {
    const char* name;
    const char* text;
};
// Indexed by -code; the texts are Hamlib's own (rigerror), so a front end reads as rotctl does.
constexpr std::array<Known, 21> kErrors{{
    {"RIG_OK", "Command completed successfully"},
    {"RIG_EINVAL", "Invalid parameter"},
    {"RIG_ECONF", "Invalid configuration"},
    {"RIG_ENOMEM", "Memory shortage"},
    {"RIG_ENIMPL", "Feature not implemented"},
    {"RIG_ETIMEOUT", "Communication timed out"},
    {"RIG_EIO", "IO error"},
    {"RIG_EINTERNAL", "Internal Hamlib error"},
    {"RIG_EPROTO", "Protocol error"},
    {"RIG_ERJCTED", "Command rejected by the rig"},
    {"RIG_ETRUNC", "Command performed, but arg truncated, result not guaranteed"},
    {"RIG_ENAVAIL", "Feature not available"},
    {"RIG_ENTARGET", "Target VFO unaccessible"},
    {"RIG_BUSERROR", "Communication bus error"},
    {"RIG_BUSBUSY", "Communication bus collision"},
    {"RIG_EARG", "NULL RIG handle or invalid pointer parameter"},
    {"RIG_EVFO", "Invalid VFO"},
    {"RIG_EDOM", "Argument out of domain of func"},
    {"RIG_EDEPRECATED", "Function deprecated"},
    {"RIG_ESECURITY", "Security error password not provided or crypto failure"},
    {"RIG_EPOWER", "Rig is not powered on"},
}};

const Known* known(int code) {
    const int index = -code;
    return index >= 0 && index < static_cast<int>(kErrors.size()) ? &kErrors[static_cast<std::size_t>(index)] : nullptr;
}

std::string trim(std::string_view s) {
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos) {
        return {};
    }
    const auto last = s.find_last_not_of(" \t\r\n");
    return std::string(s.substr(first, last - first + 1));
}

bool starts_with(std::string_view s, std::string_view prefix) {
    return s.substr(0, prefix.size()) == prefix;
}

std::optional<int> rprt(std::string_view line) {
    if (!starts_with(line, "RPRT ")) {
        return std::nullopt;
    }
    return std::atoi(std::string(line.substr(5)).c_str());
}

// "Can Park:\tY" -> true
bool caps_flag(const std::string& line, std::string_view key, bool& flag) {
    if (!starts_with(line, key)) {
        return false;
    }
    flag = trim(std::string_view(line).substr(key.size())) == "Y";
    return true;
}

}  // namespace

std::string error_name(int code) {
    if (const Known* k = known(code)) {
        return k->name;
    }
    return "RIG_E?(" + std::to_string(code) + ")";
}

std::string error_text(int code) {
    if (const Known* k = known(code)) {
        return k->text;
    }
    return "error " + std::to_string(code);
}

std::vector<std::string> Reply::values() const {
    std::vector<std::string> out;
    for (const std::string& line : lines) {
        // "Key: value", or "Key:" alone when the value is empty ("Status flags:" of an idle rotator).
        const auto colon = line.find(':');
        const bool keyed = colon != std::string::npos &&
                           (colon + 1 == line.size() || line[colon + 1] == ' ' || line[colon + 1] == '\t');
        out.push_back(keyed ? trim(std::string_view(line).substr(colon + 1)) : line);
    }
    return out;
}

std::string request(std::string_view command, Protocol protocol) {
    switch (protocol) {
        case Protocol::plain:
            return std::string(command) + "\n";
        case Protocol::extended:
            return "+" + std::string(command) + "\n";
        case Protocol::extended_semicolon:
            return ";" + std::string(command) + "\n";
    }
    return {};
}

std::optional<Reply> take_reply(std::string& buffer, Protocol protocol, Shape shape) {
    Reply reply;
    std::size_t at = 0;
    if (protocol == Protocol::extended_semicolon) {
        // One line: "get_pos:;Azimuth: 1.00;Elevation: 2.00;RPRT 0".
        const auto nl = buffer.find('\n');
        if (nl == std::string::npos) {
            return std::nullopt;
        }
        std::istringstream fields(buffer.substr(0, nl));
        bool header = true;
        for (std::string field; std::getline(fields, field, ';');) {
            field = trim(field);
            if (const auto c = rprt(field)) {
                reply.code = *c;
            } else if (!header && !field.empty()) {
                reply.lines.push_back(field);
            }
            header = false;
        }
        buffer.erase(0, nl + 1);
        return reply;
    }
    bool header = protocol == Protocol::extended;
    for (;;) {
        const auto nl = buffer.find('\n', at);
        if (nl == std::string::npos) {
            return std::nullopt;
        }
        const std::string line = trim(std::string_view(buffer).substr(at, nl - at));
        at = nl + 1;
        if (const auto c = rprt(line)) {
            // An error in the extended protocol may come without its header (an unknown command).
            reply.code = *c;
            break;
        }
        if (header) {
            header = false;
            continue;
        }
        if (protocol == Protocol::plain && shape.end == Shape::End::done && line == "done") {
            break;
        }
        reply.lines.push_back(line);
        if (protocol == Protocol::plain && shape.end == Shape::End::values &&
            static_cast<int>(reply.lines.size()) >= shape.lines) {
            break;
        }
    }
    buffer.erase(0, at);
    return reply;
}

std::optional<Limits> parse_dump_state(const std::vector<std::string>& lines) {
    Limits l;
    int found = 0;
    auto take = [&](const std::string& line, std::string_view key, double& into) {
        if (!starts_with(line, key)) {
            return;
        }
        if (const auto v = parse_number(std::string_view(line).substr(key.size()))) {
            into = *v;
            ++found;
        }
    };
    for (const std::string& line : lines) {
        take(line, "min_az=", l.min_az);
        take(line, "max_az=", l.max_az);
        take(line, "min_el=", l.min_el);
        take(line, "max_el=", l.max_el);
        take(line, "Minimum Azimuth:", l.min_az);
        take(line, "Maximum Azimuth:", l.max_az);
        take(line, "Minimum Elevation:", l.min_el);
        take(line, "Maximum Elevation:", l.max_el);
    }
    if (found == 0 && lines.size() >= 6) {
        // Hamlib 3's answer: protocol version, model, then the four limits bare.
        const auto a = parse_number(lines[2]), b = parse_number(lines[3]), c = parse_number(lines[4]),
                   d = parse_number(lines[5]);
        if (a && b && c && d) {
            return Limits{*a, *b, *c, *d};
        }
    }
    if (found != 4) {
        return std::nullopt;
    }
    return l;
}

Caps parse_dump_caps(const std::vector<std::string>& lines) {
    Caps c;
    std::string mfg, model;
    bool in_levels = false;
    Limits range;
    int range_lines = 0;
    auto take = [&](const std::string& line, std::string_view key, double& into) {
        if (starts_with(line, key)) {
            if (const auto v = parse_number(std::string_view(line).substr(key.size()))) {
                into = *v;
                ++range_lines;
            }
        }
    };
    for (const std::string& raw : lines) {
        const std::string got = trim(raw);
        // "Extra levels:", then per level its name alone on a line and "Label:", "Range:" lines.
        if (starts_with(got, "Extra levels:")) {
            in_levels = true;
            continue;
        }
        if (in_levels && got.find(':') == std::string::npos) {
            c.levels.push_back({got, "", ""});
            continue;
        }
        if (in_levels && !c.levels.empty() && starts_with(got, "Label:"))
            c.levels.back().label = trim(got.substr(6));
        if (in_levels && !c.levels.empty() && starts_with(got, "Range:"))
            c.levels.back().range = trim(got.substr(6));
        if (in_levels && starts_with(got, "Get parameters:"))
            in_levels = false;
        if (starts_with(got, "Mfg name:"))
            mfg = trim(got.substr(9));
        if (starts_with(got, "Model name:"))
            model = trim(got.substr(11));
        if (starts_with(got, "Backend version:"))
            c.backend = trim(got.substr(16));
        caps_flag(got, "Can Park:", c.can_park) || caps_flag(got, "Can Reset:", c.can_reset) ||
            caps_flag(got, "Can get Status:", c.can_status);
        take(got, "Min Azimuth:", range.min_az);
        take(got, "Max Azimuth:", range.max_az);
        take(got, "Min Elevation:", range.min_el);
        take(got, "Max Elevation:", range.max_el);
    }
    if (range_lines == 4) {
        c.limits = range;
    }
    c.model = trim(mfg + " " + model);
    return c;
}

Limits narrowed_by_info(Limits limits, const std::string& info) {
    const auto at = info.find("; el limits ");
    if (at == std::string::npos) {
        return limits;
    }
    const std::string rest = info.substr(at + 12);
    const auto dots = rest.find("..");
    if (dots == std::string::npos) {
        return limits;
    }
    const auto end = rest.find_first_of(";, ", dots + 2);
    const auto lo = parse_number(rest.substr(0, dots));
    const auto hi = parse_number(rest.substr(dots + 2, end == std::string::npos ? std::string::npos : end - dots - 2));
    if (lo && hi && *lo <= *hi) {
        limits.min_el = std::max(limits.min_el, *lo);
        limits.max_el = std::min(limits.max_el, *hi);
    }
    return limits;
}

std::optional<double> parse_number(std::string_view text) {
    std::string s = trim(text);
    if (const auto colon = s.find(": "); colon != std::string::npos) {
        s = trim(s.substr(colon + 2));
    }
    if (s.empty()) {
        return std::nullopt;
    }
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0') {
        return std::nullopt;
    }
    return v;
}

std::vector<std::string> words(const std::vector<std::string>& lines) {
    std::vector<std::string> out;
    for (const std::string& line : lines) {
        std::istringstream in(line);
        for (std::string w; in >> w;) {
            out.push_back(w);
        }
    }
    return out;
}

}  // namespace birdcage::rotctl
