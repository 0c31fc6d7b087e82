// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The console engine without any I/O or thread: bytes in, bytes out, simulated time advanced
// explicitly. Emulator wraps it with a pty and a thread; tests can drive it directly.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "birdcage_sim/emulator.hpp"

namespace birdcage::sim {

struct Engine;

class Console {
public:
    explicit Console(const Options& options);
    ~Console();
    Console(const Console&) = delete;
    Console& operator=(const Console&) = delete;

    void feed(std::string_view bytes);  // bytes from the client
    void advance(double dt);            // simulated seconds
    std::string take_output();          // bytes the dish sent since the last call

    Pose position() const;
    double mechanical_az() const;
    // How long the emulated motor of `axis` (0 = AZ, 1 = EL) takes for a move of `degrees`, from the
    // command to rest, its start-up delay included (Axis::move_time with the variant's parameters
    // and Options::motor's overrides).
    double move_time(int axis, double degrees) const;
    bool moving() const;
    bool search_running() const;
    bool shell_alive() const;
    bool booting() const;
    const std::vector<Sample>& history() const;
    unsigned hazards() const;
    const std::vector<std::string>& hazard_commands() const;  // the line of each hazard counted
    const std::vector<std::string>& commands() const;
    double time() const;
    AzEl beam_direction() const;  // see Emulator::beam_direction
    double epoch() const;
    // Truth rows since the last call (kept only when Options::truth_path is set): one every 0.1
    // simulated seconds and one at every start and end of motion.
    std::vector<TruthRow> take_truth();
    void power_cycle();
    // Fault injection (axis 0 = AZ, 1 = EL): see Emulator::inject_motor_stall.
    void inject_motor_stall(int axis);
    unsigned motor_stalls() const;

private:
    std::unique_ptr<Engine> engine_;
};

}  // namespace birdcage::sim
