#include "birdcage/errors.hpp"

namespace birdcage {

const char* to_string(Errc code) {
    switch (code) {
    case Errc::ok: return "ok";
    case Errc::timeout: return "timeout";
    case Errc::protocol: return "protocol error";
    case Errc::io: return "I/O error";
    case Errc::invalid_argument: return "invalid argument";
    case Errc::unsupported: return "unsupported";
    case Errc::hazard: return "refused: hazardous command";
    case Errc::not_homed: return "axes not homed";
    case Errc::not_initialised: return "not initialised";
    case Errc::busy: return "busy";
    case Errc::disconnected: return "disconnected";
    }
    return "unknown error";
}

}  // namespace birdcage
