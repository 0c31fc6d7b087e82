#include "replay.hpp"

#include <utility>

namespace birdcage::sim {
namespace {

// Context in a failure report: this many chunks before the divergence.
constexpr std::size_t context_chunks = 3;

}  // namespace

Replayer::Replayer(Transcript transcript, ReplayMode mode, std::string source)
    : transcript_(std::move(transcript)), mode_(mode), source_(std::move(source))
{
    pump();
}

std::string Replayer::receive(std::string_view bytes)
{
    if (fell_back_) return std::string(bytes);
    if (failure_) return {};
    input_.append(bytes);
    pump();
    return std::exchange(fallback_bytes_, {});
}

void Replayer::advance(double dt)
{
    now_ += dt;
    pump();
}

std::string Replayer::take_output() { return std::exchange(output_, {}); }

void Replayer::pump()
{
    while (replaying() && next_ < transcript_.entries.size()) {
        const TranscriptEntry& entry = transcript_.entries[next_];
        if (entry.direction == Direction::dish_to_host) {
            const double due = last_event_ + entry.delay_ms / 1000.0;
            if (now_ < due) return;
            output_ += entry.bytes;
            last_event_ = due;
            ++next_;
            continue;
        }
        // Host chunks are matched as a byte stream: how the client's writes were split does not matter.
        std::size_t used = 0;
        while (used < input_.size() && matched_ < entry.bytes.size() && input_[used] == entry.bytes[matched_]) {
            ++used;
            ++matched_;
        }
        if (matched_ < entry.bytes.size() && used < input_.size()) {
            diverge(entry.bytes.substr(0, matched_) + input_, "");
            return;
        }
        input_.erase(0, used);
        if (matched_ < entry.bytes.size()) return;  // wait for the rest of the command
        matched_ = 0;
        last_event_ = now_;
        ++next_;
    }
    if (replaying() && next_ == transcript_.entries.size() && !input_.empty())
        diverge(std::exchange(input_, {}), "the transcript has ended");
}

void Replayer::diverge(std::string received, const std::string& why)
{
    input_.clear();
    matched_ = 0;
    if (mode_ == ReplayMode::lenient) {
        fell_back_ = true;
        fallback_bytes_ = std::move(received);
        return;
    }
    const auto& entries = transcript_.entries;
    std::string report = "replay of " + source_ + " failed: ";
    if (next_ < entries.size()) {
        const TranscriptEntry& expected = entries[next_];
        report += "unexpected command at line " + std::to_string(expected.line_number) + "\n";
        for (std::size_t i = next_ > context_chunks ? next_ - context_chunks : 0; i < next_; ++i)
            report += "  line " + std::to_string(entries[i].line_number) + ":  " + format_entry(entries[i]) + "\n";
        report += "  expected:  > " + escape_chunk(expected.bytes) + "\n";
    } else {
        report += "unexpected bytes after the last line (" + why + ")\n";
    }
    report += "  received:  > " + escape_chunk(received) + "\n";
    failure_ = std::move(report);
}

}  // namespace birdcage::sim
