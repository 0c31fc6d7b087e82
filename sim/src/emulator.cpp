// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage_sim/emulator.hpp"

#include <poll.h>
#include <unistd.h>
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <random>
#include <system_error>
#include <thread>

#include "birdcage_sim/console.hpp"
#include "pty.hpp"
#include "replay.hpp"

namespace birdcage::sim {
namespace {

constexpr int poll_timeout_ms = 2;
// A client that never reads must not make the emulator hoard memory; older bytes go first,
// as a UART FIFO would lose them.
constexpr std::size_t max_unsent_bytes = 1 << 20;

using Clock = std::chrono::steady_clock;

// Points `link` at `target`, replacing an existing link atomically.
void link_to(const std::string& target, const std::string& link) {
    const std::string temporary = link + ".new";
    ::unlink(temporary.c_str());
    if (::symlink(target.c_str(), temporary.c_str()) != 0 || ::rename(temporary.c_str(), link.c_str()) != 0) {
        const int error = errno;
        ::unlink(temporary.c_str());
        throw std::system_error(error, std::generic_category(), "symlink " + link);
    }
}

}  // namespace

// Threads: the console thread runs run(); the public methods come from any thread. io_mutex
// guards the pty's existence (held by the console thread for a whole loop iteration, so that a
// hang_up never closes an fd it is polling); `mutex` guards the console, the replayer and the
// fault state. Lock order: io_mutex, then mutex.
struct Emulator::Impl {
    explicit Impl(Options opts)
        : options(std::move(opts)),
          pty(std::make_unique<Pty>()),
          console(options),
          faults(options.line_faults),
          drop_rng(options.seed ^ 0xd409u),
          noise_rng(options.seed ^ 0xfa17u) {
        if (!options.truth_path.empty()) {
            truth = std::fopen(options.truth_path.c_str(), "w");
            if (truth == nullptr)
                throw std::system_error(errno, std::generic_category(), "truth file " + options.truth_path);
            std::fputs("utc,t,dish_az,dish_el,sky_az,sky_el,moving\n", truth);
            write_truth(console.take_truth());
            std::fflush(truth);
            truth_flushed_at = Clock::now();
        }
        if (options.replay != ReplayMode::off)
            // `a` alone reads the position on every variant (docs/firmware.md §2, §6.3).
            replayer.emplace(load_transcript(options.transcript_path), options.replay, options.transcript_path,
                             std::vector<std::string>{"a"});
        device_path = pty->slave_path();
        if (!options.link_path.empty()) {
            link_to(pty->slave_path(), options.link_path);
            device_path = options.link_path;
        }
        thread = std::thread([this] { run(); });
    }

    ~Impl() {
        stopping = true;
        thread.join();
        if (truth != nullptr) {
            write_truth(console.take_truth());
            std::fclose(truth);
        }
        if (!options.link_path.empty())
            ::unlink(options.link_path.c_str());
    }

    // Under `mutex` (or with the console thread stopped).
    void write_truth(const std::vector<TruthRow>& rows) {
        for (const TruthRow& row : rows) {
            std::fprintf(truth, "%s,%.3f,%.4f,%.4f,%.4f,%.4f,%d\n", format_utc(console.epoch() + row.t).c_str(), row.t,
                         row.dish_az, row.dish_el, row.sky_az, row.sky_el, row.moving ? 1 : 0);
        }
    }

    unsigned char random_byte() { return static_cast<unsigned char>(noise_rng() >> 24); }

    // Under `mutex`. Drop and polarity act on what the dish sends, before the stall gate.
    std::string filter_dish_output(const std::string& bytes) {
        std::string kept;
        kept.reserve(bytes.size());
        // One draw per byte while dropping is on: the same seed and output give the same losses.
        const double p = std::clamp(faults.drop_probability, 0.0, 1.0);
        const auto threshold = static_cast<std::uint64_t>(p * 4294967296.0);
        for (const char byte : bytes) {
            if (p > 0.0 && static_cast<std::uint64_t>(drop_rng()) < threshold) {
                ++counters.dropped_bytes;
                continue;
            }
            kept.push_back(faults.inverted_polarity ? static_cast<char>(~static_cast<unsigned char>(byte)) : byte);
        }
        return kept;
    }

    void run() {
        auto last = Clock::now();
        std::string wire;           // bytes on their way to the client
        auto line_free_at = last;   // pacing: when the line has sent every byte given to it
        double noise_credit = 0.0;  // idle noise bytes due
        char buffer[4096];
        // The pacing rate is read with the output it applies to (after poll(), under `mutex`):
        // read before poll(), a set_output_pacing() made while the thread waited would let the
        // next reply out unpaced. Before poll() only the previous rate decides whether to wait
        // for POLLOUT.
        int baud = 0;
        auto byte_time = Clock::duration::zero();
        while (!stopping) {
            std::unique_lock io(io_mutex);
            const int fd = pty ? pty->master() : -1;
            const bool can_write = !wire.empty() && (baud <= 0 || Clock::now() >= line_free_at + byte_time);

            std::string received;
            if (fd >= 0) {
                pollfd descriptor{fd, static_cast<short>(POLLIN | (can_write ? POLLOUT : 0)), 0};
                const int ready = ::poll(&descriptor, 1, poll_timeout_ms);
                if (ready > 0 && (descriptor.revents & POLLIN) != 0) {
                    const ssize_t count = ::read(fd, buffer, sizeof buffer);
                    if (count > 0)
                        received.assign(buffer, static_cast<std::size_t>(count));
                }
                if (ready > 0 && (descriptor.revents & (POLLHUP | POLLERR)) != 0)
                    std::this_thread::sleep_for(std::chrono::milliseconds(poll_timeout_ms));
            } else {
                std::this_thread::sleep_for(std::chrono::milliseconds(poll_timeout_ms));
            }
            const auto now = Clock::now();
            const double real_dt = std::chrono::duration<double>(now - last).count();
            const double dt = real_dt * options.time_scale;
            last = now;

            std::string sent;  // dish output released to the line this iteration
            std::string noise;
            {
                std::lock_guard lock(mutex);
                baud = faults.pace_baud;
                byte_time = std::chrono::duration_cast<Clock::duration>(
                    std::chrono::duration<double>(baud > 0 ? 10.0 / baud : 0.0));
                std::string input;
                if (faults.ignore_input) {
                    counters.ignored_bytes += received.size();
                } else {
                    held_input += received;
                }
                const bool stalled = console.time() < stall_until;
                if (!stalled)
                    input = std::exchange(held_input, {});
                std::string output;
                if (replayer && (replayer->replaying() || replayer->failure())) {
                    // The model keeps its own time but stays silent until a lenient fallback.
                    const std::string unmatched = replayer->receive(input);
                    replayer->advance(dt);
                    output = replayer->take_output();
                    if (!unmatched.empty())
                        console.feed(unmatched);
                    console.advance(dt);
                    const std::string model_output = console.take_output();
                    if (replayer->fell_back())
                        output += model_output;
                } else {
                    if (!input.empty())
                        console.feed(input);
                    console.advance(dt);
                    output = console.take_output();
                }
                counters.motor_stalls = console.motor_stalls();
                if (truth != nullptr) {
                    write_truth(console.take_truth());
                    // Often enough for a test that reads the file while the dish runs.
                    if (now - truth_flushed_at >= std::chrono::milliseconds(250)) {
                        std::fflush(truth);
                        truth_flushed_at = now;
                    }
                }
                held_output += filter_dish_output(output);
                if (console.time() >= stall_until)
                    sent = std::exchange(held_output, {});
                noise = std::exchange(pending_garbage, {});
                if (faults.idle_noise_bps > 0.0 && wire.empty() && sent.empty() && noise.empty()) {
                    noise_credit += faults.idle_noise_bps * real_dt;
                    for (; noise_credit >= 1.0; noise_credit -= 1.0)
                        noise.push_back(static_cast<char>(random_byte()));
                } else if (faults.idle_noise_bps <= 0.0) {
                    noise_credit = 0.0;
                }
                if (fd < 0) {
                    counters.discarded_bytes += sent.size();
                } else {
                    counters.garbage_bytes += noise.size();
                }
            }
            if (options.trace) {
                if (!received.empty())
                    options.trace(true, received);
                if (!sent.empty())
                    options.trace(false, sent);
                if (!noise.empty())
                    options.trace(false, noise);
            }
            if (fd < 0) {  // unplugged: nobody hears the dish
                wire.clear();
                continue;
            }
            if (wire.empty() || baud <= 0)
                line_free_at = std::max(line_free_at, now);
            wire += sent;
            wire += noise;
            if (wire.size() > max_unsent_bytes)
                wire.erase(0, wire.size() - max_unsent_bytes);
            if (wire.empty())
                continue;
            std::size_t allowed = wire.size();
            if (baud > 0) {
                const auto elapsed = Clock::now() - line_free_at;
                allowed = elapsed < byte_time
                              ? 0
                              : std::min<std::size_t>(allowed, static_cast<std::size_t>(elapsed / byte_time));
            }
            if (allowed == 0)
                continue;
            // The count of paced bytes changes under the same lock as the write that sends them, so
            // a client that has read the bytes never sees a count without them (fault_counters()).
            std::unique_lock counting(mutex, std::defer_lock);
            if (baud > 0)
                counting.lock();
            const ssize_t count = ::write(fd, wire.data(), allowed);
            if (count > 0) {
                wire.erase(0, static_cast<std::size_t>(count));
                if (baud > 0) {
                    line_free_at += byte_time * count;
                    counters.paced_bytes += static_cast<std::uint64_t>(count);
                }
            }
        }
    }

    void hang_up() {
        std::lock_guard io(io_mutex);
        if (!pty)
            return;
        pty.reset();  // master and guard closed: the slave side is hung up
        if (!options.link_path.empty())
            ::unlink(options.link_path.c_str());
        std::lock_guard lock(mutex);
        ++injected;
        // Bytes on their way in are lost with the adapter.
        counters.ignored_bytes += held_input.size();
        held_input.clear();
    }

    void reconnect() {
        std::lock_guard io(io_mutex);
        if (pty)
            return;
        auto fresh = std::make_unique<Pty>();
        if (!options.link_path.empty())
            link_to(fresh->slave_path(), options.link_path);
        std::lock_guard lock(mutex);
        device_path = options.link_path.empty() ? fresh->slave_path() : options.link_path;
        pty = std::move(fresh);
    }

    Options options;
    mutable std::mutex io_mutex;
    std::unique_ptr<Pty> pty;  // null while hung up
    mutable std::mutex mutex;
    Console console;
    std::optional<Replayer> replayer;
    std::string device_path;
    LineFaults faults;
    std::mt19937 drop_rng;  // separate streams: noise does not shift which bytes drop
    std::mt19937 noise_rng;
    double stall_until = 0.0;     // simulated time
    std::string held_input;       // client bytes not yet given to the console (stall)
    std::string held_output;      // dish bytes not yet on the line (stall)
    std::string pending_garbage;  // inject_garbage bytes for the console thread
    FaultCounters counters;
    std::FILE* truth = nullptr;  // Options::truth_path
    Clock::time_point truth_flushed_at;
    unsigned injected = 0;
    std::atomic<bool> stopping{false};
    std::thread thread;
};

Emulator::Emulator(Options options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Emulator::~Emulator() = default;

std::string Emulator::device_path() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->device_path;
}

Pose Emulator::true_position() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.position();
}

double Emulator::true_mechanical_az() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.mechanical_az();
}

double Emulator::move_time(int axis, double degrees) const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.move_time(axis, degrees);
}

bool Emulator::moving() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.moving();
}

bool Emulator::search_running() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.search_running();
}

bool Emulator::shell_alive() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.shell_alive();
}

std::vector<Sample> Emulator::history() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.history();
}

unsigned Emulator::hazards_received() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.hazards();
}

std::vector<std::string> Emulator::hazard_commands() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.hazard_commands();
}

std::vector<std::string> Emulator::received_commands() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.commands();
}

double Emulator::sim_time() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.time();
}

AzEl Emulator::beam_direction() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.beam_direction();
}

double Emulator::epoch() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->console.epoch();
}

std::optional<std::string> Emulator::replay_failure() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer ? impl_->replayer->failure() : std::nullopt;
}

bool Emulator::replay_complete() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer && impl_->replayer->complete();
}

bool Emulator::replay_fell_back() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer && impl_->replayer->fell_back();
}

void Emulator::power_cycle() {
    std::lock_guard lock(impl_->mutex);
    ++impl_->injected;
    impl_->console.power_cycle();
}

void Emulator::inject_garbage(std::size_t bytes) {
    std::lock_guard lock(impl_->mutex);
    ++impl_->injected;
    for (std::size_t i = 0; i < bytes; ++i)
        impl_->pending_garbage.push_back(static_cast<char>(impl_->random_byte()));
}

void Emulator::set_idle_noise(double bytes_per_second) {
    std::lock_guard lock(impl_->mutex);
    impl_->faults.idle_noise_bps = std::max(bytes_per_second, 0.0);
}

void Emulator::set_inverted_polarity(bool on) {
    std::lock_guard lock(impl_->mutex);
    impl_->faults.inverted_polarity = on;
}

void Emulator::set_ignore_input(bool on) {
    std::lock_guard lock(impl_->mutex);
    impl_->faults.ignore_input = on;
}

void Emulator::set_drop_probability(double p) {
    std::lock_guard lock(impl_->mutex);
    impl_->faults.drop_probability = std::clamp(p, 0.0, 1.0);
}

void Emulator::set_output_pacing(int baud) {
    std::lock_guard lock(impl_->mutex);
    impl_->faults.pace_baud = std::max(baud, 0);
}

void Emulator::stall_output(double sim_seconds) {
    std::lock_guard lock(impl_->mutex);
    ++impl_->injected;
    impl_->stall_until = std::max(impl_->stall_until, impl_->console.time() + std::max(sim_seconds, 0.0));
}

void Emulator::hang_up() {
    impl_->hang_up();
}
void Emulator::reconnect() {
    impl_->reconnect();
}

bool Emulator::connected() const {
    std::lock_guard io(impl_->io_mutex);
    return impl_->pty != nullptr;
}

void Emulator::inject_motor_stall(int motor) {
    std::lock_guard lock(impl_->mutex);
    ++impl_->injected;
    impl_->console.inject_motor_stall(motor);
}

unsigned Emulator::faults_injected() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->injected;
}

FaultCounters Emulator::fault_counters() const {
    std::lock_guard lock(impl_->mutex);
    FaultCounters counters = impl_->counters;
    counters.motor_stalls = impl_->console.motor_stalls();
    return counters;
}

LineFaults Emulator::line_faults() const {
    std::lock_guard lock(impl_->mutex);
    return impl_->faults;
}

}  // namespace birdcage::sim
