// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// End-to-end harness: the dish emulator (in this process), the distribution's unmodified
// /usr/bin/rotctld with our backend preloaded, and clients (stock rotctl -m 2, or raw TCP).
#pragma once

#include <birdcage_sim/emulator.hpp>

#include "rotctl_client.hpp"

#include <sys/types.h>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace e2e {

// Path of the backend library under test: the one this build made (set by CMake), unless a
// program chose another with use_backend_library().
std::string backend_library();
// From now on every rotctld and rotctl this process starts preloads `path` instead (a benchmark's
// --backend: a copied program measures the backend it is given).
void use_backend_library(std::string path);
// The directory of this process's executable (from /proc/self/exe), where a program of the build
// tree finds what was built beside it; empty if it cannot be read.
std::string executable_directory();
// Environment that makes a stock Hamlib program load the backend: LD_PRELOAD (with the sanitizer
// runtime first in a sanitizer build, which a non-instrumented rotctld needs).
std::map<std::string, std::string> preload_environment();

struct CommandResult {
    int exit_code = -1;
    std::string out;
    std::string err;
};

// Runs a program to completion with extra environment variables, capturing stdout and stderr.
CommandResult run(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env = {},
                  std::chrono::milliseconds timeout = std::chrono::seconds(60));

// A child process that is terminated (SIGTERM, then SIGKILL) when this object goes away.
class Child {
public:
    Child(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
          const std::string& log_path);
    ~Child();
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    bool running();
    pid_t pid() const { return pid_; }

private:
    pid_t pid_ = -1;
    bool reaped_ = false;
};

// Waits until predicate() holds, checking every few milliseconds; false at the deadline.
bool wait_until(const std::function<bool()>& predicate, std::chrono::milliseconds timeout);

// The TCP port a process listens on (its first listening socket); 0 while it listens on none.
int listening_tcp_port(pid_t pid);

// An emulator at (az, el), running time_scale times faster than real time.
birdcage::sim::Options dish_options(birdcage::sim::Variant variant, double az = 100.0, double el = 30.0,
                                    double time_scale = 50.0);
// Great-circle-free azimuth distance: |a - b| the short way round, in [0, 180].
double angle_between(double a, double b);
// Great-circle angle between two directions on the sky (az/el degrees), in degrees.
double sky_angle(double az1, double el1, double az2, double el2);
// The dish is at rest within `tolerance` degrees of (az, el).
bool settled_at(birdcage::sim::Emulator& dish, double az, double el, double tolerance = 0.1);
// Every number in a rotctl reply, in order.
std::vector<double> numbers(const std::string& text);

// A line-oriented rotctld client over one TCP connection (like Gpredict's), in the plain protocol;
// the tests read rotctld's raw lines through it. The library's Client is client().
class RotctldConnection {
public:
    explicit RotctldConnection(int port);
    RotctldConnection(const RotctldConnection&) = delete;
    RotctldConnection& operator=(const RotctldConnection&) = delete;
    // Sends one command line and reads until `lines` reply lines have arrived (or the timeout).
    std::string ask(const std::string& command, int lines,
                    std::chrono::milliseconds timeout = std::chrono::seconds(10));
    // Sends bytes as they are (no line ending added); false if the connection is gone.
    bool send_raw(const std::string& bytes);
    // Reads until `lines` reply lines have arrived (or the timeout) and hands exactly those back.
    std::string read_lines(int lines, std::chrono::milliseconds timeout = std::chrono::seconds(10));
    // `p`: the two values, or the RPRT line when the backend answered with an error.
    struct Position {
        bool ok = false;
        double az = 0, el = 0;
        std::string error;  // e.g. "RPRT -5"; empty when nothing arrived
    };
    Position get_position(std::chrono::milliseconds timeout = std::chrono::seconds(5));
    birdcage::rotctl::Client& client() { return client_; }

private:
    birdcage::rotctl::Client client_;
};

// Types console lines into the dish as a user at a terminal would (each line ends with CR), before
// the backend opens the port: e.g. to leave the dish inside a submenu. Waits until the dish has
// read each line and its reply has gone quiet; the reply is read and discarded.
void type_into(birdcage::sim::Emulator& dish, const std::vector<std::string>& lines);

// The dish received no word of the core's hazard rule (docs/firmware.md §15) outside a move request:
// a Catch2 check naming the lines it counted (stderr in the benchmark). Rig runs it at teardown;
// a test that holds an Emulator of its own keeps a HazardWatch beside it.
void expect_no_hazards(const birdcage::sim::Emulator& dish);
class HazardWatch {
public:
    explicit HazardWatch(const birdcage::sim::Emulator& dish) : dish_(dish) {}
    ~HazardWatch();
    HazardWatch(const HazardWatch&) = delete;
    HazardWatch& operator=(const HazardWatch&) = delete;

private:
    const birdcage::sim::Emulator& dish_;
};

// Emulator + preloaded stock rotctld for one Winegard model; at teardown, expect_no_hazards().
class Rig {
public:
    // `prepare` runs after the emulator starts and before rotctld opens the port; rotctld must
    // listen within `open_timeout` (it opens the dish first).
    Rig(birdcage::sim::Options dish, int model, std::vector<std::string> extra_rotctld_args = {},
        const std::function<void(birdcage::sim::Emulator&)>& prepare = {},
        std::chrono::milliseconds open_timeout = std::chrono::seconds(60));
    ~Rig();
    birdcage::sim::Emulator& dish() { return *dish_; }
    int port() const { return port_; }
    pid_t rotctld_pid() const { return rotctld_->pid(); }
    bool rotctld_running() { return rotctld_->running(); }
    const std::string& rotctld_log() const { return log_path_; }
    std::string rotctld_log_text() const;
    // Stock NET rotctl client: rotctl -m 2 -r 127.0.0.1:<port> <args...>
    CommandResult rotctl(const std::vector<std::string>& args);

private:
    std::unique_ptr<birdcage::sim::Emulator> dish_;
    int port_ = 0;
    std::string log_path_;
    std::unique_ptr<Child> rotctld_;
};

}  // namespace e2e
