// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Hamlib glue for the Winegard backend: rot_caps per firmware variant, conf parameters, and the
// callbacks that forward to birdcage::RotatorService. This is the only file that knows Hamlib
// (besides hamlib_compat.h); everything it calls is the plain C++ core.
// Over 500 lines: about half is tables (the conf parameters, ext levels and one rot_caps per
// model); each callback is a few-line forward to RotatorService with the error mapping.
#include "hamlib_abi.hpp"
#include "hamlib_compat.h"
#include "winegard.h"

#include "base/clock.hpp"
#include "dish/controller.hpp"
#include "base/errors.hpp"
#include "base/log.hpp"
#include "base/option_range.hpp"
#include "dish/receiver.hpp"
#include "service/rotator_service.hpp"
#include "tracking/steering.hpp"
#include "console/transport.hpp"
#include "firmware/variants.hpp"

#include <array>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
#include <string>

#ifndef BIRDCAGE_MODEL_FAMILY
#define BIRDCAGE_MODEL_FAMILY 901
#endif

namespace {

using birdcage::Errc;
using birdcage::Status;

constexpr const char* kBackendVersion = "20261122.0";

// Variants registered as Hamlib models. Each one is a row of the core's variant table; the
// caps below are derived from that row so limits and baud rates live in one place.
constexpr std::array kRegisteredVariants = {
    birdcage::VariantId::travler_hal000, birdcage::VariantId::travler_hal205, birdcage::VariantId::travler_pro,
    birdcage::VariantId::carryout2003,   birdcage::VariantId::carryout_g2,
};

// Accepted by Hamlib's own range check (which answers RPRT -1 outside it, and Gpredict disengages
// after five errors). They cover Gpredict's 0..360 and -180..180 azimuth modes and its default
// 0..90 elevation; the backend then clamps to what the variant can really do.
constexpr float kCapsMinAz = -180.0f;
constexpr float kCapsMaxAz = 540.0f;
constexpr float kCapsMinEl = 0.0f;
constexpr float kCapsMaxEl = 90.0f;


struct WinegardPriv {
    birdcage::ControllerOptions options;
    birdcage::PointingOptions pointing;   // mode unset: the variant's default
    double time_scale = 1.0;   // emulator runs only: the backend's clock runs this many times faster
    int rssi_samples = birdcage::rssi_default_samples;   // ext level RSSI_SAMPLES
    std::unique_ptr<birdcage::RotatorService> service;
    std::string info;
};

// Set at load when the running Hamlib is another release of the build's ABI; logged at open.
std::string& abi_note() {
    static std::string note;
    return note;
}

WinegardPriv* priv_of(ROT* rot) {
    return static_cast<WinegardPriv*>(WG_ROTSTATE(rot)->priv);
}

int to_hamlib_error(const Status& status) {
    switch (status.code) {
    case Errc::ok: return RIG_OK;
    case Errc::timeout: return -RIG_ETIMEOUT;
    case Errc::protocol: return -RIG_EPROTO;
    // Hamlib 4.7+ rotctld drops the client on -RIG_EIO: reserved for a port that is gone.
    case Errc::io: return -RIG_EIO;
    // The service reopens a hung-up port by path: recoverable, so the client must stay connected.
    case Errc::disconnected: return -RIG_ETIMEOUT;
    case Errc::invalid_argument: return -RIG_EINVAL;
    case Errc::unsupported: return -RIG_ENAVAIL;
    case Errc::hazard: return -RIG_ERJCTED;
    case Errc::not_homed: return -RIG_ERJCTED;
    case Errc::busy: return -RIG_ERJCTED;
    case Errc::not_initialised: return -RIG_ENAVAIL;
    }
    return -RIG_EINTERNAL;
}

// Stock rotctld runs at RIG_DEBUG_NONE unless given -v, where rot_debug prints nothing and a
// failed open shows only rigerror()'s text ("Protocol error" after whatever the saved-message
// buffer holds). What a user must read (waiting for a booting dish, why open failed, a wrong baud
// rate) is therefore also written to stderr when Hamlib's level would hide it.
void say(rig_debug_level_e level, const std::string& text) {
    rot_debug(level, "winegard: %s\n", text.c_str());
    if (level <= RIG_DEBUG_WARN && !rig_need_debug(level)) {
        std::fprintf(stderr, "winegard: %s\n", text.c_str());
    }
}

int report(const char* where, const Status& status) {
    if (!status) {
        say(RIG_DEBUG_ERR, std::string(where) + ": " + birdcage::to_string(status.code) + ": " + status.message);
    }
    return to_hamlib_error(status);
}

rig_debug_level_e to_hamlib_level(birdcage::LogLevel level) {
    switch (level) {
    case birdcage::LogLevel::error: return RIG_DEBUG_ERR;
    case birdcage::LogLevel::warning: return RIG_DEBUG_WARN;
    case birdcage::LogLevel::verbose: return RIG_DEBUG_VERBOSE;
    case birdcage::LogLevel::trace: return RIG_DEBUG_TRACE;
    }
    return RIG_DEBUG_TRACE;
}

const birdcage::FirmwareProfile* profile_for_model(rot_model_t model) {
    for (birdcage::VariantId id : kRegisteredVariants) {
        const birdcage::FirmwareProfile& p = birdcage::profile(id);
        if (ROT_MAKE_MODEL(BIRDCAGE_MODEL_FAMILY, p.model_index) == model) {
            return &p;
        }
    }
    if (ROT_MAKE_MODEL(BIRDCAGE_MODEL_FAMILY, birdcage::probe_profile().model_index) == model) {
        return &birdcage::probe_profile();  // the auto-detecting model
    }
    return nullptr;
}

bool is_auto(const birdcage::FirmwareProfile* p) { return p == &birdcage::probe_profile(); }

bool parse_bool(const char* text, bool* out) {
    if (std::strcmp(text, "1") == 0 || std::strcmp(text, "on") == 0 || std::strcmp(text, "true") == 0) {
        *out = true;
        return true;
    }
    if (std::strcmp(text, "0") == 0 || std::strcmp(text, "off") == 0 || std::strcmp(text, "false") == 0) {
        *out = false;
        return true;
    }
    return false;
}

bool parse_number(const char* text, double* out) {
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text, &end);
    if (end == text || *end != '\0' || errno != 0 || !std::isfinite(value)) {
        return false;
    }
    *out = value;
    return true;
}

// A number inside the core's range for the option.
bool parse_in(const char* text, const birdcage::OptionRange& range, double* out) {
    return parse_number(text, out) && range.contains(*out);
}

bool parse_optional_in(const char* text, const birdcage::OptionRange& range, std::optional<double>& out) {
    double number = 0;
    if (!parse_in(text, range, &number)) {
        return false;
    }
    out = number;
    return true;
}

extern "C" int winegard_rot_init(ROT* rot) {
    const birdcage::FirmwareProfile* profile = profile_for_model(rot->caps->rot_model);
    if (profile == nullptr) {
        return -RIG_EINVAL;
    }
    auto* priv = new (std::nothrow) WinegardPriv{};
    if (priv == nullptr) {
        return -RIG_ENOMEM;
    }
    priv->options.variant = profile->id;
    priv->options.detect = is_auto(profile);
    priv->options.log = [](birdcage::LogLevel level, const std::string& message) {
        say(to_hamlib_level(level), message);
    };
    WG_ROTSTATE(rot)->priv = priv;
    return RIG_OK;
}

extern "C" int winegard_rot_cleanup(ROT* rot) {
    delete priv_of(rot);
    WG_ROTSTATE(rot)->priv = nullptr;
    return RIG_OK;
}

extern "C" int winegard_rot_open(ROT* rot) {
    WinegardPriv* priv = priv_of(rot);
    hamlib_port_t* port = WG_ROTPORT(rot);
    rot_debug(RIG_DEBUG_VERBOSE, "winegard: opening %s on %s, fd %d\n", rot->caps->model_name,
              port->pathname, port->fd);
    if (!abi_note().empty()) {
        rot_debug(RIG_DEBUG_VERBOSE, "winegard: %s\n", abi_note().c_str());
    }
    if (port->fd < 0) {
        return -RIG_EIO;
    }
    // Hamlib owns the fd (it closes it in rot_close); it is non-blocking, which FdTransport polls.
    // After a hang-up (adapter unplugged) Hamlib's fd is dead and rotctld never reopens it: the
    // service opens the same path itself, on its own fd (Hamlib's stays untouched for rot_close).
    auto transport = std::make_unique<birdcage::FdTransport>(port->fd, false);
    const std::string path = port->pathname;
    const int baud = port->parm.serial.rate > 0 ? port->parm.serial.rate : rot->caps->serial_rate_max;
    birdcage::TransportFactory reopen = [path, baud]() -> birdcage::Result<std::unique_ptr<birdcage::Transport>> {
        auto opened = birdcage::FdTransport::open(path, baud);
        if (!opened) {
            return {nullptr, opened.status};
        }
        return {std::move(opened.value), birdcage::Status::ok()};
    };
    birdcage::ControllerOptions options = priv->options;
    // `_` reports the rate the line really runs at (rotctld -s), not the table's.
    options.line_baud = port->type.rig == RIG_PORT_SERIAL ? baud : 0;
    options.leapfrog = priv->pointing.mode == birdcage::PointingMode::leapfrog;
    if (priv->time_scale != 1.0) {
        // Against an emulator running k times faster: the core's clock runs k times faster, and
        // with it every period of the worker (ServiceTiming is dish time); I/O deadlines stay
        // real (the pty is real).
        options.clock = birdcage::DishClock::scaled(priv->time_scale);
    }
    priv->service = std::make_unique<birdcage::RotatorService>(std::move(transport), options, birdcage::ServiceTiming{},
                                                               std::move(reopen));
    priv->service->set_pointing(priv->pointing);
    if (Status st = priv->service->start(); !st) {
        priv->service.reset();
        return report(__func__, st);
    }
    return RIG_OK;
}

extern "C" int winegard_rot_close(ROT* rot) {
    WinegardPriv* priv = priv_of(rot);
    if (priv->service) {
        priv->service->shutdown();
        priv->service.reset();
    }
    return RIG_OK;
}

// ---- conf parameters: one row per parameter (token, name, help, type, default, parse, format) ----
// Numeric ranges and defaults are the core's (OptionRange next to each option, the option
// structs' initialisers, the variant's profile); this table only names and formats them.

std::string format_number(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", value);
    return buf;
}

std::string format_seconds(std::chrono::milliseconds duration) { return std::to_string(duration.count() / 1000); }

std::string format_flag(bool on) { return on ? "1" : "0"; }

using birdcage::ControllerOptions;
using birdcage::PointingOptions;

struct ConfParam {
    long token;
    const char* name;
    const char* label;
    const char* tooltip;
    enum rig_conf_e type;
    birdcage::OptionRange range;                                        // numeric only
    std::string (*dflt)(const birdcage::FirmwareProfile&);              // shown by rotctl -L
    bool (*parse)(const char* text, WinegardPriv& priv);               // false: -RIG_EINVAL
    std::string (*format)(const WinegardPriv& priv);
};

const birdcage::FirmwareProfile& variant_profile(const WinegardPriv& priv) { return birdcage::profile(priv.options.variant); }

const ConfParam kConfParams[] = {
    {1, "variant", "Firmware variant",
     "auto (identify at open), hal000, hal205, pro, carryout2003 or g2; overrides the model's variant",
     RIG_CONF_STRING, {},
     [](const birdcage::FirmwareProfile& p) { return std::string(p.short_name); },
     [](const char* text, WinegardPriv& priv) {
         if (std::strcmp(text, "auto") == 0) {
             priv.options.detect = true;
             return true;
         }
         const auto id = birdcage::variant_from_name(text);
         if (!id) {
             return false;
         }
         priv.options.variant = *id;
         priv.options.detect = false;
         return true;
     },
     [](const WinegardPriv& priv) {
         return priv.options.detect ? std::string("auto") : std::string(variant_profile(priv).short_name);
     }},
    {2, "leapfrog", "Leapfrog",
     "Same as pointing=leapfrog (1) or pointing=none (0); kept for older configurations",
     RIG_CONF_CHECKBUTTON, {},
     [](const birdcage::FirmwareProfile&) { return format_flag(PointingOptions{}.mode == birdcage::PointingMode::leapfrog); },
     [](const char* text, WinegardPriv& priv) {
         bool on = false;
         if (!parse_bool(text, &on)) {
             return false;
         }
         priv.pointing.mode = on ? birdcage::PointingMode::leapfrog : birdcage::PointingMode::none;
         return true;
     },
     [](const WinegardPriv& priv) {
         return std::string(priv.pointing.mode == birdcage::PointingMode::leapfrog ? "1" : "0");
     }},
    {3, "boot_timeout", "Boot timeout", "Seconds to wait at open for a booting dish to finish homing",
     RIG_CONF_NUMERIC, ControllerOptions::boot_timeout_range_s,
     [](const birdcage::FirmwareProfile&) { return format_seconds(ControllerOptions{}.boot_timeout); },
     [](const char* text, WinegardPriv& priv) {
         double number = 0;
         if (!parse_in(text, ControllerOptions::boot_timeout_range_s, &number)) {
             return false;
         }
         priv.options.boot_timeout = std::chrono::milliseconds(static_cast<long long>(number * 1000.0));
         return true;
     },
     [](const WinegardPriv& priv) { return format_seconds(priv.options.boot_timeout); }},
    {4, "skip_init", "Skip init", "Assume the dish is booted, its TV search stopped and the motor menu open",
     RIG_CONF_CHECKBUTTON, {}, [](const birdcage::FirmwareProfile&) { return format_flag(ControllerOptions{}.skip_init); },
     [](const char* text, WinegardPriv& priv) { return parse_bool(text, &priv.options.skip_init); },
     [](const WinegardPriv& priv) { return format_flag(priv.options.skip_init); }},
    {5, "el_min", "Min elevation", "Lowest elevation the backend will command (never below the variant's limit)",
     RIG_CONF_NUMERIC, ControllerOptions::el_range, [](const birdcage::FirmwareProfile& p) { return format_number(p.el_min); },
     [](const char* text, WinegardPriv& priv) { return parse_optional_in(text, ControllerOptions::el_range, priv.options.el_min); },
     [](const WinegardPriv& priv) { return format_number(priv.options.el_min.value_or(variant_profile(priv).el_min)); }},
    {6, "el_max", "Max elevation", "Highest elevation the backend will command (never above the variant's limit)",
     RIG_CONF_NUMERIC, ControllerOptions::el_range, [](const birdcage::FirmwareProfile& p) { return format_number(p.el_max); },
     [](const char* text, WinegardPriv& priv) { return parse_optional_in(text, ControllerOptions::el_range, priv.options.el_max); },
     [](const WinegardPriv& priv) { return format_number(priv.options.el_max.value_or(variant_profile(priv).el_max)); }},
    {7, "az_min", "Min azimuth",
     "Wrap range: azimuth targets (0..360) below this are clamped to it (with az_max; default: whole circle)",
     RIG_CONF_NUMERIC, ControllerOptions::az_range,
     [](const birdcage::FirmwareProfile&) { return format_number(ControllerOptions::az_range.min); },
     [](const char* text, WinegardPriv& priv) { return parse_optional_in(text, ControllerOptions::az_range, priv.options.az_min); },
     [](const WinegardPriv& priv) { return format_number(priv.options.az_min.value_or(ControllerOptions::az_range.min)); }},
    {8, "az_max", "Max azimuth", "Wrap range: azimuth targets (0..360) above this are clamped to it (with az_min)",
     RIG_CONF_NUMERIC, ControllerOptions::az_range,
     [](const birdcage::FirmwareProfile&) { return format_number(ControllerOptions::az_range.max); },
     [](const char* text, WinegardPriv& priv) { return parse_optional_in(text, ControllerOptions::az_range, priv.options.az_max); },
     [](const WinegardPriv& priv) { return format_number(priv.options.az_max.value_or(ControllerOptions::az_range.max)); }},
    {9, "pointing", "Pointing mode",
     "predictive (aim where the satellite will be, inferred from the targets), leapfrog (upstream "
     "overshoot of a lagging axis) or none (each target as sent); unset: predictive or none by how fast this "
     "dish's small steps turn out to be (first guess: predictive on the G2, none on the others)",
     RIG_CONF_STRING, {},
     [](const birdcage::FirmwareProfile& p) { return std::string(p.predictive_by_default ? "predictive" : "none"); },
     [](const char* text, WinegardPriv& priv) {
         const auto mode = birdcage::pointing_mode_from_name(text);
         if (!mode) {
             return false;
         }
         priv.pointing.mode = *mode;
         return true;
     },
     [](const WinegardPriv& priv) {
         const bool predictive = variant_profile(priv).predictive_by_default;
         return std::string(birdcage::pointing_mode_name(
             priv.pointing.mode.value_or(predictive ? birdcage::PointingMode::predictive : birdcage::PointingMode::none)));
     }},
    {10, "deadband", "Deadband",
     "Predictive mode: largest on-sky error (degrees) per axis before the dish moves again",
     RIG_CONF_NUMERIC, PointingOptions::deadband_range_deg,
     [](const birdcage::FirmwareProfile&) { return format_number(PointingOptions{}.deadband_deg); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, PointingOptions::deadband_range_deg, &priv.pointing.deadband_deg);
     },
     [](const WinegardPriv& priv) { return format_number(priv.pointing.deadband_deg); }},
    {11, "time_scale", "Time scale",
     "Emulator runs only: the dish's clock runs this many times faster than real time (birdcage-sim --time-scale)",
     RIG_CONF_NUMERIC, birdcage::DishClock::scale_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::DishClock{}.scale()); },
     [](const char* text, WinegardPriv& priv) { return parse_in(text, birdcage::DishClock::scale_range, &priv.time_scale); },
     [](const WinegardPriv& priv) { return format_number(priv.time_scale); }},
    {12, "az_mapping", "Azimuth mapping",
     "How the firmware maps an azimuth command onto its travel: auto (learn it from where the dish goes), "
     "nearest (the branch nearest the dish), literal (the number is the mechanical angle) or wrap_manager "
     "(never through a wrap point, e.g. north: the long way round instead)",
     RIG_CONF_STRING, {}, [](const birdcage::FirmwareProfile&) { return std::string("auto"); },
     [](const char* text, WinegardPriv& priv) {
         if (std::strcmp(text, "auto") == 0) {
             priv.options.az_mapping.reset();
             return true;
         }
         const auto mapping = birdcage::azmap::mapping_from_name(text);
         if (!mapping) {
             return false;
         }
         priv.options.az_mapping = *mapping;
         return true;
     },
     [](const WinegardPriv& priv) {
         return priv.options.az_mapping ? std::string(birdcage::azmap::mapping_name(*priv.options.az_mapping))
                                        : std::string("auto");
     }},
    {13, "pass_model", "Pass model",
     "Predictive mode: follow the satellite's orbit fitted to the client's targets, to the end of the pass (1), "
     "or only the local estimate from the last targets (0)",
     RIG_CONF_CHECKBUTTON, {},
     [](const birdcage::FirmwareProfile&) { return format_flag(PointingOptions{}.predictor.use_pass_model); },
     [](const char* text, WinegardPriv& priv) { return parse_bool(text, &priv.pointing.predictor.use_pass_model); },
     [](const WinegardPriv& priv) { return format_flag(priv.pointing.predictor.use_pass_model); }},
    {14, "deadband_share", "Deadband share of the client threshold",
     "Predictive mode: the deadband grows to this share of the client's own threshold, as learned from its "
     "targets (at most 1 degree; 0: the deadband alone). Fewer motor starts at coarse thresholds",
     RIG_CONF_NUMERIC, PointingOptions::client_threshold_share_range,
     [](const birdcage::FirmwareProfile&) { return format_number(PointingOptions{}.client_threshold_share); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, PointingOptions::client_threshold_share_range, &priv.pointing.client_threshold_share);
     },
     [](const WinegardPriv& priv) { return format_number(priv.pointing.client_threshold_share); }},
    {15, "latitude", "Site latitude",
     "Degrees north (south negative) of the dish, for the orbit fitted to the targets: the Earth turns under "
     "the pass (none: the fit takes the Earth as still, which is less exact)",
     RIG_CONF_NUMERIC, birdcage::OrbitModelSettings::latitude_range,
     [](const birdcage::FirmwareProfile&) { return std::string("none"); },
     [](const char* text, WinegardPriv& priv) {
         if (std::strcmp(text, "none") == 0) {
             priv.pointing.predictor.orbit.latitude_deg.reset();
             return true;
         }
         return parse_optional_in(text, birdcage::OrbitModelSettings::latitude_range,
                                  priv.pointing.predictor.orbit.latitude_deg);
     },
     [](const WinegardPriv& priv) {
         const auto& latitude = priv.pointing.predictor.orbit.latitude_deg;
         return latitude ? format_number(*latitude) : std::string("none");
     }},
};
constexpr std::size_t kConfCount = sizeof kConfParams / sizeof kConfParams[0];

const ConfParam* conf_param(hamlib_token_t token) {
    for (const ConfParam& c : kConfParams) {
        if (c.token == static_cast<long>(token)) {
            return &c;
        }
    }
    return nullptr;
}

extern "C" int winegard_set_conf(ROT* rot, hamlib_token_t token, const char* val) {
    const ConfParam* c = conf_param(token);
    if (c == nullptr) {
        rot_debug(RIG_DEBUG_ERR, "winegard: unknown conf token %ld\n", static_cast<long>(token));
        return -RIG_EINVAL;
    }
    // Every parameter is read once, at open: the controller, the service and its pointing are built
    // from them then. A value set afterwards (rotctl's `C`) would be stored and echoed by get_conf
    // while the running service kept the old one, so it is refused and the client is told.
    if (priv_of(rot)->service) {
        rot_debug(RIG_DEBUG_ERR,
                  "winegard: %s can only be set before the rotator is opened; pass -C %s=%s when starting "
                  "rotctld (or rotctl)\n",
                  c->name, c->name, val);
        return -RIG_EINVAL;
    }
    if (!c->parse(val, *priv_of(rot))) {
        rot_debug(RIG_DEBUG_ERR, "winegard: bad value \"%s\" for %s\n", val, c->name);
        return -RIG_EINVAL;
    }
    return RIG_OK;
}

extern "C" int winegard_get_conf2(ROT* rot, hamlib_token_t token, char* val, int val_len) {
    const ConfParam* c = conf_param(token);
    if (c == nullptr) {
        return -RIG_EINVAL;
    }
    std::snprintf(val, static_cast<std::size_t>(val_len), "%s", c->format(*priv_of(rot)).c_str());
    return RIG_OK;
}

extern "C" int winegard_get_conf(ROT* rot, hamlib_token_t token, char* val) {
    return winegard_get_conf2(rot, token, val, 128); // Hamlib's own buffer size for get_conf
}

birdcage::RotatorService* open_service(ROT* rot) {
    return priv_of(rot)->service.get();
}

extern "C" int winegard_set_position(ROT* rot, azimuth_t az, elevation_t el) {
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    rot_debug(RIG_DEBUG_VERBOSE, "winegard: set_position %.2f %.2f\n", static_cast<double>(az),
              static_cast<double>(el));
    return report(__func__, service->set_target({static_cast<double>(az), static_cast<double>(el)}));
}

extern "C" int winegard_get_position(ROT* rot, azimuth_t* az, elevation_t* el) {
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    birdcage::Result<birdcage::AzEl> pos = service->position();
    if (!pos) {
        return report(__func__, pos.status);
    }
    *az = static_cast<azimuth_t>(pos.value.az);
    *el = static_cast<elevation_t>(pos.value.el);
    return RIG_OK;
}

extern "C" int winegard_stop(ROT* rot) {
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    return report(__func__, service->stop());
}

extern "C" int winegard_park(ROT* rot) {
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    return report(__func__, service->park());
}

// Hamlib defines one rotator reset type, ROT_RESET_ALL (1, `R 1`): the homing run. Any other
// number names nothing Hamlib knows, so it is refused rather than taken as a request to home.
extern "C" int winegard_reset(ROT* rot, rot_reset_t reset) {
    if (reset != ROT_RESET_ALL) {
        rot_debug(RIG_DEBUG_ERR, "winegard: reset type %d is not supported; only ROT_RESET_ALL (%d, rotctl R %d) homes\n",
                  reset, ROT_RESET_ALL, ROT_RESET_ALL);
        return -RIG_EINVAL;
    }
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    return report(__func__, service->reset());
}

extern "C" int winegard_get_status(ROT* rot, rot_status_t* status) {
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    // Hamlib has no "homing" flag: a home is reported as BUSY (the console is held by the
    // firmware's home command, targets wait for it) and MOVING.
    unsigned flags = service->idle() ? ROT_STATUS_NONE : ROT_STATUS_MOVING;
    if (service->homing()) {
        flags |= ROT_STATUS_BUSY | ROT_STATUS_MOVING;
    }
    // Nor a "not ready" one (4.5 to master): a dish that cannot be asked (rebooting, unplugged,
    // being re-synchronised) is BUSY alone, "not accepting commands" for now; a target set
    // meanwhile waits for it. Whether it moves is unknown, so not MOVING. get_info says why.
    if (!service->answering()) {
        flags = ROT_STATUS_BUSY;
    }
    *status = static_cast<rot_status_t>(flags);
    return RIG_OK;
}

extern "C" const char* winegard_get_info(ROT* rot) {
    WinegardPriv* priv = priv_of(rot);
    priv->info = priv->service ? "Winegard " + priv->service->describe()
                               : "Winegard " + std::string(birdcage::profile(priv->options.variant).display_name) +
                                     " (not open)";
    return priv->info.c_str();
}

// Extension levels: the receiver (receiver.hpp) through stock rotctld's `v`/`V` (`v ?` lists them).
// Every model lists them (the probe model learns its variant only at open); a variant without a
// tuner answers -RIG_ENAVAIL.
enum ExtLevelToken : int { tok_rssi = 101, tok_rssi_samples = 102, tok_lnb_volts = 103 };

confparams ext_level(int token, const char* name, const char* label, const char* tooltip, float min, float max,
                     float step) {
    confparams c{};
    c.token = token;
    c.name = name;
    c.label = label;
    c.tooltip = tooltip;
    c.dflt = "";
    c.type = RIG_CONF_NUMERIC;
    c.u.n.min = min;
    c.u.n.max = max;
    c.u.n.step = step;
    return c;
}

const confparams* ext_levels() {
    static const std::array<confparams, 4> levels = {
        ext_level(tok_rssi, "RSSI", "Signal strength",
                  "Tuner signal strength (ADC counts), the average of RSSI_SAMPLES reads at 20 ms; read only",
                  0.0f, 65535.0f, 1.0f),
        ext_level(tok_rssi_samples, "RSSI_SAMPLES", "RSSI samples", "Reads averaged per RSSI reading", 1.0f,
                  static_cast<float>(birdcage::rssi_max_samples), 1.0f),
        ext_level(tok_lnb_volts, "LNB", "LNB supply (V)",
                  "LNB supply: 13 V (lnbdc odu, vertical) or 18 V (lnbdc stb, horizontal, the boot default)", 13.0f,
                  18.0f, 5.0f),
        confparams{},   // RIG_CONF_END
    };
    return levels.data();
}

extern "C" int winegard_set_ext_level(ROT* rot, hamlib_token_t token, value_t val) {
    WinegardPriv* priv = priv_of(rot);
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    switch (token) {
    case tok_rssi_samples: {
        const double samples = static_cast<double>(val.f);
        if (!std::isfinite(samples) || samples < 1.0 || samples > birdcage::rssi_max_samples) {
            return report(__func__, {Errc::invalid_argument, "RSSI_SAMPLES is 1.." + std::to_string(birdcage::rssi_max_samples)});
        }
        priv->rssi_samples = static_cast<int>(std::lround(samples));
        return RIG_OK;
    }
    case tok_lnb_volts: {
        const auto supply = birdcage::lnb_supply_from_volts(static_cast<double>(val.f));
        if (!supply) {
            return report(__func__, supply.status);
        }
        rot_debug(RIG_DEBUG_VERBOSE, "winegard: LNB supply %d V\n", birdcage::lnb_volts(supply.value));
        return report(__func__, service->set_lnb_supply(supply.value));
    }
    case tok_rssi:
        return report(__func__, {Errc::invalid_argument, "RSSI is read only"});
    default:
        return -RIG_EINVAL;
    }
}

extern "C" int winegard_get_ext_level(ROT* rot, hamlib_token_t token, value_t* val) {
    WinegardPriv* priv = priv_of(rot);
    birdcage::RotatorService* service = open_service(rot);
    if (service == nullptr) {
        return -RIG_EIO;
    }
    switch (token) {
    case tok_rssi: {
        const auto reading = service->read_signal(priv->rssi_samples);
        if (!reading) {
            return report(__func__, reading.status);
        }
        val->f = static_cast<float>(reading.value.average);
        return RIG_OK;
    }
    case tok_rssi_samples:
        val->f = static_cast<float>(priv->rssi_samples);
        return RIG_OK;
    case tok_lnb_volts:
        if (service->profile().receiver_menu.empty()) {
            return report(__func__, {Errc::unsupported, std::string(service->profile().display_name) + " has no satellite tuner"});
        }
        if (const auto supply = service->lnb_supply()) {
            val->f = static_cast<float>(birdcage::lnb_volts(*supply));
            return RIG_OK;
        }
        // Never a made-up 18: after rotctld restarts the dish may still be at 13 V.
        return report(__func__, {Errc::not_initialised, "the LNB supply is unknown: the dish's DVB dis did not say it "
                                                         "and it has not been set since open (V LNB 13|18 sets it)"});
    default:
        return -RIG_EINVAL;
    }
}

// Conf parameters per model: the defaults shown by `rotctl -L` are the variant's own values.
struct VariantConf {
    std::array<std::string, kConfCount> defaults;
    std::array<confparams, kConfCount + 1> params{};  // last = RIG_CONF_END
};

void fill_conf(VariantConf& conf, const birdcage::FirmwareProfile& p) {
    for (std::size_t i = 0; i < kConfCount; ++i) {
        const ConfParam& row = kConfParams[i];
        conf.defaults[i] = row.dflt(p);
        confparams c{};
        c.token = row.token;
        c.name = row.name;
        c.label = row.label;
        c.tooltip = row.tooltip;
        c.dflt = conf.defaults[i].c_str();
        c.type = row.type;
        if (row.type == RIG_CONF_NUMERIC) {
            c.u.n.min = static_cast<float>(row.range.min);
            c.u.n.max = static_cast<float>(row.range.max);
            c.u.n.step = static_cast<float>(row.range.step);
        }
        conf.params[i] = c;
    }
}

struct RegisteredModel {
    rot_caps caps{};
    VariantConf conf;
    std::string model_name;
    std::string macro_name;
};

// can_home: the model answers `R 1` by homing. A variant without a homing command gets no reset in
// its caps (`\dump_caps` says "Can Reset: N", and Hamlib answers `R` with RIG_ENAVAIL as before);
// the probe model learns its variant only at open, so it keeps it.
void fill_caps(RegisteredModel& m, const birdcage::FirmwareProfile& p, bool can_home) {
    fill_conf(m.conf, p);
    m.macro_name = "ROT_MODEL_WINEGARD_" + std::string(p.short_name);
    m.model_name = std::string(p.display_name);
    for (char& ch : m.macro_name) {
        ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    }

    rot_caps& c = m.caps;
    c.rot_model = ROT_MAKE_MODEL(BIRDCAGE_MODEL_FAMILY, p.model_index);
    c.model_name = m.model_name.c_str();
    c.mfg_name = "Winegard";
    c.version = kBackendVersion;
    c.copyright = "LGPL";   // LGPL-2.1-or-later (COPYING), in the words of Hamlib's own backends
    c.status = RIG_STATUS_ALPHA;
    c.rot_type = ROT_TYPE_AZEL;
    c.port_type = RIG_PORT_SERIAL;
    c.serial_rate_min = 9600;
    c.serial_rate_max = p.baud;
    c.serial_data_bits = 8;
    c.serial_stop_bits = 1;
    c.serial_parity = RIG_PARITY_NONE;
    c.serial_handshake = RIG_HANDSHAKE_NONE;
    c.write_delay = 0;
    c.post_write_delay = 0;
    c.timeout = 1000;
    c.retry = 0;
    c.has_status = static_cast<rot_status_t>(ROT_STATUS_MOVING | ROT_STATUS_BUSY);
    c.min_az = kCapsMinAz;
    c.max_az = kCapsMaxAz;
    c.min_el = kCapsMinEl;
    c.max_el = kCapsMaxEl;
    c.cfgparams = m.conf.params.data();
    c.rot_init = winegard_rot_init;
    c.rot_cleanup = winegard_rot_cleanup;
    c.rot_open = winegard_rot_open;
    c.rot_close = winegard_rot_close;
    c.set_conf = winegard_set_conf;
    c.get_conf = winegard_get_conf;
    c.set_position = winegard_set_position;
    c.get_position = winegard_get_position;
    c.stop = winegard_stop;
    c.park = winegard_park;
    c.reset = can_home ? winegard_reset : nullptr;
    c.get_info = winegard_get_info;
    c.get_status = winegard_get_status;
    c.macro_name = m.macro_name.c_str();
    c.get_conf2 = winegard_get_conf2;
    c.extlevels = ext_levels();
    c.set_ext_level = winegard_set_ext_level;
    c.get_ext_level = winegard_get_ext_level;
}

} // namespace

extern "C" int initrots4_winegard(void* /*be_handle*/) {
    // Function-local static: built on first call, whatever the order of static initialisation
    // (the preload constructor may run before this library's other initialisers). Hamlib keeps
    // the caps pointers, so the storage lives until exit.
    // The caps point into their own strings, so they are filled in place, never copied or moved.
    static std::array<RegisteredModel, kRegisteredVariants.size() + 1> models;
    static const bool filled = [] {
        for (std::size_t i = 0; i < kRegisteredVariants.size(); ++i) {
            const birdcage::FirmwareProfile& p = birdcage::profile(kRegisteredVariants[i]);
            fill_caps(models[i], p, !p.home_commands.empty());
        }
        fill_caps(models.back(), birdcage::probe_profile(), true);
        return true;
    }();
    (void)filled;
    int first_error = RIG_OK;
    for (RegisteredModel& m : models) {
        const int rc = rot_register(&m.caps);
        if (rc != RIG_OK && first_error == RIG_OK) {
            first_error = rc;
        }
    }
    return first_error;
}

#ifndef BIRDCAGE_IN_HAMLIB
#include <dlfcn.h>

namespace {

// The soname major of the libhamlib that provides rot_register in this process (the one the
// models would be registered with), 0 if it cannot be told.
int running_hamlib_soname() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&rot_register), &info) == 0 || info.dli_fname == nullptr) {
        return 0;
    }
    char resolved[PATH_MAX];
    const char* path = ::realpath(info.dli_fname, resolved) != nullptr ? resolved : info.dli_fname;
    return birdcage::hamlib::soname_major(path).value_or(0);
}

// Hamlib's debug level starts at TRACE before the program sets it, so rot_register() would print
// on every program start that inherits LD_PRELOAD. Register silently, then restore the level.
rig_debug_level_e current_debug_level() {
    int level = RIG_DEBUG_NONE;
    for (int l = RIG_DEBUG_BUG; l <= RIG_DEBUG_CACHE; ++l) {
        if (rig_need_debug(static_cast<rig_debug_level_e>(l))) {
            level = l;
        }
    }
    return static_cast<rig_debug_level_e>(level);
}

__attribute__((constructor)) void winegard_preload_register() {
    // Registering caps built for another Hamlib ABI would let Hamlib write through a struct s_rot
    // of another shape: refuse before touching anything, in one line naming both.
    const birdcage::hamlib::AbiVerdict abi = birdcage::hamlib::check_abi(
        BIRDCAGE_HAMLIB_BUILT_VERSION, BIRDCAGE_HAMLIB_BUILT_SONAME, hamlib_version2 != nullptr ? hamlib_version2 : "",
        running_hamlib_soname());
    if (!abi.compatible) {
        std::fprintf(stderr, "hamlib-winegard: %s; the Winegard models are not registered (rebuild the backend for this Hamlib)\n",
                     abi.message.c_str());
        return;
    }
    abi_note() = abi.message;
    const rig_debug_level_e saved = current_debug_level();
    rig_set_debug(RIG_DEBUG_NONE);
    const int rc = initrots4_winegard(nullptr);
    rig_set_debug(saved);
    if (rc != RIG_OK) {
        std::fprintf(stderr, "hamlib-winegard: model registration failed (%s); is model family %d taken?\n",
                     rigerror(rc), BIRDCAGE_MODEL_FAMILY);
    }
}

} // namespace
#endif
