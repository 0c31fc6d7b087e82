#include "birdcage_sim/emulator.hpp"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <mutex>
#include <poll.h>
#include <system_error>
#include <thread>
#include <unistd.h>

#include "birdcage_sim/console.hpp"
#include "pty.hpp"
#include "replay.hpp"

namespace birdcage::sim {
namespace {

constexpr int poll_timeout_ms = 2;
// A client that never reads must not make the emulator hoard memory; older bytes go first,
// as a UART FIFO would lose them.
constexpr std::size_t max_unsent_bytes = 1 << 20;

}  // namespace

struct Emulator::Impl {
    explicit Impl(Options opts) : options(std::move(opts)), console(options)
    {
        if (options.replay != ReplayMode::off)
            replayer.emplace(load_transcript(options.transcript_path), options.replay, options.transcript_path);
        device_path = pty.slave_path();
        if (!options.link_path.empty()) {
            ::unlink(options.link_path.c_str());
            if (::symlink(pty.slave_path().c_str(), options.link_path.c_str()) != 0)
                throw std::system_error(errno, std::generic_category(), "symlink " + options.link_path);
            device_path = options.link_path;
        }
        thread = std::thread([this] { run(); });
    }

    ~Impl()
    {
        stopping = true;
        thread.join();
        if (!options.link_path.empty()) ::unlink(options.link_path.c_str());
    }

    void run()
    {
        using clock = std::chrono::steady_clock;
        auto last = clock::now();
        std::string unsent;
        char buffer[4096];
        while (!stopping) {
            pollfd descriptor{pty.master(), static_cast<short>(POLLIN | (unsent.empty() ? 0 : POLLOUT)), 0};
            const int ready = ::poll(&descriptor, 1, poll_timeout_ms);
            std::string received;
            if (ready > 0 && (descriptor.revents & POLLIN) != 0) {
                const ssize_t count = ::read(pty.master(), buffer, sizeof buffer);
                if (count > 0) received.assign(buffer, static_cast<std::size_t>(count));
            }
            if (ready > 0 && (descriptor.revents & (POLLHUP | POLLERR)) != 0)
                std::this_thread::sleep_for(std::chrono::milliseconds(poll_timeout_ms));
            const auto now = clock::now();
            const double dt = std::chrono::duration<double>(now - last).count() * options.time_scale;
            last = now;
            std::string sent;
            {
                std::lock_guard lock(mutex);
                if (replayer && (replayer->replaying() || replayer->failure())) {
                    // The model keeps its own time but stays silent until a lenient fallback.
                    const std::string unmatched = replayer->receive(received);
                    replayer->advance(dt);
                    sent = replayer->take_output();
                    if (!unmatched.empty()) console.feed(unmatched);
                    console.advance(dt);
                    const std::string model_output = console.take_output();
                    if (replayer->fell_back()) sent += model_output;
                } else {
                    if (!received.empty()) console.feed(received);
                    console.advance(dt);
                    sent = console.take_output();
                }
            }
            if (options.trace) {
                if (!received.empty()) options.trace(true, received);
                if (!sent.empty()) options.trace(false, sent);
            }
            unsent += sent;
            if (unsent.size() > max_unsent_bytes) unsent.erase(0, unsent.size() - max_unsent_bytes);
            if (!unsent.empty()) {
                const ssize_t count = ::write(pty.master(), unsent.data(), unsent.size());
                if (count > 0) unsent.erase(0, static_cast<std::size_t>(count));
            }
        }
    }

    Options options;
    Pty pty;
    mutable std::mutex mutex;
    Console console;
    std::optional<Replayer> replayer;
    std::string device_path;
    std::atomic<bool> stopping{false};
    std::thread thread;
};

Emulator::Emulator(Options options) : impl_(std::make_unique<Impl>(std::move(options))) {}
Emulator::~Emulator() = default;

const std::string& Emulator::device_path() const { return impl_->device_path; }

Pose Emulator::true_position() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.position();
}

double Emulator::true_mechanical_az() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.mechanical_az();
}

bool Emulator::moving() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.moving();
}

bool Emulator::search_running() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.search_running();
}

bool Emulator::shell_alive() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.shell_alive();
}

std::vector<Sample> Emulator::history() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.history();
}

unsigned Emulator::hazards_received() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.hazards();
}

std::vector<std::string> Emulator::received_commands() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.commands();
}

double Emulator::sim_time() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->console.time();
}

std::optional<std::string> Emulator::replay_failure() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer ? impl_->replayer->failure() : std::nullopt;
}

bool Emulator::replay_complete() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer && impl_->replayer->complete();
}

bool Emulator::replay_fell_back() const
{
    std::lock_guard lock(impl_->mutex);
    return impl_->replayer && impl_->replayer->fell_back();
}

void Emulator::power_cycle()
{
    std::lock_guard lock(impl_->mutex);
    impl_->console.power_cycle();
}

}  // namespace birdcage::sim
