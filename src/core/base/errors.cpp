// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "base/errors.hpp"

namespace birdcage {

const char* to_string(Errc code) {
    switch (code) {
        case Errc::ok:
            return "ok";
        case Errc::timeout:
            return "timeout";
        case Errc::protocol:
            return "protocol error";
        case Errc::io:
            return "I/O error";
        case Errc::invalid_argument:
            return "invalid argument";
        case Errc::unsupported:
            return "unsupported";
        case Errc::hazard:
            return "refused: hazardous command";
        case Errc::not_homed:
            return "axes not homed";
        case Errc::not_initialised:
            return "not initialised";
        case Errc::busy:
            return "busy";
        case Errc::disconnected:
            return "disconnected";
    }
    return "unknown error";
}

const char* errc_name(Errc code) {
    switch (code) {
        case Errc::ok:
            return "ok";
        case Errc::timeout:
            return "timeout";
        case Errc::protocol:
            return "protocol";
        case Errc::io:
            return "io";
        case Errc::invalid_argument:
            return "invalid_argument";
        case Errc::unsupported:
            return "unsupported";
        case Errc::hazard:
            return "hazard";
        case Errc::not_homed:
            return "not_homed";
        case Errc::not_initialised:
            return "not_initialised";
        case Errc::busy:
            return "busy";
        case Errc::disconnected:
            return "disconnected";
    }
    return "unknown";
}

}  // namespace birdcage
