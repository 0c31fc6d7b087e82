// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "scan_launcher.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>

extern char** environ;

namespace birdcage::tui {

ScanLauncher::~ScanLauncher() {
    cancel();
    if (pid_ > 0) {
        int status = 0;
        ::waitpid(pid_, &status, 0);
    }
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

bool ScanLauncher::start(const std::string& program, const std::vector<std::string>& args, std::string* why) {
    if (running()) {
        *why = "a scan is already running";
        return false;
    }
    int pipe_fds[2];
    if (::pipe2(pipe_fds, O_CLOEXEC) != 0) {
        *why = std::string("pipe: ") + std::strerror(errno);
        return false;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    // Its stdout (the CSV when no --out is given) is not wanted on the screen; stderr is the progress.
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
    pid_t pid = -1;
    const int rc = spawn_program(program, args, actions, &pid);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipe_fds[1]);
    if (rc != 0) {
        ::close(pipe_fds[0]);
        *why = "cannot run " + program + ": " + std::strerror(rc);
        return false;
    }
    ::fcntl(pipe_fds[0], F_SETFL, ::fcntl(pipe_fds[0], F_GETFL) | O_NONBLOCK);
    if (fd_ >= 0) {
        ::close(fd_);
    }
    fd_ = pipe_fds[0];
    pid_ = pid;
    pending_.clear();
    progress = "starting " + program;
    done = total = 0;
    exit_status.reset();
    started = true;
    stopped = false;
    return true;
}

void ScanLauncher::take(const std::string& line) {
    if (line.empty()) {
        return;
    }
    std::string text = line;
    while (!text.empty() && text.back() == ' ') {
        text.pop_back();
    }
    progress = text;
    int d = 0, t = 0;
    if (std::sscanf(text.c_str(), "birdcage-skyscan: %d/%d", &d, &t) == 2 && t > 0) {
        done = d;
        total = t;
    }
}

void ScanLauncher::pump() {
    if (fd_ >= 0) {
        char buffer[512];
        for (;;) {
            const ssize_t got = ::read(fd_, buffer, sizeof buffer);
            if (got <= 0) {
                break;
            }
            pending_.append(buffer, static_cast<std::size_t>(got));
        }
        // Progress lines end in '\r' (rewritten in place on a terminal), messages in '\n'.
        std::size_t end;
        while ((end = pending_.find_first_of("\r\n")) != std::string::npos) {
            take(pending_.substr(0, end));
            pending_.erase(0, end + 1);
        }
    }
    if (pid_ > 0) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
            pid_ = -1;
            exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            take(pending_);
            pending_.clear();
        }
    }
}

void ScanLauncher::cancel() {
    if (pid_ > 0) {
        ::kill(pid_, SIGTERM);
        stopped = true;
    }
}

std::string ScanLauncher::outcome() const {
    if (running()) {
        return "running, x stops it";
    }
    if (stopped) {
        return "scan stopped";  // its SIGTERM status (143) is ours, not a failure
    }
    return exit_status == 0 ? "done" : "failed with status " + std::to_string(exit_status.value_or(-1));
}

std::string skyscan_program(const std::string& argv0) {
    char self[4096];
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    std::string dir;
    if (n > 0) {
        dir.assign(self, static_cast<std::size_t>(n));
    } else {
        dir = argv0;
    }
    if (const auto slash = dir.rfind('/'); slash != std::string::npos) {
        dir.resize(slash);
        const std::string beside = dir + "/birdcage-skyscan";
        if (::access(beside.c_str(), X_OK) == 0) {
            return beside;
        }
        // A build tree keeps the tools in a sibling directory.
        const std::string sibling = dir + "/../tools/birdcage-skyscan";
        if (::access(sibling.c_str(), X_OK) == 0) {
            return sibling;
        }
    }
    return "birdcage-skyscan";
}

int spawn_program(const std::string& program, const std::vector<std::string>& args,
                  const posix_spawn_file_actions_t& actions, pid_t* pid) {
    std::vector<std::string> argv_text{program};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_text) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    return ::posix_spawnp(pid, program.c_str(), &actions, nullptr, argv.data(), environ);
}

}  // namespace birdcage::tui
