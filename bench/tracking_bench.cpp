// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Tracking benchmark (docs/benchmarks.md): realistic LEO passes, a Gpredict-like client driving the stock
// rotctld with the backend preloaded, the dish emulator's true position as ground truth.
// Prints a table and writes CSV (summary, pooled latency, one trace per run) for bench/plot.py.
// Measures and reports; asserts nothing. See docs/benchmarks.md.
//
//   tracking_bench [--scale K] [--jobs N] [--passes a,b] [--variants g2,hal205]
//                  [--modes none,leapfrog,predictive,auto,oracle,oracle-motor] [--thresholds 0.5,5]
//                  [--window SECONDS] [--engage S] [--measure FROM,TO]
//                  [--mappings nearest,literal,wrap_manager] [--client-limits dish,wide] [--out DIR]
//                  [--client gpredict|current]
//                  [--passes-dir DIR] [--backend FILE]
//                  [--conf KEY=VALUE]... [--motor-startup-delay S] [--motor-speed AZ,EL] [--motor-accel A]
//
// The --motor-* options give every run the emulator's motor dynamics switches (sim/README.md,
// "motor"): e.g. a Trav'ler that meets the documented timings but starts seconds after each command.
// Mode oracle-motor is the oracle with the backend also told that motor (conf motor=delay/speed/accel,
// the azimuth speed): the aim a backend that knew the motor exactly would take. It needs --motor-speed
// and --motor-accel (the emulator's default Trav'ler is 20,20 and 2).
//
// --client-limits sets the rotator limits the Gpredict-like client clamps its targets to (Gpredict's
// MinEl/MaxEl, docs/gpredict.md): `dish` = the dish's elevation range (what README advised before the orbit model), so the
// client sends (AOS azimuth, floor) before the pass and never asks beyond the cap; `wide` = 0-90, so
// the backend clamps instead and the client, seeing the dish held at its floor more than a threshold
// off the satellite, sends a fresh target every cycle from AOS (a wide run starts at AOS, a dish run
// 6 deg below the floor). Azimuth stays 0-360 in both. The oracle runs once, with the dish's limits.
//
// --engage S starts the client (and the run) at S on the pass clock (the pass file's t) instead;
// --measure FROM,TO takes the error figures over that stretch of the pass clock only, and ends the
// run at TO. Together they replay the real-Gpredict loop's schedule (scripts/gpredict-loop.sh; on
// iss-45 its clock is the pass file's t minus 68 s): `--engage 108 --measure 248,428`
// (docs/benchmarks.md, "The benchmark's Gpredict client against real Gpredict").
//
// --backend FILE is the backend every rotctld preloads (default: the libhamlib-winegard.so built
// beside this program, found from where the program is; it refuses to start when there is none, so
// a copy of the program measures the backend it is given). --out DIR receives the CSV (default:
// out/ beside the program, in the build tree; the directory it runs from is left alone).
//
// --client current replaces the Gpredict-like client by one without look-ahead (testbed/gpredict_client.hpp,
// ClientSettings::look_ahead): it sends the satellite's direction as it is whenever that has moved a
// threshold from its last target. The run names and the summary's `client` column say so.
//
// --mappings runs every pass under each way the emulated firmware may map an azimuth target onto
// its travel (docs/firmware.md, "azimuth mapping"); the backend is not told which one it meets.
//
// Every run passes `-C time_scale=K` to rotctld, so the backend's clock and polling periods run at
// the emulator's pace and the time scale no longer distorts what the backend does; the program
// checks first that the backend it preloads knows that parameter (and `pointing`).
//
// Over 500 lines: one standalone program (options, the run of one pass, the ground-truth figures,
// the CSV and table output), each part used once and read top to bottom.
#include "gpredict_client.hpp"
#include "harness.hpp"
#include "pass.hpp"

#include "birdcage_sim/motor.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace {

using bench::Direction;
using birdcage::sim::Variant;

// The dishes benchmarked. The wire floor is the `a` position query as this variant's console
// answers it (2 bytes out, the echoed reply and prompt back), 10 bits per byte at its baud rate
// (docs/tracking.md §1.1) — what a synchronous `p` would cost at best on a real serial line; the
// emulator's pty has no baud rate, so this is computed, not measured.
struct VariantRow {
    const char* key;
    Variant variant;
    int model;
    const char* label;
    int baud;
    double el_min, el_max;
    const char* position_exchange;  // bytes on the wire for one `a` query, both directions
    // Mechanical azimuth window (README model table): decides whether one continuous branch could
    // have held a pass, i.e. whether an unwind was avoidable.
    double az_lo, az_hi;
};
const VariantRow variant_rows[] = {
    {"g2", Variant::carryout_g2, 90105, "Carryout G2", 115200, 18.0, 65.0,
     "a\r"
     "a\r\nAngle[0] = 180.00\r\nAngle[1] = 45.00\r\nMOT>",
     -423.33, 23.33},
    {"hal205", Variant::travler_hal205, 90102, "Trav'ler HAL 2.05", 57600, 15.0, 90.0,
     "a\r"
     "a\r\nAZ = 180.00 EL = 45.00 SK = 0.00\r\nMOTOR>",
     0.0, 455.0},
};

double wire_floor_ms(const VariantRow& v) {
    const double bytes = static_cast<double>(std::string(v.position_exchange).size());
    return bytes * 10.0 / v.baud * 1000.0;
}

// Pointing modes: one row per setting of the backend's `pointing` conf parameter.
struct ModeRow {
    const char* key;
    const char* label;
    std::vector<std::string> rotctld_args;
    bool oracle = false;       // the client posts the true position every cycle; run once, threshold 0
    bool knows_motor = false;  // the backend is told the emulated motor (conf motor, from --motor-*)
};
const std::vector<ModeRow> mode_rows = {
    {"none", "no compensation", {"-C", "pointing=none"}},
    {"leapfrog", "leapfrog (upstream thresholds, EL bug fixed)", {"-C", "pointing=leapfrog"}},
    {"predictive", "predictive (target motion from the P stream)", {"-C", "pointing=predictive"}},
    {"auto", "pointing unset: the variant's first guess, then what the dish's own step times say", {}},
    {"oracle", "oracle: predictive fed the true position every second", {"-C", "pointing=predictive"}, true},
    {"oracle-motor",
     "oracle that knows the motor: the oracle, the backend told the motor's delay, speed, accel",
     {"-C", "pointing=predictive"},
     true,
     true},
};

// Re-acquired after the elevation cap: the first moment the error is back within this.
constexpr double reacquire_within_deg = 1.0;

struct Options {
    double scale = 5.0;  // as scripts/benchmark.sh runs the matrix
    int jobs = 2;
    std::vector<std::string> passes = {"iss-20", "iss-45", "iss-60", "iss-70", "iss-85",
                                       "sso-20", "sso-45", "sso-70", "sso-85"};
    std::vector<std::string> variants = {"g2", "hal205"};
    std::vector<std::string> modes = {"none", "leapfrog", "predictive", "oracle"};
    std::vector<double> thresholds = {0.5, 5.0};
    std::vector<std::string> mappings = {"nearest"};
    std::vector<std::string> client_limits = {"dish"};
    std::string client = "gpredict";                   // or "current": see --client
    double window_s = 0.0;                             // > 0: only this many seconds around the TCA
    std::optional<double> engage_s;                    // --engage: the client starts here (pass clock)
    std::optional<std::pair<double, double>> measure;  // --measure: the error's stretch (pass clock)
    std::string out;                                   // --out; empty: out/ beside this program
    std::string backend;                               // --backend; empty: the backend built beside this program
    std::string passes_dir = BIRDCAGE_BENCH_PASSES_DIR;
    std::vector<std::string> extra_conf;  // --conf key=value: passed to every run as -C key=value
    birdcage::sim::MotorDynamics motor;   // --motor-*: the emulated motor (default: the variant's)
};

struct Figures {
    double median = 0, p95 = 0, p99 = 0, max = 0, rms = 0;
    std::size_t n = 0;
};

Figures figures_of(std::vector<double> v) {
    Figures f;
    f.n = v.size();
    if (v.empty()) {
        return f;
    }
    std::sort(v.begin(), v.end());
    auto at = [&v](double q) {
        return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
    };
    f.median = at(0.5);
    f.p95 = at(0.95);
    f.p99 = at(0.99);
    f.max = v.back();
    f.rms = std::sqrt(std::accumulate(v.begin(), v.end(), 0.0, [](double s, double x) { return s + x * x; }) /
                      static_cast<double>(v.size()));
    return f;
}

struct RunSpec {
    const bench::Pass* pass;
    const VariantRow* variant;
    const ModeRow* mode;
    double threshold;
    birdcage::sim::AzMapping mapping = birdcage::sim::AzMapping::nearest;
    std::string mapping_name = "nearest";
    std::string client_limits = "dish";  // "dish" or "wide": see --client-limits
};

struct RunResult {
    RunSpec spec;
    Figures error;         // degrees, satellite inside the dish's elevation limits
    double tracked_s = 0;  // seconds of the pass inside the limits
    std::size_t motor_commands = 0;
    std::size_t set_commands = 0;  // P sent by the client
    // The tracked window: from the satellite rising to the dish's lowest elevation until it sets
    // below it again (time above an elevation cap included: the dish still follows azimuth).
    double prepass_az_travel = 0;  // dish azimuth travel before the window (pre-positioning), degrees
    double extra_az_travel = 0;    // dish azimuth travel beyond the satellite's inside the window
    bool unwound = false;          // a mid-pass unwind: extra_az_travel > 180 deg
    bool one_branch = false;       // one branch of the mechanical AZ window holds the whole window
    // Above the elevation cap: error minus the unavoidable (satellite el - cap), and the seconds
    // from the satellite dropping back below the cap until the error is within 1 deg (NaN: the run
    // has no such drop; -1: never re-acquired before the run ended).
    double above_cap_s = 0;
    Figures cap_excess;
    double reacquire_s = std::nan("");
    std::vector<double> p_ms, set_ms, p_error_deg;
    unsigned failed_replies = 0;
    double wall_s = 0;
    std::string error_text;  // non-empty: the run could not be made
};

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (!item.empty()) {
            out.push_back(item);
        }
    }
    return out;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                throw std::runtime_error(arg + " needs a value");
            }
            return argv[++i];
        };
        if (arg == "--scale") {
            o.scale = std::stod(value());
        } else if (arg == "--jobs") {
            o.jobs = std::max(1, std::stoi(value()));
        } else if (arg == "--passes") {
            o.passes = split(value());
        } else if (arg == "--variants") {
            o.variants = split(value());
        } else if (arg == "--modes") {
            o.modes = split(value());
        } else if (arg == "--thresholds") {
            o.thresholds.clear();
            for (const std::string& t : split(value())) {
                o.thresholds.push_back(std::stod(t));
            }
        } else if (arg == "--mappings") {
            o.mappings = split(value());
        } else if (arg == "--client-limits") {
            o.client_limits = split(value());
            for (const std::string& limits : o.client_limits) {
                if (limits != "dish" && limits != "wide") {
                    throw std::runtime_error("--client-limits: unknown setting " + limits + " (dish or wide)");
                }
            }
        } else if (arg == "--client") {
            o.client = value();
            if (o.client != "gpredict" && o.client != "current") {
                throw std::runtime_error("--client: unknown client " + o.client + " (gpredict or current)");
            }
        } else if (arg == "--window") {
            o.window_s = std::stod(value());
        } else if (arg == "--engage") {
            o.engage_s = std::stod(value());
        } else if (arg == "--measure") {
            const std::vector<std::string> span = split(value());
            if (span.size() != 2 || std::stod(span[0]) >= std::stod(span[1])) {
                throw std::runtime_error("--measure: expected FROM,TO with FROM < TO");
            }
            o.measure = std::make_pair(std::stod(span[0]), std::stod(span[1]));
        } else if (arg == "--out") {
            o.out = value();
        } else if (arg == "--passes-dir") {
            o.passes_dir = value();
        } else if (arg == "--backend") {
            o.backend = value();
        } else if (arg == "--conf") {
            o.extra_conf.push_back(value());
        } else if (arg == "--motor-startup-delay") {
            o.motor.startup_delay = std::stod(value());
        } else if (arg == "--motor-speed") {
            const std::vector<std::string> speeds = split(value());
            if (speeds.size() != 2) {
                throw std::runtime_error("--motor-speed: expected AZ,EL");
            }
            o.motor.az_velocity = std::stod(speeds[0]);
            o.motor.el_velocity = std::stod(speeds[1]);
        } else if (arg == "--motor-accel") {
            o.motor.accel = std::stod(value());
        } else {
            throw std::runtime_error("unknown argument " + arg + " (see the comment at the top of tracking_bench.cpp)");
        }
    }
    return o;
}

// A motor command is a move: `a <axis> <deg>` (Trav'ler and G2) or `g <az> <el>`; `a` alone is a query.
bool is_motor_command(const std::string& line) {
    return (line.rfind("a ", 0) == 0 && line.find(' ', 2) != std::string::npos) || line.rfind("g ", 0) == 0;
}

std::string run_name(const RunSpec& s) {
    char thr[16];
    std::snprintf(thr, sizeof thr, "%g", s.threshold);
    const std::string mapping = s.mapping == birdcage::sim::AzMapping::nearest ? "" : "_" + s.mapping_name;
    // Dish limits keep the names bench/plot.py looks for.
    const std::string limits = s.client_limits == "dish" ? "" : "_" + s.client_limits;
    return std::string(s.pass->name()) + "_" + s.variant->key + "_" + s.mode->key + "_thr" + thr + mapping + limits;
}

RunResult run_one(const RunSpec& spec, const Options& options) {
    RunResult result;
    result.spec = spec;
    const auto wall_start = std::chrono::steady_clock::now();
    const bench::Pass& pass = *spec.pass;
    const VariantRow& v = *spec.variant;

    // The run covers the pass from a little below the dish's lowest elevation (Gpredict has been
    // holding the dish at the AOS azimuth, lowest elevation, since before AOS) until the satellite
    // sets below it: the part that is measured, with a few seconds of approach. With wide client
    // limits it starts at AOS: the targets the client sends between AOS and the floor are what
    // that setting changes (with the dish's they are the floor, sent only as the azimuth drifts).
    double start =
        spec.client_limits == "wide" ? pass.aos() : std::max(pass.aos(), pass.first_time_above(v.el_min - 6.0));
    double end = pass.last_time_above(v.el_min) + 5.0;
    if (options.window_s > 0.0) {
        start = std::max(start, pass.tca() - options.window_s / 2.0);
        end = std::min(end, pass.tca() + options.window_s / 2.0);
    }
    if (options.engage_s) {
        start = *options.engage_s;
    }
    if (options.measure) {
        end = options.measure->second;
    }
    const Direction at_start = pass.at(start);
    birdcage::sim::Options dish;
    dish.variant = v.variant;
    dish.time_scale = options.scale;
    dish.start_az = options.window_s > 0.0 ? at_start.az : pass.aos_az();
    dish.start_el = std::clamp(at_start.el, v.el_min, v.el_max);
    dish.az_mapping = spec.mapping;
    dish.motor = options.motor;

    // The backend's clock runs at the emulator's pace (conf time_scale), so its polling and leg
    // chaining happen at the same simulated moments as they would at real time.
    std::vector<std::string> rotctld_args = spec.mode->rotctld_args;
    char scale_text[48];
    std::snprintf(scale_text, sizeof scale_text, "time_scale=%g", options.scale);
    rotctld_args.insert(rotctld_args.end(), {"-C", scale_text});
    // The site's latitude, as a user sets it up (docs/usage.md, conf latitude); --conf latitude=none
    // (given later, so it wins) runs without.
    char latitude_text[48];
    std::snprintf(latitude_text, sizeof latitude_text, "latitude=%.4f", spec.pass->site_latitude());
    rotctld_args.insert(rotctld_args.end(), {"-C", latitude_text});
    if (spec.mode->knows_motor) {
        char motor_text[96];
        std::snprintf(motor_text, sizeof motor_text, "motor=%g/%g/%g", options.motor.startup_delay,
                      options.motor.az_velocity.value_or(0.0), options.motor.accel.value_or(0.0));
        rotctld_args.insert(rotctld_args.end(), {"-C", motor_text});
    }
    for (const std::string& conf : options.extra_conf) {
        rotctld_args.insert(rotctld_args.end(), {"-C", conf});
    }
    e2e::Rig rig(dish, v.model, rotctld_args);
    const std::size_t commands_before = rig.dish().received_commands().size();

    bench::ClientSettings settings;
    settings.threshold_deg = spec.threshold;
    settings.true_position_every_cycle = spec.mode->oracle;
    settings.look_ahead = options.client == "gpredict";
    const bool wide = spec.client_limits == "wide";
    settings.min_el = wide ? 0.0 : v.el_min;
    settings.max_el = wide ? 90.0 : v.el_max;
    bench::GpredictClient client(pass, settings, rig.dish(), options.scale, rig.port(), start);
    const bench::ClientRecord record = client.run_until(end);

    const std::vector<std::string> commands = rig.dish().received_commands();
    for (std::size_t i = commands_before; i < commands.size(); ++i) {
        result.motor_commands += is_motor_command(commands[i]) ? 1 : 0;
    }
    result.set_commands = record.sent_targets.size();
    result.p_ms = record.p_round_trip_ms;
    result.set_ms = record.set_round_trip_ms;
    result.p_error_deg = record.p_error_deg;
    result.failed_replies = record.failed_replies;
    if (record.disengaged) {
        // As Gpredict would: the rest of the run is a dish left where it stopped.
        std::fprintf(stderr, "%s: the client disengaged after %d erroring cycles (MAX_ERROR_COUNT) at t=%.1f s\n",
                     run_name(spec).c_str(), record.longest_error_streak, record.disengaged_at);
    }

    // Ground truth: the emulator's history (every 20 ms simulated tick while moving, every
    // second at rest), held between samples, on the pass clock.
    std::vector<birdcage::sim::Sample> history = rig.dish().history();
    for (auto& s : history) {
        s.t = client.pass_time_of(s.t);
    }
    std::size_t h = 0;
    auto dish_at = [&](double t) {
        while (h + 1 < history.size() && history[h + 1].t <= t) {
            ++h;
        }
        return Direction{history[h].az, history[h].el};
    };

    // The truth on a 0.1 s grid: an unwind (>= 65 deg/s, so <= 6.5 deg per step) is seen whole
    // when azimuth steps are folded the short way.
    struct GridPoint {
        double t;
        Direction sat, dish;
        double error;
    };
    std::vector<GridPoint> grid;
    constexpr double grid_s = 0.1;
    for (int i = 0; start + i * grid_s <= end; ++i) {
        const double t = start + i * grid_s;
        const Direction sat = pass.at(t), pointing = dish_at(t);
        grid.push_back({t, sat, pointing, bench::angle_between(sat, pointing)});
    }
    auto measured = [&options](const GridPoint& g) {
        return !options.measure || (g.t >= options.measure->first && g.t <= options.measure->second);
    };
    auto inside = [&v, &measured](const GridPoint& g) {
        return g.sat.el >= v.el_min && g.sat.el <= v.el_max && measured(g);
    };
    auto risen = [&v](const GridPoint& g) { return g.sat.el >= v.el_min; };
    auto above_cap = [&v](const GridPoint& g) { return g.sat.el > v.el_max; };

    std::vector<double> errors, excess;
    for (const GridPoint& g : grid) {
        if (inside(g)) {
            errors.push_back(g.error);
        }
        if (above_cap(g)) {
            excess.push_back(g.error - (g.sat.el - v.el_max));
        }
    }
    result.error = figures_of(errors);
    result.tracked_s = static_cast<double>(errors.size()) * grid_s;
    result.cap_excess = figures_of(excess);
    result.above_cap_s = static_cast<double>(excess.size()) * grid_s;

    // Azimuth travel: before the tracked window (pre-positioning, a branch change there costs no
    // tracking) and inside it, where more than 180 deg beyond the satellite's own travel is a
    // mid-pass unwind.
    const auto first_risen = std::find_if(grid.begin(), grid.end(), risen);
    const auto last_risen = std::find_if(grid.rbegin(), grid.rend(), risen);
    if (first_risen != grid.end()) {
        const std::size_t i0 = static_cast<std::size_t>(first_risen - grid.begin());
        const std::size_t i1 = grid.size() - 1 - static_cast<std::size_t>(last_risen - grid.rbegin());
        double dish_travel = 0, sat_travel = 0;
        for (std::size_t i = 1; i < grid.size(); ++i) {
            const double d_dish = std::fabs(bench::az_difference(grid[i].dish.az, grid[i - 1].dish.az));
            if (i <= i0) {
                result.prepass_az_travel += d_dish;
            } else if (i <= i1) {
                dish_travel += d_dish;
                sat_travel += std::fabs(bench::az_difference(grid[i].sat.az, grid[i - 1].sat.az));
            }
        }
        const double offset_at_rise = std::fabs(bench::az_difference(grid[i0].dish.az, grid[i0].sat.az));
        result.extra_az_travel = dish_travel - sat_travel - offset_at_rise;
        result.unwound = result.extra_az_travel > 180.0;
        // The satellite's azimuth over the window, unwrapped: does any whole-turn shift of it fit
        // inside the mechanical window?
        double az = grid[i0].sat.az, lo = az, hi = az;
        for (std::size_t i = i0 + 1; i <= i1; ++i) {
            az += bench::az_difference(grid[i].sat.az, grid[i - 1].sat.az);
            lo = std::min(lo, az);
            hi = std::max(hi, az);
        }
        // A firmware wrap manager keeps the axis inside one 360-degree sector of the travel.
        double window_lo = v.az_lo, window_hi = v.az_hi;
        if (spec.mapping == birdcage::sim::AzMapping::wrap_manager) {
            window_lo = std::max(v.az_lo, birdcage::sim::wrap_sector_start(dish.az_wrap_point, v.az_lo, v.az_hi));
            window_hi = std::min(v.az_hi, window_lo + 360.0);
        }
        for (int n = -3; n <= 3 && !result.one_branch; ++n) {
            result.one_branch = lo + 360.0 * n >= window_lo && hi + 360.0 * n <= window_hi;
        }
    }

    // Re-acquisition after the cap: from the last moment the satellite drops back below it.
    for (std::size_t i = grid.size(); i-- > 1;) {
        if (above_cap(grid[i - 1]) && !above_cap(grid[i])) {
            result.reacquire_s = -1.0;
            for (std::size_t k = i; k < grid.size(); ++k) {
                if (grid[k].error <= reacquire_within_deg) {
                    result.reacquire_s = grid[k].t - grid[i].t;
                    break;
                }
            }
            break;
        }
    }

    std::filesystem::create_directories(options.out + "/runs");
    std::ofstream trace(options.out + "/runs/" + run_name(spec) + ".csv");
    trace << "t,sat_az,sat_el,dish_az,dish_el,error_deg,in_limits,cap_excess_deg\n";
    for (std::size_t i = 0; i < grid.size(); i += 2) {  // 0.2 s in the file is plenty for plots
        const GridPoint& g = grid[i];
        char line[192];
        int n = std::snprintf(line, sizeof line, "%.2f,%.3f,%.3f,%.3f,%.3f,%.4f,%d,", g.t, g.sat.az, g.sat.el,
                              g.dish.az, g.dish.el, g.error, inside(g) ? 1 : 0);
        if (above_cap(g) && n > 0 && static_cast<std::size_t>(n) < sizeof line) {
            std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "%.4f", g.error - (g.sat.el - v.el_max));
        }
        trace << line << '\n';
    }

    std::ofstream read_backs(options.out + "/runs/" + run_name(spec) + "_readback.csv");
    read_backs << "t,az,el,true_az_before,true_el_before,true_az_after,true_el_after,error_deg\n";
    for (std::size_t i = 0; i < record.read_backs.size(); ++i) {
        const auto& r = record.read_backs[i];
        read_backs << r.t << ',' << r.reported.az << ',' << r.reported.el << ',' << r.true_before.az << ','
                   << r.true_before.el << ',' << r.true_after.az << ',' << r.true_after.el << ','
                   << record.p_error_deg[i] << '\n';
    }

    std::ofstream targets(options.out + "/runs/" + run_name(spec) + "_P.csv");
    targets << "t,az,el\n";
    for (const auto& s : record.sent_targets) {
        targets << s.t << ',' << s.dir.az << ',' << s.dir.el << '\n';
    }
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return result;
}

std::string cap_text(const RunResult& r) {
    if (r.cap_excess.n == 0) {
        return "-";
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", r.cap_excess.max);
    return text;
}

std::string reacquire_text(const RunResult& r) {
    if (std::isnan(r.reacquire_s)) {
        return "-";
    }
    if (r.reacquire_s < 0) {
        return "never";
    }
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", r.reacquire_s);
    return text;
}

void print_header() {
    std::printf(
        "%-7s %-7s %-10s %-4s %-4s %4s | %6s %6s %6s | %5s %4s | %6s %7s %2s | %6s %5s | %6s %6s %6s | %6s %6s | %6s\n",
        "pass", "variant", "mode", "map", "lim", "thr", "RMS", "p95", "max", "motor", "P", "preAz", "xtraAz", "U",
        "capExc", "reacq", "p med", "p p99", "p max", "P med", "P p99", "|p|p95");
    std::printf(
        "%-7s %-7s %-10s %-4s %-4s %4s | %6s %6s %6s | %5s %4s | %6s %7s %2s | %6s %5s | %6s %6s %6s | %6s %6s | %6s\n",
        "", "", "", "", "", "deg", "deg", "deg", "deg", "cmds", "sent", "deg", "deg", "", "max", "s", "ms", "ms", "ms",
        "ms", "ms", "deg");
}

void print_row(const RunResult& r) {
    const Figures p = figures_of(r.p_ms), set = figures_of(r.set_ms), pe = figures_of(r.p_error_deg);
    std::printf(
        "%-7s %-7s %-10s %-4.4s %-4.4s %4g | %6.3f %6.3f %6.3f | %5zu %4zu | %6.0f %7.0f %2s | %6s %5s | %6.3f %6.3f "
        "%6.3f | "
        "%6.3f %6.3f | %6.3f\n",
        r.spec.pass->name().c_str(), r.spec.variant->key, r.spec.mode->key, r.spec.mapping_name.c_str(),
        r.spec.client_limits.c_str(), r.spec.threshold, r.error.rms, r.error.p95, r.error.max, r.motor_commands,
        r.set_commands, r.prepass_az_travel, r.extra_az_travel, r.unwound ? (r.one_branch ? "UA" : "U") : "",
        cap_text(r).c_str(), reacquire_text(r).c_str(), p.median, p.p99, p.max, set.median, set.p99, pe.p95);
    std::fflush(stdout);
}

// A failed rig start carries rotctld's whole -vvvv log; what matters is its first line and the
// lines that say what went wrong.
std::string short_error(const std::string& text) {
    std::istringstream lines(text);
    std::string line, out;
    int kept = 0;
    bool first = true;
    while (std::getline(lines, line)) {
        const bool telling = line.find("conf") != std::string::npos || line.find("rror") != std::string::npos ||
                             line.find("nvalid") != std::string::npos || line.find("token") != std::string::npos;
        if (first || (telling && kept < 6)) {
            out += (first ? "" : "\n    ") + line;
            kept += first ? 0 : 1;
            first = false;
        }
    }
    return out;
}

// The conf parameters every run relies on must exist in the backend that is preloaded: an older
// build would make every rotctld refuse to start. `rotctl -L` lists them (it then fails to open
// the port given, which is what we want).
bool backend_has_conf(const std::vector<std::string>& keys, int model, std::string* missing) {
    const e2e::CommandResult listing =
        e2e::run({"/usr/bin/rotctl", "-m", std::to_string(model), "-r", "/nonexistent/birdcage-bench", "-L"},
                 e2e::preload_environment(), std::chrono::seconds(30));
    for (const std::string& key : keys) {
        if (listing.out.find("\n" + key + ": ") == std::string::npos && listing.out.rfind(key + ": ", 0) != 0) {
            *missing += (missing->empty() ? "" : ", ") + key;
        }
    }
    return missing->empty();
}

struct Pooled {
    Figures p, set, p_error;
};

Pooled pool(const std::vector<RunResult>& results, const VariantRow& v, const ModeRow& m) {
    std::vector<double> p, set, pe;
    for (const RunResult& r : results) {
        if (r.error_text.empty() && r.spec.variant == &v && r.spec.mode == &m) {
            p.insert(p.end(), r.p_ms.begin(), r.p_ms.end());
            set.insert(set.end(), r.set_ms.begin(), r.set_ms.end());
            pe.insert(pe.end(), r.p_error_deg.begin(), r.p_error_deg.end());
        }
    }
    return {figures_of(p), figures_of(set), figures_of(pe)};
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    try {
        options = parse(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tracking_bench: %s\n", e.what());
        return 2;
    }
    // Beside this program: the build tree's layout (bench/ and src/hamlib/ under one build dir).
    const std::string here = e2e::executable_directory();
    if (options.backend.empty()) {
        options.backend = here.empty()
                              ? std::string()
                              : (std::filesystem::path(here) / BIRDCAGE_BENCH_BACKEND).lexically_normal().string();
    }
    if (options.backend.empty() || !std::filesystem::is_regular_file(options.backend)) {
        std::fprintf(
            stderr, "tracking_bench: no backend at %s: name the libhamlib-winegard.so to preload with --backend FILE\n",
            options.backend.empty() ? "(this program's directory is unknown)" : options.backend.c_str());
        return 2;
    }
    e2e::use_backend_library(std::filesystem::absolute(options.backend).string());
    if (options.out.empty()) {
        if (here.empty()) {
            std::fprintf(stderr, "tracking_bench: this program's directory is unknown: name one with --out DIR\n");
            return 2;
        }
        options.out = here + "/out";
    }
    std::vector<bench::Pass> passes;
    try {
        for (const std::string& name : options.passes) {
            passes.push_back(bench::Pass::load(options.passes_dir + "/" + name + ".csv"));
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tracking_bench: %s\n", e.what());
        return 2;
    }
    std::vector<RunSpec> specs;
    for (const bench::Pass& pass : passes) {
        for (const std::string& vk : options.variants) {
            const auto v = std::find_if(std::begin(variant_rows), std::end(variant_rows),
                                        [&](const VariantRow& r) { return vk == r.key; });
            if (v == std::end(variant_rows)) {
                std::fprintf(stderr, "tracking_bench: unknown variant %s\n", vk.c_str());
                return 2;
            }
            for (const std::string& mk : options.modes) {
                const auto m =
                    std::find_if(mode_rows.begin(), mode_rows.end(), [&](const ModeRow& r) { return mk == r.key; });
                if (m == mode_rows.end()) {
                    std::fprintf(stderr, "tracking_bench: unknown mode %s\n", mk.c_str());
                    return 2;
                }
                if (m->knows_motor && (!options.motor.az_velocity || !options.motor.accel)) {
                    std::fprintf(stderr,
                                 "tracking_bench: mode %s needs --motor-speed and --motor-accel (the "
                                 "motor it tells the backend)\n",
                                 mk.c_str());
                    return 2;
                }
                for (const std::string& mapping_name : options.mappings) {
                    const auto mapping = birdcage::sim::parse_az_mapping(mapping_name);
                    if (!mapping) {
                        std::fprintf(stderr, "tracking_bench: unknown azimuth mapping %s\n", mapping_name.c_str());
                        return 2;
                    }
                    if (m->oracle) {
                        specs.push_back({&pass, &*v, &*m, 0.0, *mapping, mapping_name, "dish"});
                        continue;
                    }
                    for (double thr : options.thresholds) {
                        for (const std::string& limits : options.client_limits) {
                            specs.push_back({&pass, &*v, &*m, thr, *mapping, mapping_name, limits});
                        }
                    }
                }
            }
        }
    }
    if (specs.empty()) {
        std::fprintf(stderr, "tracking_bench: nothing to run\n");
        return 2;
    }
    std::string missing;
    if (!backend_has_conf({"pointing", "time_scale"}, specs.front().variant->model, &missing)) {
        std::fprintf(stderr,
                     "tracking_bench: the backend %s has no conf parameter %s; every rotctld would refuse to start.\n"
                     "Rebuild it from a tree that has `pointing` and `time_scale`.\n",
                     e2e::backend_library().c_str(), missing.c_str());
        return 2;
    }

    std::printf(
        "tracking benchmark: %zu runs, time scale %gx (emulator and backend, -C time_scale=%g), %d in "
        "parallel%s\n",
        specs.size(), options.scale, options.scale, options.jobs,
        options.window_s > 0 ? (", window " + std::to_string(options.window_s) + " s around TCA").c_str() : "");
    std::printf("backend %s, CSV into %s\n", e2e::backend_library().c_str(), options.out.c_str());
    if (options.engage_s || options.measure) {
        std::printf(
            "schedule: client engaged at %s, error measured over %s (pass clock, s)\n",
            options.engage_s ? std::to_string(*options.engage_s).c_str() : "the default",
            options.measure
                ? (std::to_string(options.measure->first) + "-" + std::to_string(options.measure->second)).c_str()
                : "the whole pass");
    }
    if (options.client != "gpredict") {
        std::printf(
            "client: no look-ahead: the satellite's current direction each time it moved a threshold from "
            "the last target (--client current)\n");
    }
    if (options.motor.startup_delay > 0.0 || options.motor.az_velocity || options.motor.accel) {
        std::printf(
            "motor: start-up delay %g s, speed %s, acceleration %s (emulator's motor switches)\n",
            options.motor.startup_delay,
            options.motor.az_velocity ? (std::to_string(*options.motor.az_velocity) + "," +
                                         std::to_string(options.motor.el_velocity.value_or(0)) + " deg/s")
                                            .c_str()
                                      : "the variant's",
            options.motor.accel ? (std::to_string(*options.motor.accel) + " deg/s^2").c_str() : "the variant's");
    }
    std::printf(
        "error = great-circle angle satellite vs true dish direction while the satellite is inside the dish's\n"
        "elevation limits; preAz = dish AZ travel before the satellite rose to the lowest elevation\n"
        "(pre-positioning); xtraAz = dish AZ travel beyond the satellite's after that; U = mid-pass unwind\n"
        "(xtraAz > 180), UA = avoidable one (one branch of the AZ window holds the pass); capExc = max of\n"
        "error - (sat el - cap) above the EL cap; reacq = s from dropping below the cap to error <= %g deg;\n"
        "lim = the client's rotator limits (dish: the dish's EL range, wide: EL 0-90)\n",
        reacquire_within_deg);
    print_header();

    std::vector<RunResult> results(specs.size());
    std::atomic<std::size_t> next{0};
    std::mutex print_mutex;
    auto worker = [&] {
        for (std::size_t i = next++; i < specs.size(); i = next++) {
            // A run whose client got no answers at all measured nothing; it is made once more.
            for (int attempt = 0; attempt < 2; ++attempt) {
                try {
                    results[i] = run_one(specs[i], options);
                    if (!results[i].p_error_deg.empty()) {
                        break;
                    }
                    results[i].error_text = "rotctld did not answer the client";
                } catch (const std::exception& e) {
                    results[i].spec = specs[i];
                    results[i].error_text = short_error(e.what());
                }
            }
            std::lock_guard lock(print_mutex);
            if (results[i].error_text.empty()) {
                print_row(results[i]);
            } else {
                std::printf("%s: FAILED: %s\n", run_name(specs[i]).c_str(), results[i].error_text.c_str());
            }
        }
    };
    std::vector<std::thread> threads;
    for (int j = 0; j < options.jobs; ++j) {
        threads.emplace_back(worker);
    }
    for (auto& t : threads) {
        t.join();
    }

    std::filesystem::create_directories(options.out);
    std::ofstream summary(options.out + "/summary.csv");
    summary << "pass,peak_el,crosses_north,variant,mode,az_mapping,threshold,client_limits,scale,window_s,tracked_s,"
               "rms,p95,max,motor_commands,"
               "set_commands,prepass_az_travel,extra_az_travel,unwound,one_branch,above_cap_s,cap_excess_p95,"
               "cap_excess_max,reacquire_s,p_median_ms,p_p95_ms,p_p99_ms,p_max_ms,P_median_ms,P_p95_ms,P_p99_ms,"
               "P_max_ms,p_error_p95_deg,p_error_p99_deg,p_error_max_deg,wire_floor_ms,failed_replies,wall_s,client\n";
    for (const RunResult& r : results) {
        if (!r.error_text.empty()) {
            continue;
        }
        const Figures p = figures_of(r.p_ms), set = figures_of(r.set_ms), pe = figures_of(r.p_error_deg);
        // Empty fields: no time above the cap, or no drop below it inside the run.
        char cap_p95[24] = "", cap_max[24] = "", reacquire[24] = "";
        if (r.cap_excess.n > 0) {
            std::snprintf(cap_p95, sizeof cap_p95, "%.4f", r.cap_excess.p95);
            std::snprintf(cap_max, sizeof cap_max, "%.4f", r.cap_excess.max);
        }
        if (!std::isnan(r.reacquire_s)) {
            std::snprintf(reacquire, sizeof reacquire, "%.1f", r.reacquire_s);
        }
        char line[768];
        std::snprintf(
            line, sizeof line,
            "%s,%.2f,%d,%s,%s,%s,%g,%s,%g,%g,%.1f,%.4f,%.4f,%.4f,%zu,%zu,%.1f,%.1f,%d,%d,%.1f,%s,%s,%s,%.4f,%.4f,"
            "%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%u,%.1f,%s\n",
            r.spec.pass->name().c_str(), r.spec.pass->peak_el(), r.spec.pass->crosses_north() ? 1 : 0,
            r.spec.variant->key, r.spec.mode->key, r.spec.mapping_name.c_str(), r.spec.threshold,
            r.spec.client_limits.c_str(), options.scale, options.window_s, r.tracked_s, r.error.rms, r.error.p95,
            r.error.max, r.motor_commands, r.set_commands, r.prepass_az_travel, r.extra_az_travel, r.unwound ? 1 : 0,
            r.one_branch ? 1 : 0, r.above_cap_s, cap_p95, cap_max, reacquire, p.median, p.p95, p.p99, p.max, set.median,
            set.p95, set.p99, set.max, pe.p95, pe.p99, pe.max, wire_floor_ms(*r.spec.variant), r.failed_replies,
            r.wall_s, r.spec.mode->oracle ? "oracle" : options.client.c_str());
        summary << line;
    }

    // Latency per variant and mode, every `p` and `P` of those runs pooled: the figures the goals
    // are stated in.
    std::ofstream latency(options.out + "/latency.csv");
    latency << "variant,mode,scale,runs,p_n,p_median_ms,p_p95_ms,p_p99_ms,p_max_ms,P_n,P_median_ms,P_p95_ms,P_p99_ms,"
               "P_max_ms,wire_floor_ms,p_error_median_deg,p_error_p95_deg,p_error_p99_deg,p_error_max_deg\n";
    std::printf(
        "\nlatency through rotctld per variant and mode (all runs pooled; wire floor = one `a` query at the "
        "baud rate)\n");
    std::printf("%-18s %-10s %-3s %7s %9s %9s %9s %9s | %s\n", "variant", "mode", "cmd", "n", "median", "p95", "p99",
                "max", "wire floor");
    for (const VariantRow& v : variant_rows) {
        for (const ModeRow& m : mode_rows) {
            const Pooled f = pool(results, v, m);
            if (f.p.n == 0) {
                continue;
            }
            const auto runs = std::count_if(results.begin(), results.end(), [&](const RunResult& r) {
                return r.error_text.empty() && r.spec.variant == &v && r.spec.mode == &m;
            });
            for (auto [label, data] : {std::pair{"p", &f.p}, std::pair{"P", &f.set}}) {
                std::printf("%-18s %-10s %-3s %7zu %7.3fms %7.3fms %7.3fms %7.3fms | %.2f ms (%d baud)\n", v.label,
                            m.key, label, data->n, data->median, data->p95, data->p99, data->max, wire_floor_ms(v),
                            v.baud);
            }
            std::printf(
                "%-18s %-10s %-3s %7zu reported-vs-true position: median %.3f, p95 %.3f, p99 %.3f, max %.3f "
                "deg\n",
                v.label, m.key, "p", f.p_error.n, f.p_error.median, f.p_error.p95, f.p_error.p99, f.p_error.max);
            char line[512];
            std::snprintf(line, sizeof line,
                          "%s,%s,%g,%ld,%zu,%.4f,%.4f,%.4f,%.4f,%zu,%.4f,%.4f,%.4f,%.4f,%.2f,%.4f,%.4f,%.4f,%.4f\n",
                          v.key, m.key, options.scale, static_cast<long>(runs), f.p.n, f.p.median, f.p.p95, f.p.p99,
                          f.p.max, f.set.n, f.set.median, f.set.p95, f.set.p99, f.set.max, wire_floor_ms(v),
                          f.p_error.median, f.p_error.p95, f.p_error.p99, f.p_error.max);
            latency << line;
        }
    }
    std::printf("\nCSV: %s/summary.csv, %s/latency.csv, traces in %s/runs/\n", options.out.c_str(), options.out.c_str(),
                options.out.c_str());
    return 0;
}
