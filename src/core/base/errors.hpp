// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Error values used everywhere inside the core. The Hamlib glue maps Errc to -RIG_E* in one switch.
#pragma once

#include <string>

namespace birdcage {

enum class Errc {
    ok,
    timeout,           // the dish did not answer (or finish) before a deadline
    protocol,          // the dish answered something we could not use, or reported a fault (stall)
    io,                // the operating system refused an operation on the port
    invalid_argument,  // the caller asked for something meaningless (NaN target, unknown name)
    unsupported,       // the variant cannot do this
    hazard,            // refused: the command is a documented way to damage or hang the dish
    not_homed,         // the axes are uncalibrated (G2 reports INT_MAX)
    not_initialised,   // initialize() has not succeeded yet
    busy,              // the console is occupied (e.g. a `g` move that any input would abort)
    disconnected,      // the port hung up (pty closed, USB adapter unplugged)
};

const char* to_string(Errc code);  // words for people; may be reworded
// The enumerator's own name (`not_homed`), for machine-read output such as the transcript golden
// files: it changes only when the enumerator does.
const char* errc_name(Errc code);

struct Status {
    Errc code = Errc::ok;
    std::string message;

    explicit operator bool() const { return code == Errc::ok; }
    static Status ok() { return {}; }
};

template <class T>
struct Result {
    T value{};
    Status status;

    explicit operator bool() const { return static_cast<bool>(status); }
};

}  // namespace birdcage
