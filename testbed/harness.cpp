// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "harness.hpp"

// Built into each test program (which then links Catch2's runner) and into the benchmark (which
// does not): the teardown check reports through Catch2 where it can, on stderr otherwise.
#ifdef BIRDCAGE_E2E_WITH_CATCH
#include <catch2/catch.hpp>
#endif

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace e2e {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

namespace {
std::string& chosen_backend() {
    static std::string path;
    return path;
}
}  // namespace

std::string backend_library() {
    return chosen_backend().empty() ? BIRDCAGE_BACKEND_LIBRARY : chosen_backend();
}

void use_backend_library(std::string path) {
    chosen_backend() = std::move(path);
}

std::string executable_directory() {
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    return error ? std::string() : self.parent_path().string();
}

std::map<std::string, std::string> preload_environment() {
#ifdef BIRDCAGE_SANITIZER_RUNTIME
    // rotctld's own allocations are not ours to judge: leak checking stays on in the in-process tests.
    return {{"LD_PRELOAD", std::string(BIRDCAGE_SANITIZER_RUNTIME) + ":" + backend_library()},
            {"ASAN_OPTIONS", "detect_leaks=0"}};
#else
    return {{"LD_PRELOAD", backend_library()}};
#endif
}

namespace {

std::vector<std::string> merged_environment(const std::map<std::string, std::string>& extra) {
    std::vector<std::string> env;
    for (char** e = environ; *e != nullptr; ++e) {
        std::string entry(*e);
        const std::string key = entry.substr(0, entry.find('='));
        if (extra.count(key) == 0) {
            env.push_back(entry);
        }
    }
    for (const auto& [k, v] : extra) {
        env.push_back(k + "=" + v);
    }
    return env;
}

std::vector<char*> c_strings(std::vector<std::string>& strings) {
    std::vector<char*> out;
    for (std::string& s : strings) {
        out.push_back(s.data());
    }
    out.push_back(nullptr);
    return out;
}

pid_t spawn(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env, int stdout_fd,
            int stderr_fd) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, stdout_fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, stderr_fd, STDERR_FILENO);
    // Nothing else leaks into the child: an inherited pty master (the emulator's) would keep the
    // pty alive after Emulator::hang_up(), and the child would never see the hang-up.
    posix_spawn_file_actions_addclosefrom_np(&actions, STDERR_FILENO + 1);
    std::vector<std::string> args = argv;
    std::vector<std::string> envs = merged_environment(env);
    std::vector<char*> c_args = c_strings(args);
    std::vector<char*> c_env = c_strings(envs);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, c_args[0], &actions, nullptr, c_args.data(), c_env.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
        throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(rc));
    }
    return pid;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

std::string temp_path(const char* stem) {
    char pattern[128];
    std::snprintf(pattern, sizeof pattern, "/tmp/birdcage-%s-XXXXXX", stem);
    const int fd = mkstemp(pattern);
    if (fd < 0) {
        throw std::runtime_error("mkstemp failed");
    }
    close(fd);
    return pattern;
}

}  // namespace

CommandResult run(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
                  std::chrono::milliseconds timeout) {
    const std::string out_path = temp_path("out");
    const std::string err_path = temp_path("err");
    const int out_fd = open(out_path.c_str(), O_WRONLY | O_TRUNC);
    const int err_fd = open(err_path.c_str(), O_WRONLY | O_TRUNC);
    const pid_t pid = spawn(argv, env, out_fd, err_fd);
    close(out_fd);
    close(err_fd);

    CommandResult result;
    int status = 0;
    const auto deadline = Clock::now() + timeout;
    while (true) {
        const pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid) {
            result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            break;
        }
        if (Clock::now() > deadline) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            result.exit_code = -1;
            break;
        }
        std::this_thread::sleep_for(2ms);
    }
    result.out = slurp(out_path);
    result.err = slurp(err_path);
    unlink(out_path.c_str());
    unlink(err_path.c_str());
    return result;
}

Child::Child(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
             const std::string& log_path) {
    const int log_fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    pid_ = spawn(argv, env, log_fd, log_fd);
    close(log_fd);
}

bool Child::running() {
    if (reaped_) {
        return false;
    }
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
        reaped_ = true;
        return false;
    }
    return true;
}

Child::~Child() {
    if (!running()) {
        return;
    }
    kill(pid_, SIGTERM);
    if (!wait_until([this] { return !running(); }, 3s)) {
        kill(pid_, SIGKILL);
        int status = 0;
        waitpid(pid_, &status, 0);
    }
}

bool wait_until(const std::function<bool()>& predicate, std::chrono::milliseconds timeout) {
    const auto deadline = Clock::now() + timeout;
    while (!predicate()) {
        if (Clock::now() > deadline) {
            return false;
        }
        std::this_thread::sleep_for(5ms);
    }
    return true;
}

birdcage::sim::Options dish_options(birdcage::sim::Variant variant, double az, double el, double time_scale) {
    birdcage::sim::Options o;
    o.variant = variant;
    o.time_scale = time_scale;
    o.start_az = az;
    o.start_el = el;
    return o;
}

double angle_between(double a, double b) {
    const double d = std::fmod(std::fabs(a - b), 360.0);
    return d > 180.0 ? 360.0 - d : d;
}

double sky_angle(double az1, double el1, double az2, double el2) {
    // The haversine form stays accurate for the small angles that matter here.
    constexpr double deg = std::numbers::pi / 180.0;
    const double s_el = std::sin((el1 - el2) * deg / 2.0);
    const double s_az = std::sin((az1 - az2) * deg / 2.0);
    const double h = s_el * s_el + std::cos(el1 * deg) * std::cos(el2 * deg) * s_az * s_az;
    return 2.0 * std::asin(std::min(1.0, std::sqrt(h))) / deg;
}

bool settled_at(birdcage::sim::Emulator& dish, double az, double el, double tolerance) {
    const birdcage::sim::Pose p = dish.true_position();
    return !dish.moving() && angle_between(p.az, az) <= tolerance && std::fabs(p.el - el) <= tolerance;
}

std::vector<double> numbers(const std::string& text) {
    std::vector<double> out;
    std::istringstream in(text);
    double v = 0;
    while (in >> v) {
        out.push_back(v);
    }
    return out;
}

int listening_tcp_port(pid_t pid) {
    // The process's socket inodes, from its fd links ("socket:[12345]").
    std::vector<std::string> inodes;
    const std::string fd_dir = "/proc/" + std::to_string(pid) + "/fd";
    for (int fd = 0; fd < 256; ++fd) {
        char target[64] = {};
        const std::string link = fd_dir + "/" + std::to_string(fd);
        const ssize_t length = readlink(link.c_str(), target, sizeof target - 1);
        if (length > 9 && std::strncmp(target, "socket:[", 8) == 0) {
            inodes.emplace_back(target + 8, static_cast<std::size_t>(length) - 9);
        }
    }
    // Its network namespace's TCP table: "sl local_address rem_address st ... inode"; a
    // listening socket has state 0A; the local address is hex "ip:port".
    std::ifstream table("/proc/" + std::to_string(pid) + "/net/tcp");
    std::string line;
    std::getline(table, line);  // header
    while (std::getline(table, line)) {
        std::istringstream fields(line);
        std::string slot, local, remote, state, queues, timer, retransmits, uid, timeout, inode;
        fields >> slot >> local >> remote >> state >> queues >> timer >> retransmits >> uid >> timeout >> inode;
        if (state != "0A" || std::find(inodes.begin(), inodes.end(), inode) == inodes.end()) {
            continue;
        }
        const auto colon = local.find(':');
        if (colon != std::string::npos) {
            return static_cast<int>(std::stoul(local.substr(colon + 1), nullptr, 16));
        }
    }
    return 0;
}

RotctldConnection::RotctldConnection(int port)
    : client_("127.0.0.1", port,
              birdcage::rotctl::Options{.protocol = birdcage::rotctl::Protocol::plain, .probe = false}) {
    if (std::string why; !client_.connect(&why)) {
        throw std::runtime_error("cannot connect to rotctld on port " + std::to_string(port) + ": " + why);
    }
}

bool RotctldConnection::send_raw(const std::string& bytes) {
    return client_.send_raw(bytes);
}

std::string RotctldConnection::ask(const std::string& command, int lines, std::chrono::milliseconds timeout) {
    if (!send_raw(command + "\n")) {
        return {};
    }
    return read_lines(lines, timeout);
}

std::string RotctldConnection::read_lines(int lines, std::chrono::milliseconds timeout) {
    return client_.read_lines(lines, timeout);
}

RotctldConnection::Position RotctldConnection::get_position(std::chrono::milliseconds timeout) {
    Position out;
    client_.set_timeout(timeout);
    const int code = client_.get_position(out.az, out.el);
    out.ok = code == 0;
    if (!out.ok) {
        out.error = client_.connected() ? "RPRT " + std::to_string(code) : "no reply";
    }
    return out;
}

void type_into(birdcage::sim::Emulator& dish, const std::vector<std::string>& lines) {
    const int fd = open(dish.device_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        throw std::runtime_error("cannot open " + dish.device_path());
    }
    auto drain_until_quiet = [fd] {
        char buf[512];
        for (;;) {
            pollfd p{fd, POLLIN, 0};
            if (poll(&p, 1, 100) <= 0 || read(fd, buf, sizeof buf) <= 0) {
                return;
            }
        }
    };
    for (const std::string& line : lines) {
        const std::size_t before = dish.received_commands().size();
        const std::string wire = line + "\r";
        if (write(fd, wire.data(), wire.size()) != static_cast<ssize_t>(wire.size())) {
            close(fd);
            throw std::runtime_error("cannot type into the dish");
        }
        wait_until([&] { return dish.received_commands().size() > before; }, 5s);
        drain_until_quiet();
    }
    close(fd);
}

Rig::Rig(birdcage::sim::Options dish, int model, std::vector<std::string> extra_rotctld_args,
         const std::function<void(birdcage::sim::Emulator&)>& prepare, std::chrono::milliseconds open_timeout)
    : dish_(std::make_unique<birdcage::sim::Emulator>(std::move(dish))), log_path_(temp_path("rotctld")) {
    if (prepare) {
        prepare(*dish_);
    }
    std::vector<std::string> argv = {"/usr/bin/rotctld",
                                     "-m",
                                     std::to_string(model),
                                     "-r",
                                     dish_->device_path(),
                                     "-T",
                                     "127.0.0.1",
                                     "-t",
                                     "0",
                                     "-vvvv"};
    argv.insert(argv.end(), extra_rotctld_args.begin(), extra_rotctld_args.end());
    rotctld_ = std::make_unique<Child>(argv, preload_environment(), log_path_);
    // rotctld opens the rotator (and so initialises the dish) before it listens. It listens on a
    // port the kernel picks (-t 0), read back from its own socket table: no other test's rotctld
    // can hold it, which a port chosen here and released before rotctld binds cannot promise.
    const bool up = wait_until(
        [this] {
            if (!rotctld_->running()) {
                return true;
            }
            port_ = listening_tcp_port(rotctld_->pid());
            return port_ != 0;
        },
        open_timeout);
    if (!up || !rotctld_->running()) {
        throw std::runtime_error("rotctld did not come up; its log:\n" + rotctld_log_text());
    }
}

void expect_no_hazards(const birdcage::sim::Emulator& dish) {
    const unsigned hazards = dish.hazards_received();
    std::string lines;
    for (const std::string& line : dish.hazard_commands()) {
        lines += (lines.empty() ? "\"" : ", \"") + line + "\"";
    }
#ifdef BIRDCAGE_E2E_WITH_CATCH
    INFO("hazards the dish received: " << lines);
    CHECK(hazards == 0);
#else
    if (hazards != 0) {
        std::fprintf(stderr, "the dish received %u hazard(s): %s\n", hazards, lines.c_str());
    }
#endif
}

HazardWatch::~HazardWatch() {
    expect_no_hazards(dish_);
}

Rig::~Rig() {
    rotctld_.reset();
    // Every test that drives a dish through rotctld holds it to 0 hazards, whatever it checks itself
    // (docs/development.md): the words the core's hazard rule names, counted by the emulator.
    expect_no_hazards(*dish_);
    // Debugging a benchmark or test run: BIRDCAGE_KEEP_ROTCTLD_LOGS=1 keeps each rotctld -vvvv log.
    const char* keep = std::getenv("BIRDCAGE_KEEP_ROTCTLD_LOGS");
    if (keep && std::string(keep) == "1") {
        std::fprintf(stderr, "rotctld log kept: %s\n", log_path_.c_str());
        return;
    }
    unlink(log_path_.c_str());
}

std::string Rig::rotctld_log_text() const {
    return slurp(log_path_);
}

CommandResult Rig::rotctl(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {"/usr/bin/rotctl", "-m", "2", "-r", "127.0.0.1:" + std::to_string(port_)};
    argv.insert(argv.end(), args.begin(), args.end());
    return run(argv);
}

}  // namespace e2e
