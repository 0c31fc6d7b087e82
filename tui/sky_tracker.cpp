// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "sky_tracker.hpp"

#include "scan_launcher.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace birdcage::tui {

std::optional<double> parse_iso_time(const std::string& text) {
    int year = 0, month = 0, day = 0, hour = 0, minute = 0, used = 0;
    double second = 0;
    if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%lf%n", &year, &month, &day, &hour, &minute, &second, &used) !=
        6) {
        return std::nullopt;
    }
    const std::string zone = text.substr(static_cast<std::size_t>(used));
    if (!zone.empty() && zone != "Z" && zone != "+00:00") {
        return std::nullopt;
    }
    std::tm tm{};
    tm.tm_year = year - 1900;
    tm.tm_mon = month - 1;
    tm.tm_mday = day;
    tm.tm_hour = hour;
    tm.tm_min = minute;
    return static_cast<double>(::timegm(&tm)) + second;
}

std::string iso_time(double unix_seconds) {
    const auto whole = static_cast<std::time_t>(std::floor(unix_seconds));
    std::tm tm{};
    ::gmtime_r(&whole, &tm);
    char text[40];
    std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &tm);
    char fraction[8];
    std::snprintf(fraction, sizeof fraction, "%.3f", unix_seconds - static_cast<double>(whole));
    return std::string(text) + (fraction + 1) + "Z";  // ".123"
}

SkyClock::SkyClock(const SkyOptions& options)
    : at_(options.at),
      scale_(options.time_scale),
      wall_start_(static_cast<double>(std::time(nullptr))),
      started_(std::chrono::steady_clock::now()) {}

double SkyClock::now() const {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    if (!at_ && !scale_) {
        return wall_start_ + elapsed;
    }
    return at_.value_or(wall_start_) + elapsed * scale_.value_or(1.0);
}

std::vector<std::string> SkyClock::args() const {
    if (!at_ && !scale_) {
        return {};
    }
    char scale[32];
    std::snprintf(scale, sizeof scale, "%g", scale_.value_or(1.0));
    return {"--at", iso_time(now()), "--time-scale", scale};
}

std::vector<std::string> sky_common_args(const SkyOptions& options, const SkyClock& clock) {
    std::vector<std::string> args{"--host", options.host, "--port", std::to_string(options.port)};
    const std::pair<const char*, const std::optional<double>*> station[] = {
        {"--lat", &options.lat}, {"--lon", &options.lon}, {"--alt", &options.alt}};
    for (const auto& [flag, value] : station) {
        if (*value) {
            char text[32];
            std::snprintf(text, sizeof text, "%.6g", **value);
            args.insert(args.end(), {flag, text});
        }
    }
    for (const auto& tle : options.tles) {
        args.insert(args.end(), {"--tle", tle});
    }
    const auto timing = clock.args();
    args.insert(args.end(), timing.begin(), timing.end());
    return args;
}

// ---- Child -------------------------------------------------------------------------------------

Child::~Child() {
    if (pid_ > 0) {
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
    for (const int fd : {out_, err_}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
}

bool Child::start(const std::string& program, const std::vector<std::string>& args, std::string* why) {
    if (running()) {
        *why = "already running";
        return false;
    }
    int out_fds[2], err_fds[2];
    if (::pipe2(out_fds, O_CLOEXEC) != 0) {
        *why = std::string("pipe: ") + std::strerror(errno);
        return false;
    }
    if (::pipe2(err_fds, O_CLOEXEC) != 0) {
        *why = std::string("pipe: ") + std::strerror(errno);
        ::close(out_fds[0]);
        ::close(out_fds[1]);
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, out_fds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, err_fds[1], STDERR_FILENO);
    pid_t pid = -1;
    const int rc = spawn_program(program, args, actions, &pid);
    posix_spawn_file_actions_destroy(&actions);
    ::close(out_fds[1]);
    ::close(err_fds[1]);
    if (rc != 0) {
        ::close(out_fds[0]);
        ::close(err_fds[0]);
        *why = "cannot run " + program + ": " + std::strerror(rc);
        return false;
    }
    for (const int fd : {out_fds[0], err_fds[0]}) {
        ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
    }
    for (const int fd : {out_, err_}) {
        if (fd >= 0) {
            ::close(fd);
        }
    }
    out_ = out_fds[0];
    err_ = err_fds[0];
    pid_ = pid;
    out_pending_.clear();
    err_pending_.clear();
    exit_status.reset();
    last_error_line.clear();
    return true;
}

namespace {

void drain(int fd, std::string& pending) {
    if (fd < 0) {
        return;
    }
    char buffer[4096];
    for (;;) {
        const ssize_t got = ::read(fd, buffer, sizeof buffer);
        if (got <= 0) {
            return;
        }
        pending.append(buffer, static_cast<std::size_t>(got));
    }
}

std::vector<std::string> take_lines(std::string& pending) {
    std::vector<std::string> lines;
    std::size_t end;
    while ((end = pending.find_first_of("\r\n")) != std::string::npos) {
        if (end > 0) {
            lines.push_back(pending.substr(0, end));
        }
        pending.erase(0, end + 1);
    }
    return lines;
}

}  // namespace

void Child::read_stderr() {
    drain(err_, err_pending_);
    for (auto& line : take_lines(err_pending_)) {
        last_error_line = std::move(line);
    }
}

std::vector<std::string> Child::pump() {
    drain(out_, out_pending_);
    read_stderr();
    auto lines = take_lines(out_pending_);
    if (pid_ > 0) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            // What it wrote just before it ended.
            drain(out_, out_pending_);
            read_stderr();
            for (auto& line : take_lines(out_pending_)) {
                lines.push_back(std::move(line));
            }
            if (!out_pending_.empty()) {
                lines.push_back(out_pending_);
                out_pending_.clear();
            }
            if (!err_pending_.empty()) {
                last_error_line = err_pending_;
                err_pending_.clear();
            }
        }
    }
    return lines;
}

void Child::terminate() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
    }
}

// ---- queries -----------------------------------------------------------------------------------

bool SkyQuery::start(const std::string& program, const std::vector<std::string>& args, std::string* why) {
    answer.reset();
    error.clear();
    text_.clear();
    std::vector<std::string> with_json = args;
    with_json.push_back("--json");
    return child_.start(program, with_json, why);
}

bool SkyQuery::pump() {
    const bool was_running = child_.running();
    for (const auto& line : child_.pump()) {
        text_ += line + "\n";
    }
    if (!was_running || child_.running()) {
        return false;
    }
    if (child_.exit_status != 0) {
        error = !child_.last_error_line.empty()
                    ? child_.last_error_line
                    : "birdcage-track exited with status " + std::to_string(child_.exit_status.value_or(-1));
        return true;
    }
    std::string why;
    answer = parse_json(text_, &why);
    if (!answer || answer->type != Json::Type::object) {
        answer.reset();
        error = "birdcage-track's answer is not a JSON object (" + (why.empty() ? "not an object" : why) + ")";
    }
    return true;
}

std::vector<VisibleTarget> visible_targets(const Json& answer) {
    std::vector<VisibleTarget> out;
    const Json* targets = answer.find("targets");
    if (targets == nullptr) {
        return out;
    }
    for (const auto& item : targets->items) {
        VisibleTarget t;
        t.name = item.text_at("name");
        t.kind = item.text_at("kind");
        t.az = item.number_at("az").value_or(NAN);
        t.el = item.number_at("el").value_or(NAN);
        const Json* in_window = item.find("in_window");
        t.in_window = in_window != nullptr && in_window->boolean;
        if (!t.name.empty()) {
            out.push_back(std::move(t));
        }
    }
    // In the window first (what can be tracked now), then the highest.
    std::stable_sort(out.begin(), out.end(), [](const VisibleTarget& a, const VisibleTarget& b) {
        return a.in_window != b.in_window ? a.in_window : a.el > b.el;
    });
    return out;
}

std::vector<PassTimes> passes(const Json& answer) {
    std::vector<PassTimes> out;
    const Json* list = answer.find("passes");
    if (list == nullptr) {
        return out;
    }
    for (const auto& item : list->items) {
        PassTimes p;
        p.aos = item.text_at("aos");
        p.tca = item.text_at("tca");
        p.los = item.text_at("los");
        p.max_el = item.number_at("max_el").value_or(NAN);
        p.aos_az = item.number_at("aos_az").value_or(NAN);
        p.tca_az = item.number_at("tca_az").value_or(NAN);
        p.los_az = item.number_at("los_az").value_or(NAN);
        p.duration_s = item.number_at("duration_s").value_or(NAN);
        out.push_back(std::move(p));
    }
    return out;
}

// ---- the track ---------------------------------------------------------------------------------

bool Tracker::start(const std::string& program, const std::vector<std::string>& args, const std::string& name,
                    std::string* why) {
    if (running()) {
        *why = "already tracking " + target + " (x stops it)";
        return false;
    }
    std::vector<std::string> full = args;
    full.insert(full.end(), {"--json", name});
    if (!child_.start(program, full, why)) {
        return false;
    }
    static_cast<TrackState&>(*this) = TrackState{};  // what the last track showed goes
    target = name;
    phase = "starting";
    return true;
}

namespace {

std::optional<std::pair<double, double>> az_el(const Json& event, const char* key) {
    const Json* point = event.find(key);
    if (point == nullptr) {
        return std::nullopt;
    }
    const auto az = point->number_at("az"), el = point->number_at("el");
    if (!az || !el) {
        return std::nullopt;
    }
    return std::make_pair(*az, *el);
}

}  // namespace

bool Tracker::take(const std::string& line) {
    const auto event = parse_json(line);
    if (!event || event->type != Json::Type::object) {
        return false;
    }
    const std::string kind = event->text_at("event");
    if (kind == "plan") {
        target = event->text_at("target", target);
        const Json* a = event->find("aos");
        const Json* l = event->find("los");
        aos = a != nullptr && a->type == Json::Type::string ? std::optional(a->text) : std::nullopt;
        los = l != nullptr && l->type == Json::Type::string ? std::optional(l->text) : std::nullopt;
        max_el = event->number_at("max_el");
    } else if (kind == "wait") {
        phase = "waiting";
        seconds_to_aos = event->number_at("seconds_to_aos");
        aim = az_el(*event, "aim");
    } else if (kind == "progress") {
        phase = "tracking";
        seconds_to_aos.reset();
        target_position = az_el(*event, "target");
        dish_position = az_el(*event, "dish");
        error_deg = event->number_at("error_deg");
        seconds_to_los = event->number_at("seconds_to_los");
    } else if (kind == "end") {
        phase = event->text_at("outcome", "error");
        reason = event->text_at("reason");
        rms_error_deg = event->number_at("rms_error_deg");
        max_error_deg = event->number_at("max_error_deg");
        samples = static_cast<int>(event->number_at("samples").value_or(0));
        const Json* p = event->find("parked");
        parked = p != nullptr && p->boolean;
    } else {
        return false;
    }
    return true;
}

void Tracker::pump() {
    const bool was_running = child_.running();
    for (const auto& line : child_.pump()) {
        take(line);
    }
    if (was_running && !child_.running()) {
        exit_status = child_.exit_status;
        // Ended without its end event (it could not start, or died): its own words say why.
        if (phase == "starting" || phase == "waiting" || phase == "tracking") {
            phase = "error";
            reason = !child_.last_error_line.empty()
                         ? child_.last_error_line
                         : "birdcage-track exited with status " + std::to_string(exit_status.value_or(-1));
        } else if (phase == "error" && reason.empty()) {
            reason = child_.last_error_line;
        }
    }
}

void Tracker::cancel() {
    if (running()) {
        child_.terminate();
        stopped = true;
    }
}

std::string tool_program(const std::string& argv0, const std::string& name, const std::string& build_dir) {
    char self[4096];
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    std::string dir = n > 0 ? std::string(self, static_cast<std::size_t>(n)) : argv0;
    if (const auto slash = dir.rfind('/'); slash != std::string::npos) {
        dir.resize(slash);
        for (const std::string& candidate : {dir + "/" + name, dir + "/../" + build_dir + "/" + name}) {
            if (::access(candidate.c_str(), X_OK) == 0) {
                return candidate;
            }
        }
    }
    return name;
}

}  // namespace birdcage::tui
