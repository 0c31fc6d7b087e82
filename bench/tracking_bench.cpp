// Tracking benchmark (issue 5): realistic LEO passes, a Gpredict-like client driving the stock
// rotctld with the backend preloaded, the dish emulator's true position as ground truth.
// Prints a table and writes CSV (summary + one trace per run) for bench/plot.py.
// Measures and reports; asserts nothing. See docs/benchmarks.md.
//
//   tracking_bench [--scale K] [--jobs N] [--passes a,b] [--variants g2,hal205]
//                  [--modes none,leapfrog] [--thresholds 0.5,5] [--window SECONDS] [--out DIR]
#include "gpredict_client.hpp"
#include "harness.hpp"
#include "pass.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using bench::Direction;
using birdcage::sim::Variant;

// The dishes benchmarked. The wire floor is the `a` position query as this variant's console
// answers it (2 bytes out, the echoed reply and prompt back), 10 bits per byte at its baud rate
// (notes/tracking.md §1.1) — what a synchronous `p` would cost at best on a real serial line; the
// emulator's pty has no baud rate, so this is computed, not measured.
struct VariantRow {
    const char* key;
    Variant variant;
    int model;
    const char* label;
    int baud;
    double el_min, el_max;
    const char* position_exchange;  // bytes on the wire for one `a` query, both directions
};
const VariantRow variant_rows[] = {
    {"g2", Variant::carryout_g2, 90105, "Carryout G2", 115200, 18.0, 65.0,
     "a\r" "a\r\nAngle[0] = 180.00\r\nAngle[1] = 45.00\r\nMOT>"},
    {"hal205", Variant::travler_hal205, 90102, "Trav'ler HAL 2.05", 57600, 15.0, 90.0,
     "a\r" "a\r\nAZ = 180.00 EL = 45.00 SK = 0.00\r\nMOTOR>"},
};

double wire_floor_ms(const VariantRow& v) {
    const double bytes = static_cast<double>(std::string(v.position_exchange).size());
    return bytes * 10.0 / v.baud * 1000.0;
}

// Pointing modes: one row per conf setting. The predictive mode of issue 5 becomes one more row,
// e.g. {"predictive", "predictive", {"-C", "pointing=predictive"}}.
struct ModeRow {
    const char* key;
    const char* label;
    std::vector<std::string> rotctld_args;
};
const std::vector<ModeRow> mode_rows = {
    {"none", "no compensation", {"-C", "leapfrog=0"}},
    {"leapfrog", "leapfrog (seed thresholds, EL bug fixed)", {"-C", "leapfrog=1"}},
};

struct Options {
    double scale = 10.0;
    int jobs = 2;
    std::vector<std::string> passes = {"iss-20", "iss-45", "iss-70", "iss-85",
                                       "sso-20", "sso-45", "sso-70", "sso-85"};
    std::vector<std::string> variants = {"g2", "hal205"};
    std::vector<std::string> modes = {"none", "leapfrog"};
    std::vector<double> thresholds = {0.5, 5.0};
    double window_s = 0.0;  // > 0: only this many seconds around the TCA
    std::string out = "bench-out";
    std::string passes_dir = BIRDCAGE_BENCH_PASSES_DIR;
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
    auto at = [&v](double q) { return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))]; };
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
};

struct RunResult {
    RunSpec spec;
    Figures error;           // degrees, satellite inside the dish's elevation limits
    double tracked_s = 0;    // seconds of the pass inside the limits
    std::size_t motor_commands = 0;
    std::size_t set_commands = 0;  // P sent by the client
    double extra_az_travel = 0;    // dish azimuth travel beyond the satellite's, degrees
    bool unwound = false;
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
        } else if (arg == "--window") {
            o.window_s = std::stod(value());
        } else if (arg == "--out") {
            o.out = value();
        } else if (arg == "--passes-dir") {
            o.passes_dir = value();
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
    return std::string(s.pass->name()) + "_" + s.variant->key + "_" + s.mode->key + "_thr" + thr;
}

RunResult run_one(const RunSpec& spec, const Options& options) {
    RunResult result{spec, {}, 0, 0, 0, 0, false, {}, {}, {}, 0, 0, {}};
    const auto wall_start = std::chrono::steady_clock::now();
    const bench::Pass& pass = *spec.pass;
    const VariantRow& v = *spec.variant;

    // The run covers the pass from a little below the dish's lowest elevation (Gpredict has been
    // holding the dish at the AOS azimuth, lowest elevation, since before AOS) until the satellite
    // sets below it: the part that is measured, with a few seconds of approach.
    double start = std::max(pass.aos(), pass.first_time_above(v.el_min - 6.0));
    double end = pass.last_time_above(v.el_min) + 5.0;
    if (options.window_s > 0.0) {
        start = std::max(start, pass.tca() - options.window_s / 2.0);
        end = std::min(end, pass.tca() + options.window_s / 2.0);
    }
    const Direction at_start = pass.at(start);
    birdcage::sim::Options dish;
    dish.variant = v.variant;
    dish.time_scale = options.scale;
    dish.start_az = options.window_s > 0.0 ? at_start.az : pass.aos_az();
    dish.start_el = std::clamp(at_start.el, v.el_min, v.el_max);

    // One rig comes up at a time: e2e::free_tcp_port() releases the port it found, so two rigs
    // starting together could be handed the same one.
    static std::mutex rig_start_mutex;
    std::unique_lock start_lock(rig_start_mutex);
    e2e::Rig rig(dish, v.model, spec.mode->rotctld_args);
    start_lock.unlock();
    const std::size_t commands_before = rig.dish().received_commands().size();

    bench::ClientSettings settings;
    settings.threshold_deg = spec.threshold;
    settings.min_el = v.el_min;
    settings.max_el = v.el_max;
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

    std::filesystem::create_directories(options.out + "/runs");
    std::ofstream trace(options.out + "/runs/" + run_name(spec) + ".csv");
    trace << "t,sat_az,sat_el,dish_az,dish_el,error_deg,in_limits\n";
    std::vector<double> errors;
    constexpr double grid_s = 0.1;
    double dish_travel = 0, sat_travel = 0;
    Direction previous_dish = dish_at(start), previous_sat = pass.at(start);
    const double initial_offset = std::fabs(bench::az_difference(previous_dish.az, previous_sat.az));
    int row = 0;
    for (double t = start; t <= end; t += grid_s, ++row) {
        const Direction sat = pass.at(t);
        const Direction pointing = dish_at(t);
        const double error = bench::angle_between(sat, pointing);
        const bool inside = sat.el >= v.el_min && sat.el <= v.el_max;
        if (inside) {
            errors.push_back(error);
        }
        dish_travel += std::fabs(bench::az_difference(pointing.az, previous_dish.az));
        sat_travel += std::fabs(bench::az_difference(sat.az, previous_sat.az));
        previous_dish = pointing;
        previous_sat = sat;
        if (row % 2 == 0) {  // 0.2 s in the file is plenty for plots
            char line[160];
            std::snprintf(line, sizeof line, "%.2f,%.3f,%.3f,%.3f,%.3f,%.4f,%d\n", t, sat.az, sat.el, pointing.az,
                          pointing.el, error, inside ? 1 : 0);
            trace << line;
        }
    }
    // Dish travel counted on the 0.1 s grid: an unwind (≥ 65 °/s, so ≤ 6.5° per step) is seen whole.
    result.extra_az_travel = dish_travel - sat_travel - initial_offset;
    result.unwound = result.extra_az_travel > 180.0;
    result.error = figures_of(errors);
    result.tracked_s = static_cast<double>(errors.size()) * grid_s;

    std::ofstream targets(options.out + "/runs/" + run_name(spec) + "_P.csv");
    targets << "t,az,el\n";
    for (const auto& s : record.sent_targets) {
        targets << s.t << ',' << s.dir.az << ',' << s.dir.el << '\n';
    }
    result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return result;
}

void print_header() {
    std::printf("%-7s %-7s %-9s %4s | %6s %6s %6s | %5s %4s %7s | %6s %6s %6s | %6s %6s | %6s\n", "pass", "variant",
                "mode", "thr", "RMS", "p95", "max", "motor", "P", "xtraAz", "p med", "p p99", "p max", "P med",
                "P p99", "|p|p95");
    std::printf("%-7s %-7s %-9s %4s | %6s %6s %6s | %5s %4s %7s | %6s %6s %6s | %6s %6s | %6s\n", "", "", "", "deg",
                "deg", "deg", "deg", "cmds", "sent", "deg", "ms", "ms", "ms", "ms", "ms", "deg");
}

void print_row(const RunResult& r) {
    const Figures p = figures_of(r.p_ms), set = figures_of(r.set_ms), pe = figures_of(r.p_error_deg);
    std::printf("%-7s %-7s %-9s %4g | %6.3f %6.3f %6.3f | %5zu %4zu %6.0f%s | %6.3f %6.3f %6.3f | %6.3f %6.3f | %6.3f\n",
                r.spec.pass->name().c_str(), r.spec.variant->key, r.spec.mode->key, r.spec.threshold, r.error.rms,
                r.error.p95, r.error.max, r.motor_commands, r.set_commands, r.extra_az_travel, r.unwound ? "U" : " ",
                p.median, p.p99, p.max, set.median, set.p99, pe.p95);
    std::fflush(stdout);
}

} // namespace

int main(int argc, char** argv) {
    Options options;
    try {
        options = parse(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "tracking_bench: %s\n", e.what());
        return 2;
    }
    std::vector<bench::Pass> passes;
    for (const std::string& name : options.passes) {
        passes.push_back(bench::Pass::load(options.passes_dir + "/" + name + ".csv"));
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
                const auto m = std::find_if(mode_rows.begin(), mode_rows.end(),
                                            [&](const ModeRow& r) { return mk == r.key; });
                if (m == mode_rows.end()) {
                    std::fprintf(stderr, "tracking_bench: unknown mode %s\n", mk.c_str());
                    return 2;
                }
                for (double thr : options.thresholds) {
                    specs.push_back({&pass, &*v, &*m, thr});
                }
            }
        }
    }

    std::printf("tracking benchmark: %zu runs, time scale %gx, %d in parallel%s\n", specs.size(), options.scale,
                options.jobs, options.window_s > 0 ? (", window " + std::to_string(options.window_s) + " s around TCA").c_str() : "");
    std::printf("error = great-circle angle satellite vs true dish direction while the satellite is inside the dish's\n"
                "elevation limits; U = the dish azimuth unwound (travelled > 180 deg more than the satellite)\n");
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
                    results[i].error_text = e.what();
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
    summary << "pass,peak_el,crosses_north,variant,mode,threshold,scale,window_s,tracked_s,rms,p95,max,motor_commands,"
               "set_commands,extra_az_travel,unwound,p_median_ms,p_p95_ms,p_p99_ms,p_max_ms,P_median_ms,P_p95_ms,"
               "P_p99_ms,P_max_ms,p_error_p95_deg,p_error_max_deg,wire_floor_ms,failed_replies,wall_s\n";
    for (const RunResult& r : results) {
        if (!r.error_text.empty()) {
            continue;
        }
        const Figures p = figures_of(r.p_ms), set = figures_of(r.set_ms), pe = figures_of(r.p_error_deg);
        char line[512];
        std::snprintf(line, sizeof line,
                      "%s,%.2f,%d,%s,%s,%g,%g,%g,%.1f,%.4f,%.4f,%.4f,%zu,%zu,%.1f,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,"
                      "%.4f,%.4f,%.4f,%.2f,%u,%.1f\n",
                      r.spec.pass->name().c_str(), r.spec.pass->peak_el(), r.spec.pass->crosses_north() ? 1 : 0,
                      r.spec.variant->key, r.spec.mode->key, r.spec.threshold, options.scale, options.window_s,
                      r.tracked_s, r.error.rms, r.error.p95, r.error.max, r.motor_commands, r.set_commands,
                      r.extra_az_travel, r.unwound ? 1 : 0, p.median, p.p95, p.p99, p.max, set.median, set.p95,
                      set.p99, set.max, pe.p95, pe.max, wire_floor_ms(*r.spec.variant), r.failed_replies, r.wall_s);
        summary << line;
    }

    // Latency over every run of a variant: the figures the goals are stated in.
    std::printf("\nlatency through rotctld per variant (all runs pooled; wire floor = one `a` query at the baud rate)\n");
    std::printf("%-18s %-3s %7s %7s %7s %7s %7s | %s\n", "variant", "cmd", "n", "median", "p95", "p99", "max",
                "wire floor");
    for (const VariantRow& v : variant_rows) {
        std::vector<double> p, set, pe;
        for (const RunResult& r : results) {
            if (r.error_text.empty() && r.spec.variant == &v) {
                p.insert(p.end(), r.p_ms.begin(), r.p_ms.end());
                set.insert(set.end(), r.set_ms.begin(), r.set_ms.end());
                pe.insert(pe.end(), r.p_error_deg.begin(), r.p_error_deg.end());
            }
        }
        if (p.empty()) {
            continue;
        }
        for (auto [label, data] : {std::pair{"p", &p}, std::pair{"P", &set}}) {
            const Figures f = figures_of(*data);
            std::printf("%-18s %-3s %7zu %6.3fms %6.3fms %6.3fms %6.3fms | %.2f ms (%d baud)\n", v.label, label, f.n,
                        f.median, f.p95, f.p99, f.max, wire_floor_ms(v), v.baud);
        }
        const Figures f = figures_of(pe);
        std::printf("%-18s %-3s %7zu reported-vs-true position: median %.3f deg, p95 %.3f deg, max %.3f deg\n", v.label,
                    "p", f.n, f.median, f.p95, f.max);
    }
    std::printf("\nCSV: %s/summary.csv, traces in %s/runs/\n", options.out.c_str(), options.out.c_str());
    return 0;
}
