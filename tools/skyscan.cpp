// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "skyscan.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace birdcage::skyscan {
namespace {

std::optional<double> number(std::string_view text) {
    const std::string s(text);
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
        return std::nullopt;
    }
    return v;
}

std::vector<std::string_view> split(std::string_view line, char separator) {
    std::vector<std::string_view> fields;
    std::size_t start = 0;
    while (true) {
        const std::size_t at = line.find(separator, start);
        fields.push_back(line.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start));
        if (at == std::string_view::npos)
            break;
        start = at + 1;
    }
    return fields;
}

}  // namespace

std::optional<Range> parse_range(std::string_view text) {
    const auto fields = split(text, ':');
    if (fields.size() != 3)
        return std::nullopt;
    const auto from = number(fields[0]), to = number(fields[1]), step = number(fields[2]);
    if (!from || !to || !step || *step <= 0 || *from > *to)
        return std::nullopt;
    return Range{*from, *to, *step};
}

std::vector<double> values(const Range& range) {
    std::vector<double> out;
    for (long i = 0;; ++i) {
        const double v = range.from + static_cast<double>(i) * range.step;
        if (v > range.to + 1e-6)
            break;
        out.push_back(v);
    }
    return out;
}

std::vector<Point> serpentine(const Range& az, const Range& el) {
    const auto azs = values(az);
    const auto els = values(el);
    std::vector<Point> out;
    for (std::size_t column = 0; column < azs.size(); ++column) {
        for (std::size_t i = 0; i < els.size(); ++i) {
            out.push_back({azs[column], els[column % 2 == 0 ? i : els.size() - 1 - i]});
        }
    }
    return out;
}

Key key_of(double az, double el) {
    return {std::lround(az * 100.0), std::lround(el * 100.0)};
}

std::optional<Row> parse_row(std::string_view line) {
    if (!line.empty() && line.back() == '\r')
        line.remove_suffix(1);
    if (line.find(',') != std::string_view::npos) {
        const auto f = split(line, ',');
        if (f.size() < 3)
            return std::nullopt;
        const auto az = number(f[0]), el = number(f[1]), value = number(f[2]);
        if (!az || !el || !value)
            return std::nullopt;  // the header, or garbage
        return Row{*az, *el, *value, f.size() > 3 ? std::string(f[3]) : std::string()};
    }
    std::istringstream in{std::string(line)};
    std::string a, e, v, extra;
    if (!(in >> a >> e >> v) || (in >> extra))
        return std::nullopt;
    const auto az = number(a), el = number(e), value = number(v);
    if (!az || !el || !value)
        return std::nullopt;
    return Row{*az, *el, *value, {}};
}

std::size_t complete_length(std::string_view text) {
    const std::size_t last = text.rfind('\n');
    return last == std::string_view::npos ? 0 : last + 1;
}

std::vector<Row> parse_scan(std::string_view text) {
    std::vector<Row> rows;
    const std::string_view complete = text.substr(0, complete_length(text));
    std::size_t start = 0;
    while (start < complete.size()) {
        const std::size_t end = complete.find('\n', start);
        if (auto row = parse_row(complete.substr(start, end - start)))
            rows.push_back(std::move(*row));
        start = end + 1;
    }
    return rows;
}

std::vector<Point> remaining(const std::vector<Point>& plan, const std::vector<Row>& done) {
    std::set<Key> seen;
    for (const Row& row : done)
        seen.insert(key_of(row.az, row.el));
    std::vector<Point> out;
    for (const Point& p : plan) {
        if (!seen.count(key_of(p.az, p.el)))
            out.push_back(p);
    }
    return out;
}

std::string format_row(const Row& row) {
    char buffer[128];
    std::snprintf(buffer, sizeof buffer, "%.2f,%.2f,%g,%s", row.az, row.el, row.value, row.time.c_str());
    return buffer;
}

}  // namespace birdcage::skyscan
