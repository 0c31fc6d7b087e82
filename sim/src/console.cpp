// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage_sim/console.hpp"

#include <utility>

#include "engine.hpp"

namespace birdcage::sim {

Console::Console(const Options& options) : engine_(std::make_unique<Engine>(options)) {}
Console::~Console() = default;

void Console::feed(std::string_view bytes) {
    engine_->feed(bytes);
}
void Console::advance(double dt) {
    engine_->advance(dt);
}
std::string Console::take_output() {
    return engine_->take_output();
}

Pose Console::position() const {
    return {engine_->displayed_az(), engine_->motors.axis(axis_el).position()};
}
double Console::mechanical_az() const {
    return engine_->motors.axis(axis_az).position();
}
double Console::move_time(int axis, double degrees) const {
    return Axis::move_time(engine_->motors.axis(axis == 0 ? axis_az : axis_el).params(), degrees);
}
bool Console::moving() const {
    return engine_->motors.moving();
}
bool Console::search_running() const {
    return engine_->search;
}
bool Console::shell_alive() const {
    return engine_->shell_alive;
}
bool Console::booting() const {
    return engine_->booting();
}
const std::vector<Sample>& Console::history() const {
    return engine_->history;
}
unsigned Console::hazards() const {
    return engine_->hazards;
}
const std::vector<std::string>& Console::hazard_commands() const {
    return engine_->hazard_lines;
}
const std::vector<std::string>& Console::commands() const {
    return engine_->commands;
}
double Console::time() const {
    return engine_->now;
}
AzEl Console::beam_direction() const {
    return engine_->beam_direction();
}
double Console::epoch() const {
    return engine_->epoch;
}
std::vector<TruthRow> Console::take_truth() {
    return std::exchange(engine_->truth, {});
}
void Console::power_cycle() {
    engine_->start_boot();
}
void Console::inject_motor_stall(int axis) {
    if (axis == 0 || axis == 1)
        engine_->inject_motor_stall(static_cast<std::size_t>(axis));
}
unsigned Console::motor_stalls() const {
    return engine_->motor_stalls;
}

}  // namespace birdcage::sim
