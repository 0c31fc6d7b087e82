// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The Winegard backend's operations: each one a few lines forwarding to birdcage::RotatorService,
// inside guarded() (winegard_priv.hpp), with the core's errors and log lines mapped onto Hamlib's.
// The caps that point at them are C (caps/winegard.c); the conf parameters are in
// winegard_conf.cpp.
#include "winegard_priv.hpp"

#include "base/clock.hpp"
#include "base/log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace birdcage::hamlib {

namespace {

int to_hamlib_error(const Status& status) {
    switch (status.code) {
        case Errc::ok:
            return RIG_OK;
        case Errc::timeout:
            return -RIG_ETIMEOUT;
        case Errc::protocol:
            return -RIG_EPROTO;
        // Hamlib 4.7+ rotctld drops the client on -RIG_EIO: reserved for a port that is gone.
        case Errc::io:
            return -RIG_EIO;
        // The service reopens a hung-up port by path: recoverable, so the client must stay connected.
        case Errc::disconnected:
            return -RIG_ETIMEOUT;
        case Errc::invalid_argument:
            return -RIG_EINVAL;
        case Errc::unsupported:
            return -RIG_ENAVAIL;
        case Errc::hazard:
            return -RIG_ERJCTED;
        case Errc::not_homed:
            return -RIG_ERJCTED;
        case Errc::busy:
            return -RIG_ERJCTED;
        case Errc::not_initialised:
            return -RIG_ENAVAIL;
    }
    return -RIG_EINTERNAL;
}

rig_debug_level_e to_hamlib_level(LogLevel level) {
    switch (level) {
        case LogLevel::error:
            return RIG_DEBUG_ERR;
        case LogLevel::warning:
            return RIG_DEBUG_WARN;
        case LogLevel::verbose:
            return RIG_DEBUG_VERBOSE;
        case LogLevel::trace:
            return RIG_DEBUG_TRACE;
    }
    return RIG_DEBUG_TRACE;
}

bool is_auto(const FirmwareProfile* p) {
    return p == &probe_profile();
}

// The caps are C, written out per model; the facts they share with the core's variant table must
// agree with it, or the model would open as one dish and be listed as another.
bool caps_match_profile(const struct rot_caps& caps, const FirmwareProfile& p) {
    const bool can_home = is_auto(&p) || !p.home_commands.empty();
    bool ok = true;
    if (caps.model_name == nullptr || std::string(caps.model_name) != p.display_name) {
        rot_debug(RIG_DEBUG_BUG, "winegard: model %d is named \"%s\" in its caps, \"%.*s\" in the variant table\n",
                  caps.rot_model, caps.model_name != nullptr ? caps.model_name : "",
                  static_cast<int>(p.display_name.size()), p.display_name.data());
        ok = false;
    }
    if (caps.serial_rate_max != p.baud) {
        rot_debug(RIG_DEBUG_BUG, "winegard: model %d: caps serial_rate_max %d, variant table %d baud\n", caps.rot_model,
                  caps.serial_rate_max, p.baud);
        ok = false;
    }
    if ((caps.reset != nullptr) != can_home) {
        rot_debug(RIG_DEBUG_BUG, "winegard: model %d: caps %s a reset, the variant %s\n", caps.rot_model,
                  caps.reset != nullptr ? "have" : "lack", can_home ? "homes" : "cannot home");
        ok = false;
    }
    return ok;
}

// The service of an open rotator; nullptr before rot_open and after rot_close.
RotatorService* open_service(ROT* rot) {
    return priv_of(rot).service.get();
}

int not_open() {
    rot_debug(RIG_DEBUG_ERR, "winegard: the rotator is not open\n");
    return -RIG_EIO;
}

// What get_info says: the identity and the state lead, as Controller::describe() orders them (some
// clients show only the first 63 characters: Hamlib's netrotctl reads get_info into 64 bytes), and
// a dish that is not answering says so right after the identity, ahead of its last known state.
std::string describe(WinegardPriv& priv) {
    RotatorService* service = priv.service.get();
    if (service == nullptr) {
        return "Winegard " + dish_identity(profile(priv.options.variant), false) + ": not open";
    }
    std::string text = service->describe();
    if (!service->answering()) {
        const std::string state = service->initialising() ? "INITIALISING"
                                  : service->recovering() ? "RECOVERING"
                                                          : "NOT ANSWERING";
        const std::string identity = dish_identity(service->profile(), priv.options.detect) + ": ";
        if (text.rfind(identity, 0) == 0) {
            text.insert(identity.size(), state + "; last known: ");
        } else {
            text = state + "; " + text;
        }
    }
    return "Winegard " + text;
}

}  // namespace

void say(rig_debug_level_e level, const std::string& text) {
    rot_debug(level, "winegard: %s\n", text.c_str());
#if defined(BIRDCAGE_PRELOAD)
    // Stock rotctld runs at RIG_DEBUG_NONE unless given -v, where rot_debug prints nothing and a
    // failed open shows only rigerror()'s text ("Protocol error" after whatever the saved-message
    // buffer holds). What a user must read (waiting for a booting dish, why open failed, a wrong
    // baud rate) is therefore also written to stderr when Hamlib's level would hide it.
    if (level <= RIG_DEBUG_WARN && !rig_need_debug(level)) {
        std::fprintf(stderr, "winegard: %s\n", text.c_str());
    }
#endif
}

int report(const char* where, const Status& status) {
    if (!status) {
        say(RIG_DEBUG_ERR, std::string(where) + ": " + to_string(status.code) + ": " + status.message);
    }
    return to_hamlib_error(status);
}

const FirmwareProfile* profile_for_caps(const struct rot_caps& caps) {
    const char* name = static_cast<const char*>(caps.priv);
    if (name == nullptr) {
        return nullptr;
    }
    if (probe_profile().short_name == name) {
        return &probe_profile();
    }
    const auto id = variant_from_name(name);
    return id ? &profile(*id) : nullptr;
}

#if defined(BIRDCAGE_PRELOAD)
std::string& load_note() {
    static std::string note;
    return note;
}
#endif

}  // namespace birdcage::hamlib

using namespace birdcage;
using namespace birdcage::hamlib;

extern "C" int winegard_rot_init(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        if (rot == nullptr || rot->caps == nullptr || state_of(rot) == nullptr) {
            throw std::invalid_argument("rot_init without a rotator");
        }
        const FirmwareProfile* profile = profile_for_caps(*rot->caps);
        if (profile == nullptr) {
            rot_debug(RIG_DEBUG_BUG, "winegard: model %d names no variant\n", rot->caps->rot_model);
            return -RIG_EINVAL;
        }
        if (!caps_match_profile(*rot->caps, *profile)) {
            return -RIG_EINTERNAL;
        }
        auto priv = std::make_unique<WinegardPriv>();
        priv->options.variant = profile->id;
        priv->options.detect = is_auto(profile);
        priv->options.log = [](LogLevel level, const std::string& message) { say(to_hamlib_level(level), message); };
        ROTSTATE(rot)->priv = priv.release();
        return RIG_OK;
    });
}

extern "C" int winegard_rot_cleanup(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        delete &priv_of(rot);
        ROTSTATE(rot)->priv = nullptr;
        return RIG_OK;
    });
}

extern "C" int winegard_rot_open(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        WinegardPriv& priv = priv_of(rot);
        hamlib_port_t* port = ROTPORT(rot);
        rot_debug(RIG_DEBUG_VERBOSE, "winegard: opening %s on %s\n", rot->caps->model_name, port->pathname);
#if defined(BIRDCAGE_PRELOAD)
        if (!load_note().empty()) {
            rot_debug(RIG_DEBUG_VERBOSE, "winegard: %s\n", load_note().c_str());
        }
#endif
        Result<PortLink> link = open_port_link(rot);
        if (!link) {
            return report(where, link.status);
        }
        const int baud = port->parm.serial.rate > 0 ? port->parm.serial.rate : rot->caps->serial_rate_max;
        ControllerOptions options = priv.options;
        // `_` reports the rate the line really runs at (rotctld -s), not the table's.
        options.line_baud = port->type.rig == RIG_PORT_SERIAL ? baud : 0;
        options.line_is_pty = is_pseudo_terminal(port->pathname);
        options.leapfrog = priv.pointing.mode == PointingMode::leapfrog;
#if defined(BIRDCAGE_PRELOAD)
        if (priv.time_scale != 1.0) {
            // Against an emulator running k times faster: the core's clock runs k times faster, and
            // with it every period of the worker (ServiceTiming is dish time); I/O deadlines stay
            // real (the pty is real).
            options.clock = DishClock::scaled(priv.time_scale);
        }
#endif
        ServiceTiming timing;
        // Hamlib's retry (the caps' 1, or -C retry=N): the failed exchanges in a row retried before
        // the console is taken as out of sync and re-synchronised.
        timing.failures_before_recovery = std::max(static_cast<int>(port->retry), 0) + 1;
        say(RIG_DEBUG_VERBOSE, "waiting at most " + std::to_string(options.boot_timeout.count() / 1000) +
                                   " s (boot_timeout) for the console on " + port->pathname);
        priv.service = std::make_unique<RotatorService>(std::move(link.value.transport), options, timing,
                                                        std::move(link.value.reopen));
        priv.service->set_pointing(priv.pointing);
        priv.service->set_mount(priv.mount);
        if (Status st = priv.service->start(); !st) {
            priv.service.reset();
            return report(where, st);
        }
        if (priv.service->initialising()) {
            say(RIG_DEBUG_WARN, "open: the dish is still booting after boot_timeout; rot_open returns and the " +
                                    std::string("dish is initialised in the background (s reports BUSY, _ says ") +
                                    "INITIALISING; targets sent meanwhile are kept)");
        }
        return RIG_OK;
    });
}

extern "C" int winegard_rot_close(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        WinegardPriv& priv = priv_of(rot);
        if (priv.service) {
            priv.service->shutdown();
            priv.service.reset();
        }
        return RIG_OK;
    });
}

extern "C" int winegard_set_position(ROT* rot, azimuth_t az, elevation_t el) {
    return guarded(__func__, [&, where = __func__]() -> int {
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        rot_debug(RIG_DEBUG_VERBOSE, "winegard: set_position %.2f %.2f\n", static_cast<double>(az),
                  static_cast<double>(el));
        return report(where, service->set_target({static_cast<double>(az), static_cast<double>(el)}));
    });
}

extern "C" int winegard_get_position(ROT* rot, azimuth_t* az, elevation_t* el) {
    return guarded(__func__, [&, where = __func__]() -> int {
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        Result<AzEl> pos = service->position();
        if (!pos) {
            return report(where, pos.status);
        }
        *az = static_cast<azimuth_t>(pos.value.az);
        *el = static_cast<elevation_t>(pos.value.el);
        return RIG_OK;
    });
}

extern "C" int winegard_stop(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        return report(where, service->stop());
    });
}

extern "C" int winegard_park(ROT* rot) {
    return guarded(__func__, [&, where = __func__]() -> int {
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        return report(where, service->park());
    });
}

// Hamlib defines one rotator reset type, ROT_RESET_ALL (1, `R 1`): the homing run. Any other
// number names nothing Hamlib knows, so it is refused rather than taken as a request to home.
extern "C" int winegard_reset(ROT* rot, rot_reset_t reset) {
    return guarded(__func__, [&, where = __func__]() -> int {
        if (reset != ROT_RESET_ALL) {
            rot_debug(RIG_DEBUG_ERR,
                      "winegard: reset type %d is not supported; only ROT_RESET_ALL (%d, rotctl R %d) homes\n", reset,
                      ROT_RESET_ALL, ROT_RESET_ALL);
            return -RIG_EINVAL;
        }
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        return report(where, service->reset());
    });
}

extern "C" int winegard_get_status(ROT* rot, rot_status_t* status) {
    return guarded(__func__, [&, where = __func__]() -> int {
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        // Hamlib has no "homing" flag: a home is reported as BUSY (the console is held by the
        // firmware's home command, targets wait for it) and MOVING.
        unsigned flags = service->idle() ? ROT_STATUS_NONE : ROT_STATUS_MOVING;
        if (service->homing()) {
            flags |= ROT_STATUS_BUSY | ROT_STATUS_MOVING;
        }
        // Nor a "not ready" one (4.5 to master): a dish that cannot be asked (booting at open,
        // rebooting, unplugged, being re-synchronised) is BUSY alone, "not accepting commands" for
        // now; a target set meanwhile waits for it. Whether it moves is unknown, so not MOVING.
        // get_info says why.
        if (!service->answering()) {
            flags = ROT_STATUS_BUSY;
        }
        *status = static_cast<rot_status_t>(flags);
        return RIG_OK;
    });
}

extern "C" const char* winegard_get_info(ROT* rot) {
    static const char unavailable[] = "Winegard: no information (see the debug log)";
    const char* info = unavailable;
    guarded(__func__, [&, where = __func__]() -> int {
        WinegardPriv& priv = priv_of(rot);
        priv.info = describe(priv);
        info = priv.info.c_str();
        return RIG_OK;
    });
    return info;
}

extern "C" int winegard_set_ext_level(ROT* rot, hamlib_token_t token, value_t val) {
    return guarded(__func__, [&, where = __func__]() -> int {
        WinegardPriv& priv = priv_of(rot);
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        switch (token) {
            case tok_rssi_samples: {
                const double samples = static_cast<double>(val.f);
                if (!std::isfinite(samples) || samples < 1.0 || samples > rssi_max_samples) {
                    return report(where,
                                  {Errc::invalid_argument, "RSSI_SAMPLES is 1.." + std::to_string(rssi_max_samples)});
                }
                priv.rssi_samples = static_cast<int>(std::lround(samples));
                return RIG_OK;
            }
            case tok_lnb_volts: {
                const auto supply = lnb_supply_from_volts(static_cast<double>(val.f));
                if (!supply) {
                    return report(where, supply.status);
                }
                rot_debug(RIG_DEBUG_VERBOSE, "winegard: LNB supply %d V\n", lnb_volts(supply.value));
                return report(where, service->set_lnb_supply(supply.value));
            }
            case tok_rssi:
                return report(where, {Errc::invalid_argument, "RSSI is read only"});
            default:
                return -RIG_EINVAL;
        }
    });
}

extern "C" int winegard_get_ext_level(ROT* rot, hamlib_token_t token, value_t* val) {
    return guarded(__func__, [&, where = __func__]() -> int {
        WinegardPriv& priv = priv_of(rot);
        RotatorService* service = open_service(rot);
        if (service == nullptr) {
            return not_open();
        }
        switch (token) {
            case tok_rssi: {
                const auto reading = service->read_signal(priv.rssi_samples);
                if (!reading) {
                    return report(where, reading.status);
                }
                val->f = static_cast<float>(reading.value.average);
                return RIG_OK;
            }
            case tok_rssi_samples:
                val->f = static_cast<float>(priv.rssi_samples);
                return RIG_OK;
            case tok_lnb_volts:
                if (service->profile().receiver_menu.empty()) {
                    return report(where, {Errc::unsupported,
                                          std::string(service->profile().display_name) + " has no satellite tuner"});
                }
                if (const auto supply = service->lnb_supply()) {
                    val->f = static_cast<float>(lnb_volts(*supply));
                    return RIG_OK;
                }
                // Never a made-up 18: after rotctld restarts the dish may still be at 13 V.
                return report(where, {Errc::not_initialised,
                                      "the LNB supply is unknown: the dish's DVB dis did not say it "
                                      "and it has not been set since open (V LNB 13|18 sets it)"});
            default:
                return -RIG_EINVAL;
        }
    });
}

// rotctl's `w` (send_cmd) would write the client's text straight to the port: past the console
// session (its menu, its echo), past the hazard rule, from a TCP client rotctld never asks who it
// is. `w r` at the G2's MOT> releases the motors. Nothing is sent; the client is told why.
extern "C" int winegard_send_cmd(ROT* rot, const char* cmd, char* reply, int reply_len) {
    return guarded(__func__, [&, where = __func__]() -> int {
        priv_of(rot);
        if (reply != nullptr && reply_len > 0) {
            reply[0] = '\0';
        }
        rot_debug(RIG_DEBUG_ERR,
                  "winegard: raw command \"%s\" refused: the backend holds the console's session (its menu, "
                  "its echo, the hazard rule); nothing was sent\n",
                  cmd != nullptr ? cmd : "");
        return -RIG_ERJCTED;
    });
}
