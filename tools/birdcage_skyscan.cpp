// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-skyscan: scans an AZ/EL grid with the dish and streams `az,el,value,time` CSV rows.
// Talks to a running rotctld (our backend loaded) over TCP; see usage() for why.
#include "birdcage_version.hpp"
#include "cli_args.hpp"
#include "skyscan.hpp"

#include "rotctl_client.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>

namespace sc = birdcage::skyscan;
namespace rc = birdcage::rotctl;
using Clock = std::chrono::steady_clock;

namespace {

const char* const usage_text = R"(Usage: birdcage-skyscan --az FROM:TO:STEP --el FROM:TO:STEP [options]
       birdcage-skyscan --convert UPSTREAM_SCAN      (upstream `az el rssi` -> CSV on stdout)

Scans the sky with a Winegard dish through a running rotctld that has the birdcage backend
loaded (e.g. `LD_PRELOAD=libhamlib-winegard.so rotctld -m 90105 -r /dev/ttyUSB0`), and writes
one CSV row `az,el,value,time` per grid point as soon as it is measured.

Start that rotctld with `-C pointing=none`: in the G2's default predictive mode a scan's
stepping targets look like a slow satellite and the dish is aimed ahead of them.

Why rotctld and not the serial port: rotctld owns the port while it runs (a second opener would
interleave bytes with it), and the backend already enters the tuner menu between moves, guards
the hazards and keeps the cable wrap; a scan can then run next to a tracking client. It speaks
rotctld's text protocol itself because Hamlib 4.5.4's NET rotator (`rotctl -m 2`) cannot name a
backend's extension levels such as RSSI.

  --az FROM:TO:STEP   azimuth columns (degrees), scanned in ascending order
  --el FROM:TO:STEP   elevations; up in one column, down in the next (serpentine)
  --samples N         reads averaged per point (RSSI_SAMPLES, 1..100; default 10)
  --lnb 13|18         LNB supply before scanning (13 V = the upstream scans' setting)
  --out FILE          write the CSV here (default: stdout)
  --resume            keep FILE's rows (ours or the upstream format) and scan only the rest
  --host H --port N   rotctld address (default 127.0.0.1 4533)
  --tolerance DEG     arrival tolerance before reading (default 0.2)
  --help              this text
  --version           the program's version

Progress and an ETA go to stderr. Only `P`, `p`, `V` and `v` are sent: never the firmware's
own ADC `scan` (a documented deadlock).
)";

// A usage error: one line on stderr, exit status 2.
int usage_error(const std::string& message) {
    std::cerr << "birdcage-skyscan: " << message << " (see --help)\n";
    return 2;
}

std::string utc_now() {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buffer[32];
    std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
    return buffer;
}

std::string duration_text(double seconds) {
    const long s = std::lround(std::max(0.0, seconds));
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
    return buffer;
}

double az_distance(double a, double b) {
    return std::fabs(std::remainder(a - b, 360.0));
}

// Waits until two successive `p` agree with the target: set_position returns at once, and a
// reading asked before the move starts would measure the old direction.
// A dish that rests elsewhere for this long has been aimed elsewhere (pointing=predictive).
constexpr auto resting_elsewhere = std::chrono::seconds(5);

bool arrive(rc::Client& rot, const sc::Point& target, double tolerance) {
    const auto deadline = Clock::now() + std::chrono::minutes(3);
    int agreeing = 0;
    std::pair<double, double> last{-1000, -1000};
    auto last_change = Clock::now();
    while (Clock::now() < deadline) {
        double az = 0, el = 0;
        const int got = rot.get_position(az, el);
        if (!rot.connected())
            return false;
        if (got == 0) {
            agreeing =
                az_distance(az, target.az) <= tolerance && std::fabs(el - target.el) <= tolerance ? agreeing + 1 : 0;
            if (agreeing >= 2)
                return true;
            if (std::pair{az, el} != last) {
                last = {az, el};
                last_change = Clock::now();
            } else if (Clock::now() - last_change > resting_elsewhere) {
                std::fprintf(stderr,
                             "\nbirdcage-skyscan: the dish rests at %.2f %.2f instead; was rotctld started "
                             "with -C pointing=none?\n",
                             az, el);
                return false;
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
}

int convert(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::cerr << "birdcage-skyscan: cannot read " << path << "\n";
        return 1;
    }
    std::stringstream text;
    text << in.rdbuf();
    std::cout << "az,el,value,time\n";
    for (const auto& row : sc::parse_scan(text.str()))
        std::cout << sc::format_row(row) << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    std::optional<sc::Range> az, el;
    int samples = 10;
    std::optional<int> lnb;
    std::string out_path, host = "127.0.0.1", convert_path;
    int port = 4533;
    bool resume = false;
    double tolerance = 0.2;
    birdcage::cli::ArgCursor args(argc, argv);
    while (args.next()) {
        const std::string& arg = args.flag();
        const bool inline_value = args.has_inline_value();
        auto value = [&] { return args.value(); };
        if (arg == "--help" || arg == "-h") {
            std::cout << usage_text;
            return 0;
        } else if (arg == "--version") {
            std::cout << "birdcage-skyscan " BIRDCAGE_VERSION "\n";
            return 0;
        } else if ((arg == "--resume") && inline_value) {
            return usage_error(arg + " takes no value");
        } else if (arg == "--resume") {
            resume = true;
        } else if (arg == "--az" || arg == "--el") {
            const auto v = value();
            const auto range = v ? sc::parse_range(*v) : std::nullopt;
            if (!range)
                return usage_error(arg + " needs FROM:TO:STEP with FROM <= TO and STEP > 0");
            (arg == "--az" ? az : el) = range;
        } else if (arg == "--samples" || arg == "--lnb" || arg == "--port") {
            const auto v = value();
            char* end = nullptr;
            const long n = v ? std::strtol(v->c_str(), &end, 10) : 0;
            if (!v || *end != '\0')
                return usage_error(arg + " needs a whole number");
            if (arg == "--samples") {
                if (n < 1 || n > 100)
                    return usage_error("--samples is 1..100");
                samples = static_cast<int>(n);
            } else if (arg == "--lnb") {
                if (n != 13 && n != 18)
                    return usage_error("--lnb is 13 or 18");
                lnb = static_cast<int>(n);
            } else {
                if (n < 1 || n > 65535)
                    return usage_error("--port is 1..65535");
                port = static_cast<int>(n);
            }
        } else if (arg == "--out" || arg == "--host" || arg == "--convert" || arg == "--tolerance") {
            const auto v = value();
            if (!v)
                return usage_error(arg + " needs a value");
            if (arg == "--out")
                out_path = *v;
            if (arg == "--host")
                host = *v;
            if (arg == "--convert")
                convert_path = *v;
            if (arg == "--tolerance") {
                tolerance = std::atof(v->c_str());
                if (!(tolerance > 0))
                    return usage_error("--tolerance must be positive");
            }
        } else {
            return usage_error("unknown argument '" + arg + "'");
        }
    }
    if (!convert_path.empty())
        return convert(convert_path);
    if (!az || !el)
        return usage_error("--az and --el are required");
    if (resume && out_path.empty())
        return usage_error("--resume needs --out FILE");

    const std::vector<sc::Point> plan = sc::serpentine(*az, *el);
    std::vector<sc::Point> todo = plan;
    std::ofstream file;
    if (!out_path.empty()) {
        std::string existing;
        if (resume) {
            std::ifstream in(out_path, std::ios::binary);
            std::stringstream text;
            text << in.rdbuf();
            existing = text.str();
            existing.resize(sc::complete_length(existing));  // drop a row cut off by the interruption
            todo = sc::remaining(plan, sc::parse_scan(existing));
        }
        file.open(out_path, std::ios::binary | std::ios::trunc);
        if (!file) {
            std::cerr << "birdcage-skyscan: cannot write " << out_path << "\n";
            return 1;
        }
        file << (existing.empty() ? "az,el,value,time\n" : existing);
        file.flush();
        std::cerr << "birdcage-skyscan: " << plan.size() - todo.size() << " of " << plan.size() << " points already in "
                  << out_path << "\n";
    } else {
        std::cout << "az,el,value,time\n";
    }
    std::ostream& out = out_path.empty() ? std::cout : file;

    // The plain protocol: a scan takes minutes to hours, and nothing of the extended one is needed.
    rc::Client rot(host, port, rc::Options{.protocol = rc::Protocol::plain, .timeout = std::chrono::minutes(3)});
    if (std::string why; !rot.connect(&why)) {
        std::cerr << "birdcage-skyscan: cannot connect to rotctld at " << host << ":" << port << " (" << why << ")\n";
        return 1;
    }
    if (const int r = rot.set_level(rc::level::rssi_samples, samples); r != 0) {
        std::cerr << "birdcage-skyscan: rotctld refused RSSI_SAMPLES (" << rc::error_name(r) << ": "
                  << rc::error_text(r) << "); is the birdcage backend loaded and the dish a G2?\n";
        return 1;
    }
    if (lnb) {
        if (const int r = rot.set_level(rc::level::lnb, *lnb); r != 0) {
            std::cerr << "birdcage-skyscan: setting the LNB supply failed (" << rc::error_text(r) << ")\n";
            return 1;
        }
    }

    const auto started = Clock::now();
    for (std::size_t n = 0; n < todo.size(); ++n) {
        const sc::Point& point = todo[n];
        char target[64];
        std::snprintf(target, sizeof target, "%.2f %.2f", point.az, point.el);
        if (rot.set_position(point.az, point.el) != 0 || !arrive(rot, point, tolerance)) {
            std::cerr << "\nbirdcage-skyscan: the dish did not reach " << target << "\n";
            return 1;
        }
        double value = 0;
        if (const int r = rot.get_level(rc::level::rssi, value); r != 0) {
            std::cerr << "\nbirdcage-skyscan: no RSSI at " << target << " ("
                      << (rot.connected() ? rc::error_text(r) : "connection lost") << ")\n";
            return 1;
        }
        const sc::Row row{point.az, point.el, value, utc_now()};
        out << sc::format_row(row) << "\n";
        out.flush();
        const double elapsed = std::chrono::duration<double>(Clock::now() - started).count();
        const double eta = elapsed / static_cast<double>(n + 1) * static_cast<double>(todo.size() - n - 1);
        std::fprintf(stderr, "\rbirdcage-skyscan: %zu/%zu  az %7.2f el %6.2f  value %6g  ETA %s ",
                     plan.size() - todo.size() + n + 1, plan.size(), point.az, point.el, row.value,
                     duration_text(eta).c_str());
    }
    std::fprintf(stderr, "\nbirdcage-skyscan: done, %zu points in %s\n", todo.size(),
                 duration_text(std::chrono::duration<double>(Clock::now() - started).count()).c_str());
    return 0;
}
