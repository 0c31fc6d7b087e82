// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Benchmark (prints figures, asserts nothing): round trip of `p` and `P` through the stock rotctld
// with the backend preloaded, against the emulated dish, over one TCP connection like Gpredict's.
//   build/tests/e2e/bench_rotctld [iterations]
#include "harness.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {

struct Figures {
    double median_ms, p95_ms, p99_ms, max_ms;
};

Figures summarise(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    auto at = [&](double q) { return ms[static_cast<std::size_t>(q * static_cast<double>(ms.size() - 1))]; };
    return {at(0.5), at(0.95), at(0.99), ms.back()};
}

double time_one(e2e::RotctldConnection& c, const std::string& cmd, int lines) {
    const auto t0 = Clock::now();
    c.ask(cmd, lines);
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    const int iterations = argc > 1 ? std::atoi(argv[1]) : 500;
    struct Case {
        birdcage::sim::Variant variant;
        int model;
        const char* name;
    } cases[] = {{birdcage::sim::Variant::travler_hal205, 90102, "Trav'ler HAL 2.05"},
                 {birdcage::sim::Variant::carryout_g2, 90105, "Carryout G2"}};

    std::printf("rotctld round trip over loopback TCP, %d commands each (emulated dish, Hamlib %s)\n", iterations,
                "from /usr/bin/rotctld");
    std::printf("%-20s %-4s %9s %9s %9s %9s\n", "model", "cmd", "median", "p95", "p99", "max");
    for (const Case& c : cases) {
        birdcage::sim::Options o;
        o.variant = c.variant;
        o.time_scale = 1.0;
        o.start_az = 150;
        o.start_el = 40;
        e2e::Rig rig(o, c.model, {"-C", "leapfrog=0"});
        e2e::RotctldConnection conn(rig.port());
        std::vector<double> p_ms, set_ms;
        for (int i = 0; i < iterations; ++i) {
            p_ms.push_back(time_one(conn, "p", 2));
        }
        // Small steps around the start, as a tracking client sends them.
        for (int i = 0; i < iterations; ++i) {
            char cmd[64];
            std::snprintf(cmd, sizeof cmd, "P %.2f %.2f", 150.0 + (i % 20) * 0.1, 40.0 + (i % 10) * 0.1);
            set_ms.push_back(time_one(conn, cmd, 1));
        }
        for (auto [label, data] : {std::pair{"p", &p_ms}, std::pair{"P", &set_ms}}) {
            const Figures f = summarise(*data);
            std::printf("%-20s %-4s %7.3fms %7.3fms %7.3fms %7.3fms\n", c.name, label, f.median_ms, f.p95_ms, f.p99_ms,
                        f.max_ms);
        }
    }
    return 0;
}
