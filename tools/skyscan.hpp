// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-skyscan's pure parts (grid, serpentine order, resume), kept apart from its I/O so the
// unit tests reach them.
#pragma once

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace birdcage::skyscan {

struct Range {
    double from = 0, to = 0, step = 1;
};
// "110:240:1" (from:to:step, from <= to, step > 0); nullopt when malformed.
std::optional<Range> parse_range(std::string_view text);
// The values from..to inclusive (to is included when it lies on the step, within 1e-6).
std::vector<double> values(const Range& range);

struct Point {
    double az = 0, el = 0;
};
// Azimuth columns in ascending order; elevation up in even columns and down in odd ones, so the
// dish never sweeps back to the bottom of the next column (half the elevation travel of a raster).
std::vector<Point> serpentine(const Range& az, const Range& el);

// Points are compared on a 0.01 degree lattice (the CSV keeps two decimals).
using Key = std::pair<long, long>;
Key key_of(double az, double el);

struct Row {
    double az = 0, el = 0, value = 0;
    std::string time;  // empty in the upstream format
};
// One line of our CSV (`az,el,value,time`) or of the upstream scan (`az el rssi`); nullopt for a
// header, a blank or a malformed line.
std::optional<Row> parse_row(std::string_view line);
// Every complete row of a scan file's text (a last line without its newline is an interrupted
// write and is ignored).
std::vector<Row> parse_scan(std::string_view text);
// The bytes of `text` to keep before appending: up to and including its last newline.
std::size_t complete_length(std::string_view text);
// The points of `plan` not in `done`, in plan order.
std::vector<Point> remaining(const std::vector<Point>& plan, const std::vector<Row>& done);

std::string format_row(const Row& row);  // "174.00,43.00,562,2026-11-23T21:00:00Z"

}  // namespace birdcage::skyscan
