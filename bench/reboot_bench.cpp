// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Reboot benchmark (docs/benchmarks.md, "A Trav'ler reboot mid-pass"): a Trav'ler power-cycled
// mid-pass while a Gpredict-like client tracks through the stock rotctld with the backend
// preloaded. A program, not a test: it measures and prints, asserts nothing.
//
//   reboot_bench [--variants hal000,hal205] [--boot-moves park,home-return,none] [--runs N]
//                [--scale K] [--pass NAME] [--from S] [--reboot-at S] [--to S] [--late-from S]
//                [--no-reboot] [--backend FILE]
//
// Per run it measures, on the emulator's true position and its console traffic:
//   * the wall time from the dish's ready line (`NoGPS`) to the command that stops its TV search
//     (`kill Search`; HAL 2.05: `s` in its `ngsearch` menu);
//   * the RMS of the dish against the satellite over the window, with the reboot in it, and the
//     same without the samples from the power cut to the ready line (the dish is not there to
//     command then: what its firmware does in that time is outside the backend's control);
//   * the RMS before the reboot and after the dish is back on the satellite (within 1 deg), so
//     what was learnt before the reboot (lead, pointing mode, motion, orbit) shows if it is lost;
//   * the RMS from --late-from to the end of the window, the same stretch of the pass in a run with
//     the reboot and in one without (--no-reboot): tracking there differs from tracking before the
//     reboot because the pass does (the satellite climbs and speeds up), so this is the comparison
//     that tells lost state from geometry;
//   * the goal the backend can answer for: back on the satellite (within 1 deg for 5 s) after the
//     ready line, against the motors' travel time from where the calibration left the dish to where
//     the satellite is then (the emulated motors' move time, AZ then EL, start-up delays included),
//     and the slack between the two (goal: at most 1 s).
// --boot-moves runs each reading of the Trav'ler's unknown power-up calibration (sim/README.md,
// `travler_boot_moves`; docs/firmware.md §3.2).
// The default pass and window put the reboot where the `park` calibration (AZ 0, EL 45, an
// INVENTED boot move, sim/src/variants.cpp) is short: sso-85 rising through AZ 17-25 toward the
// culmination, so the reboot's cost is the boot and the search, not a turn of the cable wrap.
// Real speed is --scale 1 (the default): a run takes the window's length in real time.
// --backend FILE is the backend every rotctld preloads (default: the libhamlib-winegard.so built
// beside this program, found from where the program is; it refuses to start when there is none, so
// a copy of the program measures the backend it is given).
#include "gpredict_client.hpp"
#include "harness.hpp"
#include "pass.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace std::chrono_literals;
using birdcage::sim::Variant;
using Steady = std::chrono::steady_clock;

namespace {

struct Dish {
    std::string name;
    Variant variant;
    int model;
    double el_min, el_max;
    std::string ready_line;    // the documented last boot line
    std::string stop_command;  // the command that stops the TV search (docs/firmware.md 3.6, 4.3)
};

const std::vector<Dish>& dishes() {
    static const std::vector<Dish> all{
        {"hal000", Variant::travler_hal000, 90101, 15.0, 90.0, "NoGPS", "kill Search\r"},
        {"hal205", Variant::travler_hal205, 90102, 15.0, 90.0, "NoGPS", "s\r"},
    };
    return all;
}

struct Settings {
    std::vector<std::string> variants{"hal000", "hal205"};
    std::vector<std::string> boot_moves{"park"};
    int runs = 3;
    double scale = 1.0;
    std::string pass = "sso-85";
    double from = 300.0, reboot_at = 370.0, to = 440.0;  // pass clock, seconds
    double late_from = 400.0;                            // every reading is back on the satellite by then
    bool reboot = true;
    std::string backend;  // --backend; empty: the backend built beside this program
};

// Console traffic with the wall time it crossed at, from the emulator's console thread.
class Traffic {
public:
    void record(bool from_client, std::string_view bytes) {
        std::lock_guard lock(mutex_);
        chunks_.push_back({Steady::now(), from_client, std::string(bytes)});
    }
    struct Chunk {
        Steady::time_point at;
        bool from_client;
        std::string bytes;
    };
    std::vector<Chunk> since(Steady::time_point start) const {
        std::lock_guard lock(mutex_);
        std::vector<Chunk> out;
        for (const Chunk& c : chunks_) {
            if (c.at >= start) {
                out.push_back(c);
            }
        }
        return out;
    }

private:
    mutable std::mutex mutex_;
    std::vector<Chunk> chunks_;
};

struct RunResult {
    double ready_to_stop_s = NAN;  // wall time, NoGPS to the search stop
    double rms_deg = 0.0, before_deg = 0.0, after_deg = 0.0, max_deg = 0.0;
    double available_deg = 0.0;  // the window without the power cut to the ready line
    double late_deg = 0.0;       // --late-from to the end of the window
    double ready_after_s = NAN;  // pass seconds from the power cut to the ready line
    double back_after_s = NAN;   // pass seconds from the reboot until the dish is within 1 deg again
    double travel_s = NAN;       // the motors' move time from the dish at the ready line to the satellite then
    int error_streak = 0;
    bool disengaged = false;
};

double rms(const std::vector<double>& errors) {
    double sum = 0.0;
    for (double e : errors) {
        sum += e * e;
    }
    return errors.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(errors.size()));
}

RunResult run_once(const Dish& d, birdcage::sim::TravlerBootMoves boot_moves, const Settings& s) {
    const bench::Pass pass = bench::Pass::load(std::string(BIRDCAGE_BENCH_PASSES_DIR) + "/" + s.pass + ".csv");
    // The client engages 30 s before the window, as docs/gpredict.md tells users to.
    const double start = s.from - 30.0;
    const bench::Direction at_start = pass.at(start);
    auto options = e2e::dish_options(d.variant, at_start.az, std::clamp(at_start.el, d.el_min, d.el_max), s.scale);
    options.pace_at_line_rate = true;
    options.travler_boot_moves = boot_moves;
    Traffic traffic;
    options.trace = [&traffic](bool from_client, std::string_view bytes) { traffic.record(from_client, bytes); };
    char scale_conf[48], latitude_conf[48];
    std::snprintf(scale_conf, sizeof scale_conf, "time_scale=%g", s.scale);
    std::snprintf(latitude_conf, sizeof latitude_conf, "latitude=%.4f", pass.site_latitude());
    e2e::Rig rig(options, d.model, {"-C", scale_conf, "-C", latitude_conf});

    bench::ClientSettings client_settings;
    client_settings.threshold_deg = 0.5;  // docs/gpredict.md's setting
    client_settings.min_el = d.el_min;
    client_settings.max_el = d.el_max;
    bench::GpredictClient client(pass, client_settings, rig.dish(), s.scale, rig.port(), start);
    bench::ClientRecord record;
    std::thread tracking([&] { record = client.run_until(s.to); });

    auto pass_now = [&] { return client.pass_time_of(rig.dish().sim_time()); };
    Steady::time_point cycled_at{};
    if (s.reboot) {
        e2e::wait_until([&] { return pass_now() >= s.reboot_at; },
                        std::chrono::seconds(static_cast<int>(s.reboot_at - start + 600)));
        cycled_at = Steady::now();
        rig.dish().power_cycle();
    }
    tracking.join();

    RunResult r;
    r.error_streak = record.longest_error_streak;
    r.disengaged = record.disengaged;
    if (s.reboot) {
        // The ready line from the dish after the power cycle, then the stop from the backend.
        std::string dish_text, client_text;
        std::optional<Steady::time_point> ready_at;
        for (const auto& chunk : traffic.since(cycled_at)) {
            if (!chunk.from_client && !ready_at) {
                dish_text += chunk.bytes;
                if (dish_text.find(d.ready_line) != std::string::npos) {
                    ready_at = chunk.at;
                    r.ready_after_s = std::chrono::duration<double>(chunk.at - cycled_at).count() * s.scale;
                }
            } else if (chunk.from_client && ready_at) {
                client_text += chunk.bytes;
                const std::size_t stop = client_text.find(d.stop_command);
                // HAL 2.05's `s` counts only after `ngsearch` took it into that menu.
                const bool in_place =
                    d.stop_command != "s\r" || (stop != std::string::npos && client_text.find("ngsearch\r") < stop);
                if (stop != std::string::npos && in_place) {
                    r.ready_to_stop_s = std::chrono::duration<double>(chunk.at - *ready_at).count();
                    break;
                }
            }
        }
    }

    // Ground truth: the emulator's history, held between samples, on the pass clock.
    const std::vector<birdcage::sim::Sample> history = rig.dish().history();
    std::size_t h = 0;
    std::vector<double> all, before, after, available, late;
    bool back = !s.reboot;
    constexpr double grid_s = 0.1;
    for (int i = 0; s.from + i * grid_s <= s.to; ++i) {
        const double t = s.from + i * grid_s;
        while (h + 1 < history.size() && client.pass_time_of(history[h + 1].t) <= t) {
            ++h;
        }
        const bench::Direction sat = pass.at(t);
        if (sat.el < d.el_min || sat.el > d.el_max) {
            continue;
        }
        const double error = bench::angle_between(sat, {history[h].az, history[h].el});
        all.push_back(error);
        r.max_deg = std::max(r.max_deg, error);
        // A ready line never seen counts the rest of the window as unavailable.
        if (!s.reboot || t < s.reboot_at || (!std::isnan(r.ready_after_s) && t >= s.reboot_at + r.ready_after_s)) {
            available.push_back(error);
        }
        if (t >= s.late_from) {
            late.push_back(error);
        }
        if (t < s.reboot_at) {
            before.push_back(error);
        } else if (s.reboot) {
            // Back once within 1 deg for 5 s: the boot, the search and the return are over.
            if (!back && error <= 1.0) {
                bool holds = true;
                for (std::size_t k = h; k < history.size() && client.pass_time_of(history[k].t) <= t + 5.0; ++k) {
                    holds = holds && bench::angle_between(pass.at(client.pass_time_of(history[k].t)),
                                                          {history[k].az, history[k].el}) <= 1.0;
                }
                if (holds) {
                    back = true;
                    r.back_after_s = t - s.reboot_at;
                    // Where the calibration left the dish at the ready line, and where the satellite
                    // is when the dish is back on it: what the motors must cover, one axis at a time.
                    const double ready_t = s.reboot_at + r.ready_after_s;
                    std::size_t at_ready = 0;
                    while (at_ready + 1 < history.size() && client.pass_time_of(history[at_ready + 1].t) <= ready_t) {
                        ++at_ready;
                    }
                    if (!std::isnan(r.ready_after_s)) {
                        const birdcage::sim::Sample& from = history[at_ready];
                        const double el_to = std::clamp(sat.el, d.el_min, d.el_max);
                        r.travel_s = rig.dish().move_time(0, e2e::angle_between(from.az, sat.az)) +
                                     rig.dish().move_time(1, std::fabs(el_to - from.el));
                    }
                }
            }
            if (back) {
                after.push_back(error);
            }
        }
    }
    r.rms_deg = rms(all);
    r.before_deg = rms(before);
    r.after_deg = rms(after);
    r.available_deg = rms(available);
    r.late_deg = rms(late);
    return r;
}

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
        out.push_back(item);
    }
    return out;
}

Settings parse(int argc, char** argv) {
    Settings s;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                throw std::runtime_error(arg + " needs a value");
            }
            return argv[++i];
        };
        if (arg == "--variants") {
            s.variants = split(value());
        } else if (arg == "--boot-moves") {
            s.boot_moves = split(value());
        } else if (arg == "--late-from") {
            s.late_from = std::stod(value());
        } else if (arg == "--runs") {
            s.runs = std::stoi(value());
        } else if (arg == "--scale") {
            s.scale = std::stod(value());
        } else if (arg == "--pass") {
            s.pass = value();
        } else if (arg == "--from") {
            s.from = std::stod(value());
        } else if (arg == "--reboot-at") {
            s.reboot_at = std::stod(value());
        } else if (arg == "--to") {
            s.to = std::stod(value());
        } else if (arg == "--no-reboot") {
            s.reboot = false;
        } else if (arg == "--backend") {
            s.backend = value();
        } else {
            throw std::runtime_error("unknown argument " + arg +
                                     " (--variants, --boot-moves, --runs, --scale, --pass, --from, --reboot-at, --to,"
                                     " --late-from, --no-reboot, --backend)");
        }
    }
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        Settings s = parse(argc, argv);
        // Beside this program: the build tree's layout (bench/ and src/hamlib/ under one build dir).
        if (s.backend.empty()) {
            const std::string here = e2e::executable_directory();
            s.backend = here.empty()
                            ? std::string()
                            : (std::filesystem::path(here) / BIRDCAGE_BENCH_BACKEND).lexically_normal().string();
        }
        if (s.backend.empty() || !std::filesystem::is_regular_file(s.backend)) {
            std::fprintf(
                stderr,
                "reboot_bench: no backend at %s: name the libhamlib-winegard.so to preload with --backend FILE\n",
                s.backend.empty() ? "(this program's directory is unknown)" : s.backend.c_str());
            return 2;
        }
        e2e::use_backend_library(std::filesystem::absolute(s.backend).string());
        std::fprintf(stderr, "reboot_bench: backend %s\n", e2e::backend_library().c_str());  // stdout: the table
        std::printf(
            "variant boot_moves run ready_after_s ready_to_stop_s rms_deg available_deg before_deg after_deg "
            "late_deg max_deg back_after_s back_after_ready_s travel_s slack_s error_streak disengaged\n");
        for (const std::string& name : s.variants) {
            const auto d =
                std::find_if(dishes().begin(), dishes().end(), [&](const Dish& x) { return x.name == name; });
            if (d == dishes().end()) {
                throw std::runtime_error("unknown variant " + name + " (hal000, hal205)");
            }
            for (const std::string& reading : s.boot_moves) {
                const auto moves = birdcage::sim::parse_travler_boot_moves(reading);
                if (!moves) {
                    throw std::runtime_error("unknown boot moves " + reading + " (park, home-return, none)");
                }
                for (int run = 1; run <= s.runs; ++run) {
                    const RunResult r = run_once(*d, *moves, s);
                    const double back_after_ready = r.back_after_s - r.ready_after_s;
                    std::printf("%s %s %d %.1f %.3f %.2f %.2f %.2f %.2f %.2f %.1f %.1f %.2f %.2f %.2f %d %s\n",
                                name.c_str(), reading.c_str(), run, r.ready_after_s, r.ready_to_stop_s, r.rms_deg,
                                r.available_deg, r.before_deg, r.after_deg, r.late_deg, r.max_deg, r.back_after_s,
                                back_after_ready, r.travel_s, back_after_ready - r.travel_s, r.error_streak,
                                r.disengaged ? "yes" : "no");
                    std::fflush(stdout);
                }
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "reboot_bench: %s\n", e.what());
        return 2;
    }
    return 0;
}
