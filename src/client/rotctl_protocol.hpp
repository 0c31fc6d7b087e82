// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// rotctld's text protocol as a client reads it, without a socket: the reply shapes of the plain
// and the extended protocols, RPRT codes as names, and the answers of `\dump_state`, `\dump_caps`
// and `v ?`. Written from what Hamlib 4.5/4.6's rotctld prints; it includes none of Hamlib's
// headers, so a program that only talks to rotctld needs no Hamlib at all.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace birdcage::rotctl {

// Hamlib's error codes as rotctld reports them ("RPRT -6"); values are fixed by Hamlib's ABI.
enum class Errc : int {
    ok = 0,
    inval = 1,
    conf = 2,
    nomem = 3,
    nimpl = 4,
    timeout = 5,
    io = 6,
    internal = 7,
    proto = 8,
    rjcted = 9,
    trunc = 10,
    navail = 11,
    ntarget = 12,
    buserror = 13,
    busbusy = 14,
    arg = 15,
    vfo = 16,
    dom = 17,
    deprecated = 18,
    security = 19,
    power = 20,
};
// -RIG_E* as the protocol carries it.
constexpr int code(Errc e) {
    return -static_cast<int>(e);
}
// "RIG_EIO" for -6; "RIG_E?(-42)" for a code Hamlib does not define.
std::string error_name(int code);
// "IO error" for -6: a line a user can read.
std::string error_text(int code);

// `+cmd` answers "cmd:" header, "Key: value" lines, "RPRT n", one per line; `;cmd` the same on one
// line separated by ';'. The plain protocol answers a get with bare values and a set with "RPRT n".
enum class Protocol { plain, extended, extended_semicolon };

// How a reply ends, in the plain protocol: after `lines` value lines (or an earlier RPRT line), at
// an RPRT line (`\dump_caps`), or at "done" (`\dump_state`). The extended protocol always ends at RPRT.
struct Shape {
    enum class End { values, rprt, done } end = End::values;
    int lines = 0;
    static Shape values(int n) { return {End::values, n}; }
    static Shape until_rprt() { return {End::rprt, 0}; }
    static Shape until_done() { return {End::done, 0}; }
};

struct Reply {
    int code = 0;                    // 0 or -RIG_E*
    std::vector<std::string> lines;  // the value lines as they came, without header and RPRT
    bool ok() const { return code == 0; }
    // The value lines with their "Key: " removed (the extended protocol's keys).
    std::vector<std::string> values() const;
};

// The line sent for `command` in `protocol` ("+p\n").
std::string request(std::string_view command, Protocol protocol);
// Takes one complete reply off the front of `buffer` (bytes read so far) and returns it; nullopt
// while the reply is incomplete (buffer untouched).
std::optional<Reply> take_reply(std::string& buffer, Protocol protocol, Shape shape);

struct Limits {
    double min_az = 0, max_az = 360, min_el = 0, max_el = 90;
    bool contains(double az, double el) const { return az >= min_az && az <= max_az && el >= min_el && el <= max_el; }
};
// `\dump_state`'s lines: Hamlib 4's "min_az=..." lines, or the extended "Minimum Azimuth: ..." ones.
std::optional<Limits> parse_dump_state(const std::vector<std::string>& lines);

// What `\dump_caps` says about the rotator behind rotctld.
struct Caps {
    std::string model;    // "Winegard Carryout G2"
    std::string backend;  // "Winegard birdcage 0.1.0"
    bool can_park = false;
    bool can_reset = false;  // `R`: the Winegard backend homes the axes
    bool can_status = false;
    struct Level {
        std::string name, label, range;  // "LNB", "LNB supply (V)", "13..18/5"
    };
    std::vector<Level> levels;     // the backend's extension levels
    std::optional<Limits> limits;  // "Min Azimuth:" .. "Max Elevation:"
};
Caps parse_dump_caps(const std::vector<std::string>& lines);

// The birdcage backend's `_` names the dish's own elevation range ("; el limits 18.00..65.00"),
// narrower than the caps' 0..90: `limits` narrowed to it when `info` names it.
Limits narrowed_by_info(Limits limits, const std::string& info);

// A number a value line carries ("100.00", "Azimuth: 100.00"); nullopt when it is not one.
std::optional<double> parse_number(std::string_view text);
// The words of `v ?`'s answer.
std::vector<std::string> words(const std::vector<std::string>& lines);

}  // namespace birdcage::rotctl
