// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "console/port_lock.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>

namespace birdcage {
namespace {

std::string canonical(const std::string& path) {
    std::error_code error;
    const auto resolved = std::filesystem::canonical(path, error);
    return error ? path : resolved.string();
}

std::string read_first_line(const std::string& path) {
    std::ifstream file(path);
    std::string line;
    std::getline(file, line);
    return line;
}

bool process_alive(pid_t pid) {
    return pid > 0 && (::kill(pid, 0) == 0 || errno == EPERM);
}

std::string program_of(pid_t pid) {
    return read_first_line("/proc/" + std::to_string(pid) + "/comm");
}

std::string describe(const PortHolder& holder) {
    return "PID " + std::to_string(holder.pid) + (holder.program.empty() ? "" : " (" + holder.program + ")");
}

// The pty index of `/dev/pts/<n>`, or -1.
int pts_index(const std::string& device) {
    constexpr std::string_view prefix = "/dev/pts/";
    if (device.rfind(prefix, 0) != 0) {
        return -1;
    }
    char* end = nullptr;
    const long index = std::strtol(device.c_str() + prefix.size(), &end, 10);
    return end != nullptr && *end == '\0' ? static_cast<int>(index) : -1;
}

// Whether the process's open master (/dev/ptmx) is the other side of pty `index`: fdinfo names it.
bool holds_pty_master(const std::string& proc, const std::string& fd_name, int index) {
    std::ifstream info(proc + "/fdinfo/" + fd_name);
    std::string line;
    while (std::getline(info, line)) {
        if (line.rfind("tty-index:", 0) == 0) {
            return std::atoi(line.c_str() + std::strlen("tty-index:")) == index;
        }
    }
    return false;
}

// The PID a lock file holds: HDB (ten-digit ASCII) or the older binary form.
pid_t lock_file_pid(const std::string& path) {
    char text[32] = {};
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return 0;
    }
    const ssize_t length = ::read(fd, text, sizeof text - 1);
    ::close(fd);
    if (length == static_cast<ssize_t>(sizeof(int)) && (text[0] < '0' || text[0] > '9') && text[0] != ' ') {
        int binary = 0;
        std::memcpy(&binary, text, sizeof binary);
        return binary;
    }
    return static_cast<pid_t>(std::atol(text));
}

}  // namespace

std::vector<PortHolder> other_port_holders(const std::string& device) {
    const std::string target = canonical(device);
    const int index = pts_index(target);
    std::vector<PortHolder> holders;
    DIR* proc = ::opendir("/proc");
    if (proc == nullptr) {
        return holders;
    }
    const pid_t self = ::getpid();
    while (const dirent* entry = ::readdir(proc)) {
        char* end = nullptr;
        const long pid = std::strtol(entry->d_name, &end, 10);
        if (end == entry->d_name || *end != '\0' || pid == self) {
            continue;
        }
        const std::string dir = std::string("/proc/") + entry->d_name;
        DIR* fds = ::opendir((dir + "/fd").c_str());
        if (fds == nullptr) {
            continue;  // another user's process: not ours to see
        }
        bool holds_device = false;
        bool other_end = false;
        while (const dirent* fd = ::readdir(fds)) {
            if (fd->d_name[0] == '.') {
                continue;
            }
            char link[4096];
            const ssize_t length = ::readlink((dir + "/fd/" + fd->d_name).c_str(), link, sizeof link - 1);
            if (length <= 0) {
                continue;
            }
            const std::string_view opened(link, static_cast<std::size_t>(length));
            if (opened == target) {
                holds_device = true;
            } else if (index >= 0 && (opened == "/dev/ptmx" || opened == "/dev/pts/ptmx") &&
                       holds_pty_master(dir, fd->d_name, index)) {
                other_end = true;
            }
        }
        ::closedir(fds);
        if (holds_device && !other_end) {
            holders.push_back({static_cast<pid_t>(pid), program_of(static_cast<pid_t>(pid))});
        }
    }
    ::closedir(proc);
    return holders;
}

std::string lock_file_name(const std::string& device) {
    std::string name = canonical(device);
    if (name.rfind("/dev/", 0) == 0) {
        name.erase(0, 5);
    } else if (const std::size_t slash = name.rfind('/'); slash != std::string::npos) {
        name.erase(0, slash + 1);
    }
    for (char& c : name) {
        if (c == '/') {
            c = '_';
        }
    }
    return "LCK.." + name;
}

Result<PortLock> PortLock::acquire(const std::string& device, const std::string& lock_dir) {
    PortLock lock;
    std::string dir = lock_dir;
    if (dir.empty()) {
        const char* configured = std::getenv("BIRDCAGE_LOCK_DIR");
        dir = configured != nullptr && *configured != '\0' ? configured : "/run/lock";
    }
    const std::string path = dir + "/" + lock_file_name(device);
    for (int attempt = 0; attempt < 2 && lock.lock_file_.empty() && lock.note_.empty(); ++attempt) {
        const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
        if (fd >= 0) {
            char text[16];
            const int length = std::snprintf(text, sizeof text, "%10d\n", static_cast<int>(::getpid()));
            const bool written = ::write(fd, text, static_cast<std::size_t>(length)) == length;
            ::close(fd);
            if (!written) {
                ::unlink(path.c_str());
                lock.note_ = "could not write the lock file " + path;
                break;
            }
            lock.lock_file_ = path;
            break;
        }
        if (errno != EEXIST) {
            // No lock directory, or not ours to write (not in group `dialout`/`uucp`): Debian's
            // serial programs go on without a lock file then, and so do we.
            lock.note_ = "no lock file (" + path + ": " + std::strerror(errno) + ")";
            break;
        }
        const pid_t holder = lock_file_pid(path);
        if (holder == ::getpid()) {
            lock.note_ = "this program already holds " + path;
            break;
        }
        if (process_alive(holder)) {
            return {std::move(lock),
                    Status{Errc::busy, device + " is locked by " + describe({holder, program_of(holder)}) +
                                           " (lock file " + path + ")"}};
        }
        if (::unlink(path.c_str()) != 0 && errno != ENOENT) {  // stale: its PID is gone
            lock.note_ = "stale lock file " + path + " could not be removed: " + std::strerror(errno);
            break;
        }
    }

    lock.device_fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (lock.device_fd_ < 0) {
        const int error = errno;
        return {std::move(lock), Status{error == EBUSY ? Errc::busy : Errc::io,
                                        "cannot open " + device + ": " + std::strerror(error) +
                                            (error == EBUSY ? " (another program holds it exclusively)" : "")}};
    }
    if (::flock(lock.device_fd_, LOCK_EX | LOCK_NB) != 0) {
        const int error = errno;
        if (error == EWOULDBLOCK) {
            return {std::move(lock), Status{Errc::busy, device + " is held by another program (flock)"}};
        }
        lock.note_ += (lock.note_.empty() ? "" : "; ") + std::string("no flock: ") + std::strerror(error);
    }
    return {std::move(lock), Status::ok()};
}

Status PortLock::make_exclusive() {
    if (device_fd_ < 0 || !::isatty(device_fd_)) {
        return Status::ok();
    }
    if (::ioctl(device_fd_, TIOCEXCL) != 0) {
        return Status{Errc::io, std::string("TIOCEXCL: ") + std::strerror(errno)};
    }
    exclusive_ = true;
    return Status::ok();
}

PortLock::PortLock(PortLock&& other) noexcept
    : device_fd_(std::exchange(other.device_fd_, -1)),
      exclusive_(std::exchange(other.exclusive_, false)),
      lock_file_(std::exchange(other.lock_file_, {})),
      note_(std::move(other.note_)) {}

PortLock& PortLock::operator=(PortLock&& other) noexcept {
    if (this != &other) {
        release();
        device_fd_ = std::exchange(other.device_fd_, -1);
        exclusive_ = std::exchange(other.exclusive_, false);
        lock_file_ = std::exchange(other.lock_file_, {});
        note_ = std::move(other.note_);
    }
    return *this;
}

PortLock::~PortLock() {
    release();
}

void PortLock::release() {
    if (device_fd_ >= 0) {
        // A pty's exclusive flag outlives our descriptors while its master stays open: clear it.
        if (exclusive_) {
            ::ioctl(device_fd_, TIOCNXCL);
        }
        ::close(device_fd_);
        device_fd_ = -1;
    }
    exclusive_ = false;
    if (!lock_file_.empty()) {
        ::unlink(lock_file_.c_str());
        lock_file_.clear();
    }
}

}  // namespace birdcage
