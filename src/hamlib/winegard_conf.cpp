// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The Winegard backend's conf parameters (`-C key=value`) and extension levels: one table row per
// parameter (token, name, help, type, range, default, parse, format), and the Hamlib confparams
// lists the caps point at, filled from it per model. Numeric ranges and defaults are the core's
// (OptionRange next to each option, the option structs' initialisers, the variant's profile);
// this file only names and formats them.
#include "winegard.h"
#include "winegard_priv.hpp"

#include "base/clock.hpp"
#include "base/option_range.hpp"

#include <array>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <string>

namespace {

using birdcage::hamlib::priv_of;
using birdcage::hamlib::WinegardPriv;

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

std::string format_number(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", value);
    return buf;
}

std::string format_seconds(std::chrono::milliseconds duration) {
    return std::to_string(duration.count() / 1000);
}

std::string format_flag(bool on) {
    return on ? "1" : "0";
}

using birdcage::ControllerOptions;
using birdcage::PointingOptions;

struct ConfParam {
    long token;
    const char* name;
    const char* label;
    const char* tooltip;
    enum rig_conf_e type;
    birdcage::OptionRange range;                            // numeric only
    std::string (*dflt)(const birdcage::FirmwareProfile&);  // shown by rotctl -L
    bool (*parse)(const char* text, WinegardPriv& priv);    // false: -RIG_EINVAL
    std::string (*format)(const WinegardPriv& priv);
};

const birdcage::FirmwareProfile& variant_profile(const WinegardPriv& priv) {
    return birdcage::profile(priv.options.variant);
}

const ConfParam kConfParams[] = {
    {1,
     "variant",
     "Firmware variant",
     "auto (identify at open), hal000, hal205, pro, carryout2003 or g2; overrides the model's variant",
     RIG_CONF_STRING,
     {},
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
    {2,
     "leapfrog",
     "Leapfrog",
     "Same as pointing=leapfrog (1) or pointing=none (0); kept for older configurations",
     RIG_CONF_CHECKBUTTON,
     {},
     [](const birdcage::FirmwareProfile&) {
         return format_flag(PointingOptions{}.mode == birdcage::PointingMode::leapfrog);
     },
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
    {3, "boot_timeout", "Boot timeout",
     "Seconds rot_open waits for the console: silent until then, open fails; still booting, the dish is initialised in "
     "the background (s: BUSY)",
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
    {4,
     "skip_init",
     "Skip init",
     "Assume the dish is booted, its TV search stopped and the motor menu open",
     RIG_CONF_CHECKBUTTON,
     {},
     [](const birdcage::FirmwareProfile&) { return format_flag(ControllerOptions{}.skip_init); },
     [](const char* text, WinegardPriv& priv) { return parse_bool(text, &priv.options.skip_init); },
     [](const WinegardPriv& priv) { return format_flag(priv.options.skip_init); }},
    {5, "el_min", "Min elevation", "Lowest elevation the backend will command (never below the variant's limit)",
     RIG_CONF_NUMERIC, ControllerOptions::el_range,
     [](const birdcage::FirmwareProfile& p) { return format_number(p.el_min); },
     [](const char* text, WinegardPriv& priv) {
         return parse_optional_in(text, ControllerOptions::el_range, priv.options.el_min);
     },
     [](const WinegardPriv& priv) {
         return format_number(priv.options.el_min.value_or(variant_profile(priv).el_min));
     }},
    {6, "el_max", "Max elevation", "Highest elevation the backend will command (never above the variant's limit)",
     RIG_CONF_NUMERIC, ControllerOptions::el_range,
     [](const birdcage::FirmwareProfile& p) { return format_number(p.el_max); },
     [](const char* text, WinegardPriv& priv) {
         return parse_optional_in(text, ControllerOptions::el_range, priv.options.el_max);
     },
     [](const WinegardPriv& priv) {
         return format_number(priv.options.el_max.value_or(variant_profile(priv).el_max));
     }},
    {7, "az_min", "Min azimuth",
     "Wrap range: azimuth targets (0..360) below this are clamped to it (with az_max; default: whole circle)",
     RIG_CONF_NUMERIC, ControllerOptions::az_range,
     [](const birdcage::FirmwareProfile&) { return format_number(ControllerOptions::az_range.min); },
     [](const char* text, WinegardPriv& priv) {
         return parse_optional_in(text, ControllerOptions::az_range, priv.options.az_min);
     },
     [](const WinegardPriv& priv) {
         return format_number(priv.options.az_min.value_or(ControllerOptions::az_range.min));
     }},
    {8, "az_max", "Max azimuth", "Wrap range: azimuth targets (0..360) above this are clamped to it (with az_min)",
     RIG_CONF_NUMERIC, ControllerOptions::az_range,
     [](const birdcage::FirmwareProfile&) { return format_number(ControllerOptions::az_range.max); },
     [](const char* text, WinegardPriv& priv) {
         return parse_optional_in(text, ControllerOptions::az_range, priv.options.az_max);
     },
     [](const WinegardPriv& priv) {
         return format_number(priv.options.az_max.value_or(ControllerOptions::az_range.max));
     }},
    {9,
     "pointing",
     "Pointing mode",
     "predictive (aim where the satellite will be, inferred from the targets), leapfrog (upstream "
     "overshoot of a lagging axis) or none (each target as sent); unset: predictive or none by how fast this "
     "dish's small steps turn out to be (first guess: predictive on the G2, none on the others)",
     RIG_CONF_STRING,
     {},
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
         return std::string(birdcage::pointing_mode_name(priv.pointing.mode.value_or(
             predictive ? birdcage::PointingMode::predictive : birdcage::PointingMode::none)));
     }},
    {10, "deadband", "Deadband", "Predictive mode: largest on-sky error (degrees) per axis before the dish moves again",
     RIG_CONF_NUMERIC, PointingOptions::deadband_range_deg,
     [](const birdcage::FirmwareProfile&) { return format_number(PointingOptions{}.deadband_deg); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, PointingOptions::deadband_range_deg, &priv.pointing.deadband_deg);
     },
     [](const WinegardPriv& priv) { return format_number(priv.pointing.deadband_deg); }},
#if defined(BIRDCAGE_PRELOAD)
    {11, "time_scale", "Time scale",
     "Emulator runs only: the dish's clock runs this many times faster than real time (birdcage-sim --time-scale)",
     RIG_CONF_NUMERIC, birdcage::DishClock::scale_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::DishClock{}.scale()); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, birdcage::DishClock::scale_range, &priv.time_scale);
     },
     [](const WinegardPriv& priv) { return format_number(priv.time_scale); }},
#endif
    {12,
     "az_mapping",
     "Azimuth mapping",
     "How the firmware maps an azimuth command onto its travel: auto (learn it from where the dish goes), "
     "nearest (the branch nearest the dish), literal (the number is the mechanical angle) or wrap_manager "
     "(never through a wrap point, e.g. north: the long way round instead)",
     RIG_CONF_STRING,
     {},
     [](const birdcage::FirmwareProfile&) { return std::string("auto"); },
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
    {13,
     "pass_model",
     "Pass model",
     "Predictive mode: follow the satellite's orbit fitted to the client's targets, to the end of the pass (1), "
     "or only the local estimate from the last targets (0)",
     RIG_CONF_CHECKBUTTON,
     {},
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
    {16,
     "motor",
     "Known motor",
     "Predictive mode: the motors' start-up delay (s), top speed (deg/s) and acceleration (deg/s^2) as "
     "delay/speed/accel (rotctld splits -C at commas), used instead of what the legs show (none: learn them from the "
     "legs)",
     RIG_CONF_STRING,
     {},
     [](const birdcage::FirmwareProfile&) { return std::string("none"); },
     [](const char* text, WinegardPriv& priv) {
         if (std::strcmp(text, "none") == 0) {
             priv.pointing.known_motor.reset();
             return true;
         }
         birdcage::KnownMotor motor;
         char tail = '\0';
         if (std::sscanf(text, "%lf/%lf/%lf%c", &motor.startup_s, &motor.speed_dps, &motor.accel_dps2, &tail) != 3 ||
             !PointingOptions::known_startup_range_s.contains(motor.startup_s) ||
             !PointingOptions::known_rate_range.contains(motor.speed_dps) ||
             !PointingOptions::known_rate_range.contains(motor.accel_dps2)) {
             return false;
         }
         priv.pointing.known_motor = motor;
         return true;
     },
     [](const WinegardPriv& priv) {
         const auto& motor = priv.pointing.known_motor;
         return motor ? format_number(motor->startup_s) + "/" + format_number(motor->speed_dps) + "/" +
                            format_number(motor->accel_dps2)
                      : std::string("none");
     }},
    {17, "start_cost", "Cost of a motor start",
     "Predictive mode, a client without look-ahead: what a motor start costs, in seconds of the dish off by "
     "its deadband; each axis then steps coarser where the satellite moves fast, up to half the client's "
     "threshold (0: the deadband alone, more starts and less error)",
     RIG_CONF_NUMERIC, PointingOptions::start_cost_range_s,
     [](const birdcage::FirmwareProfile&) { return format_number(PointingOptions{}.start_cost_s); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, PointingOptions::start_cost_range_s, &priv.pointing.start_cost_s);
     },
     [](const WinegardPriv& priv) { return format_number(priv.pointing.start_cost_s); }},
    // The mount model (docs/sky.md §1): targets and `p` are in the sky, limits and wrap in the dish's axes.
    {18, "az_index", "Azimuth index",
     "Mount model: the true azimuth (degrees, east of north) the dish looks at when its azimuth reads 0; "
     "targets and p are then true azimuths, the limits stay the dish's",
     RIG_CONF_NUMERIC, birdcage::MountModel::az_index_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::MountModel{}.az_index); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, birdcage::MountModel::az_index_range, &priv.mount.az_index);
     },
     [](const WinegardPriv& priv) { return format_number(priv.mount.az_index); }},
    {19, "el_index", "Elevation index",
     "Mount model: how far (degrees) the beam points above the elevation the dish reads", RIG_CONF_NUMERIC,
     birdcage::MountModel::el_index_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::MountModel{}.el_index); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, birdcage::MountModel::el_index_range, &priv.mount.el_index);
     },
     [](const WinegardPriv& priv) { return format_number(priv.mount.el_index); }},
    {20, "tilt_north", "Tilt toward north",
     "Mount model: how far (degrees) the azimuth axis leans from the zenith toward true north (the base's "
     "north side lower)",
     RIG_CONF_NUMERIC, birdcage::MountModel::tilt_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::MountModel{}.tilt_north); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, birdcage::MountModel::tilt_range, &priv.mount.tilt_north);
     },
     [](const WinegardPriv& priv) { return format_number(priv.mount.tilt_north); }},
    {21, "tilt_east", "Tilt toward east",
     "Mount model: how far (degrees) the azimuth axis leans from the zenith toward true east (the base's "
     "east side lower)",
     RIG_CONF_NUMERIC, birdcage::MountModel::tilt_range,
     [](const birdcage::FirmwareProfile&) { return format_number(birdcage::MountModel{}.tilt_east); },
     [](const char* text, WinegardPriv& priv) {
         return parse_in(text, birdcage::MountModel::tilt_range, &priv.mount.tilt_east);
     },
     [](const WinegardPriv& priv) { return format_number(priv.mount.tilt_east); }},
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

// The defaults one model's list shows, and the list itself (RIG_CONF_END last); the list points
// into the defaults, so both live as long as the library.
struct ModelConf {
    std::array<std::string, kConfCount> defaults;
};

void fill_conf(confparams* list, ModelConf& storage, const birdcage::FirmwareProfile& p) {
    for (std::size_t i = 0; i < kConfCount; ++i) {
        const ConfParam& row = kConfParams[i];
        storage.defaults[i] = row.dflt(p);
        confparams c{};
        c.token = row.token;
        c.name = row.name;
        c.label = row.label;
        c.tooltip = row.tooltip;
        c.dflt = storage.defaults[i].c_str();
        c.type = row.type;
        if (row.type == RIG_CONF_NUMERIC) {
            c.u.n.min = static_cast<float>(row.range.min);
            c.u.n.max = static_cast<float>(row.range.max);
            c.u.n.step = static_cast<float>(row.range.step);
        }
        list[i] = c;
    }
    list[kConfCount] = confparams{};  // RIG_CONF_END
}

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

}  // namespace

extern "C" {
confparams winegard_auto_cfg_params[kConfCount + 1];
confparams winegard_hal000_cfg_params[kConfCount + 1];
confparams winegard_hal205_cfg_params[kConfCount + 1];
confparams winegard_pro_cfg_params[kConfCount + 1];
confparams winegard_carryout2003_cfg_params[kConfCount + 1];
confparams winegard_g2_cfg_params[kConfCount + 1];
// Every model lists the receiver's levels (the auto-detecting model learns its variant only at
// open); a variant without a tuner answers -RIG_ENAVAIL.
confparams winegard_ext_levels[4];
}

// Once per process, however many times Hamlib initialises the backend; Hamlib keeps pointers into
// the tables, so they are filled in place and never change afterwards.
extern "C" int winegard_init_tables(void) {
    static const int result = birdcage::hamlib::guarded(__func__, []() -> int {
        struct Target {
            const char* short_name;
            confparams* list;
        };
        const Target targets[] = {
            {"hal000", winegard_hal000_cfg_params}, {"hal205", winegard_hal205_cfg_params},
            {"pro", winegard_pro_cfg_params},       {"carryout2003", winegard_carryout2003_cfg_params},
            {"g2", winegard_g2_cfg_params},
        };
        static std::array<ModelConf, std::size(targets) + 1> storage;
        for (std::size_t i = 0; i < std::size(targets); ++i) {
            const auto id = birdcage::variant_from_name(targets[i].short_name);
            if (!id) {
                rot_debug(RIG_DEBUG_BUG, "winegard: no variant %s in the core's table\n", targets[i].short_name);
                return -RIG_EINTERNAL;
            }
            fill_conf(targets[i].list, storage[i], birdcage::profile(*id));
        }
        fill_conf(winegard_auto_cfg_params, storage.back(), birdcage::probe_profile());

        using birdcage::hamlib::tok_lnb_volts, birdcage::hamlib::tok_rssi, birdcage::hamlib::tok_rssi_samples;
        winegard_ext_levels[0] =
            ext_level(tok_rssi, "RSSI", "Signal strength",
                      "Tuner signal strength (ADC counts), the average of RSSI_SAMPLES reads at 20 ms; read only", 0.0f,
                      65535.0f, 1.0f);
        winegard_ext_levels[1] =
            ext_level(tok_rssi_samples, "RSSI_SAMPLES", "RSSI samples", "Reads averaged per RSSI reading", 1.0f,
                      static_cast<float>(birdcage::rssi_max_samples), 1.0f);
        winegard_ext_levels[2] =
            ext_level(tok_lnb_volts, "LNB", "LNB supply (V)",
                      "LNB supply: 13 V (lnbdc odu, vertical) or 18 V (lnbdc stb, horizontal, the boot default)", 13.0f,
                      18.0f, 5.0f);
        winegard_ext_levels[3] = confparams{};  // RIG_CONF_END
        return RIG_OK;
    });
    return result;
}

extern "C" int winegard_set_conf(ROT* rot, hamlib_token_t token, const char* val) {
    return birdcage::hamlib::guarded(__func__, [&]() -> int {
        const ConfParam* c = conf_param(token);
        if (c == nullptr) {
            rot_debug(RIG_DEBUG_ERR, "winegard: unknown conf token %ld\n", static_cast<long>(token));
            return -RIG_EINVAL;
        }
        // Every parameter is read once, at open: the controller, the service and its pointing are
        // built from them then. A value set afterwards (rotctl's `C`) would be stored and echoed by
        // get_conf while the running service kept the old one, so it is refused and the client is told.
        if (priv_of(rot).service) {
            rot_debug(RIG_DEBUG_ERR,
                      "winegard: %s can only be set before the rotator is opened; pass -C %s=%s when starting "
                      "rotctld (or rotctl)\n",
                      c->name, c->name, val);
            return -RIG_EINVAL;
        }
        if (!c->parse(val, priv_of(rot))) {
            rot_debug(RIG_DEBUG_ERR, "winegard: bad value \"%s\" for %s\n", val, c->name);
            return -RIG_EINVAL;
        }
        return RIG_OK;
    });
}

extern "C" int winegard_get_conf2(ROT* rot, hamlib_token_t token, char* val, int val_len) {
    return birdcage::hamlib::guarded(__func__, [&]() -> int {
        const ConfParam* c = conf_param(token);
        if (c == nullptr) {
            return -RIG_EINVAL;
        }
        std::snprintf(val, static_cast<std::size_t>(val_len), "%s", c->format(priv_of(rot)).c_str());
        return RIG_OK;
    });
}

#if defined(BIRDCAGE_PRELOAD)
extern "C" int winegard_get_conf(ROT* rot, hamlib_token_t token, char* val) {
    return winegard_get_conf2(rot, token, val, 128);  // Hamlib's own buffer size for get_conf
}
#endif
