// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Runs birdcage-skyscan as a child process and follows its progress lines on stderr
// ("birdcage-skyscan: 12/77  az ... ETA ..."), for the signal screen's launcher.
#pragma once

#include <spawn.h>
#include <sys/types.h>
#include <optional>
#include <string>
#include <vector>

namespace birdcage::tui {

class ScanLauncher {
public:
    ScanLauncher() = default;
    ~ScanLauncher();
    ScanLauncher(const ScanLauncher&) = delete;
    ScanLauncher& operator=(const ScanLauncher&) = delete;

    // Starts `program args...`; false (and why) when it cannot run.
    bool start(const std::string& program, const std::vector<std::string>& args, std::string* why);
    // Reads what the child wrote since the last call and notices its exit; never blocks.
    void pump();
    void cancel();
    bool running() const { return pid_ > 0; }

    std::string progress;            // the last progress or message line
    int done = 0, total = 0;         // points measured / planned, from the progress line
    std::optional<int> exit_status;  // set once the child has ended (128+N: signal N)
    bool started = false;
    bool stopped = false;  // ended by cancel(), not by itself
    // "running, x stops it", "done", "scan stopped" (cancel), or "failed with status N".
    std::string outcome() const;

private:
    void take(const std::string& line);

    pid_t pid_ = -1;
    int fd_ = -1;
    std::string pending_;
};

// Where the launcher finds birdcage-skyscan: beside this program (an install or a build tree puts
// both in one directory), else on PATH.
std::string skyscan_program(const std::string& argv0);

// Starts `program args...` (looked up on PATH as a shell would) with the file actions given: the
// one place the TUI's child programs (the sky scan, birdcage-track) are started. Returns
// posix_spawnp's error number (0: started, its pid in *pid).
int spawn_program(const std::string& program, const std::vector<std::string>& args,
                  const posix_spawn_file_actions_t& actions, pid_t* pid);

}  // namespace birdcage::tui
