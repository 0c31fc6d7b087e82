// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// libFuzzer target: the console synchroniser and auto-detection against a console scripted by the
// input: random interleavings of boot lines, prompts, echoes, line endings and garbage, each chunk
// either waiting in the buffer, answering the next line ending, or arriving later.
// Properties: the synchroniser returns within its budget (counted in the reads the fake serves);
// a prompt it reports ends the console text it read (only line noise may follow it); detection never sends `q` while the
// console's output ends at the G2 root prompt with G2 evidence in it.
#include "console/detect.hpp"
#include "console/synchroniser.hpp"
#include "firmware/prompt.hpp"
#include "firmware/variants.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <string>
#include <string_view>

namespace {

using namespace std::chrono_literals;

constexpr std::array<std::string_view, 16> pieces{"Bootloader v1.01",
                                                  "Ant ID - 12-IN G2",
                                                  "Boot Complete",
                                                  "Loc Startup: IDU NOT Present",
                                                  "NoGPS",
                                                  "No LNB Voltage",
                                                  "TRK>",
                                                  "MOT>",
                                                  "NVS> ",
                                                  ">",
                                                  "Enter <a3981> - A3981 menu",
                                                  "mot os nvs",
                                                  "odu - Connect to ODU",
                                                  "target",
                                                  "a - position",
                                                  "help [<command>]"};
constexpr std::array<std::string_view, 4> endings{"\r\n", "\n", "\r", ""};

// The scripted console. Every read that finds nothing queued counts; the synchroniser's budget
// in reads is bounded by budget / (shortest wait), far below the limit checked here.
class ScriptedConsole final : public birdcage::Transport {
public:
    explicit ScriptedConsole(std::string_view script) : script_(script) {}

    birdcage::Status write(std::string_view bytes, birdcage::Deadline) override {
        for (char c : bytes) {
            if (c == '\r' || c == '\n') {
                sent_.push_back(line_);
                if (line_ == "q" && last_output_ends_g2_root()) {
                    std::abort();  // `q` at the G2 root
                }
                line_.clear();
                queued_.push_back(next_chunk());
            } else {
                line_ += c;
            }
        }
        return birdcage::Status::ok();
    }

    birdcage::Result<std::size_t> read(char* buf, std::size_t n, birdcage::Deadline) override {
        if (++reads_ > 200000) {
            std::abort();  // hangs past any budget
        }
        if (queued_.empty() && !later_.empty()) {
            queued_.push_back(later_.front());
            later_.pop_front();
            return {0, {birdcage::Errc::timeout, "later"}};
        }
        if (queued_.empty() || queued_.front().empty()) {
            if (!queued_.empty()) {
                queued_.pop_front();
            }
            return {0, {birdcage::Errc::timeout, "nothing"}};
        }
        std::string& chunk = queued_.front();
        const std::size_t count = std::min(n, chunk.size());
        chunk.copy(buf, count);
        output_.append(chunk, 0, count);
        chunk.erase(0, count);
        if (chunk.empty()) {
            queued_.pop_front();
        }
        return {count, birdcage::Status::ok()};
    }

    void discard_input() override { queued_.clear(); }

    void preload() {
        for (int i = 0; i < 3 && at_ < script_.size(); ++i) {
            later_.push_back(next_chunk());
        }
    }
    const std::string& output() const { return output_; }

private:
    std::string next_chunk() {
        std::string chunk;
        while (at_ < script_.size()) {
            const auto op = static_cast<unsigned char>(script_[at_++]);
            switch (op % 5) {
                case 0:
                    return chunk;  // end of this chunk
                case 1:
                    chunk += pieces[(op / 5) % pieces.size()];
                    break;
                case 2:
                    chunk += endings[(op / 5) % endings.size()];
                    break;
                case 3:
                    chunk += static_cast<char>(op ^ 0x5a);
                    break;  // garbage, NULs included
                case 4:
                    chunk += line_;
                    break;  // an echo
            }
        }
        return chunk;
    }
    // The G2 root: its prompt, with the G2's evidence in sight (its root listing or boot lines).
    bool last_output_ends_g2_root() const {
        return birdcage::trailing_prompt(output_) == "TRK>" &&
               (output_.find("a3981") != std::string::npos || output_.find("Ant ID") != std::string::npos ||
                output_.find("Bootloader") != std::string::npos);
    }

    std::string_view script_;
    std::size_t at_ = 0;
    std::deque<std::string> queued_, later_;
    std::vector<std::string> sent_;
    std::string line_;
    std::string output_;
    std::size_t reads_ = 0;
};

// After `prompt` and its decoration marks, at one of its places in `output`, comes no console text: on the prompt's own
// line neither clean printable text (one space aside) nor mostly printable text around noise
// bytes; no later line of mostly printable bytes. Line noise (random bytes, most of them
// unprintable, possibly with a `TRK>` among them) may follow. Any place will do: a reply read
// after a poke starts a line of its own, wherever the output before it stopped.
bool ends_text_at(std::string_view output, std::size_t at, std::string_view prompt) {
    // The prompt as the console printed it, its decoration marks after '>' (`TRK>$`) included: the
    // prompt rule's own reading (src/core/firmware/prompt.hpp).
    std::string_view rest =
        output.substr(at + std::max(prompt.size(), birdcage::leading_prompt_length(output.substr(at))));
    std::size_t text = 0;
    std::size_t noise = 0;
    bool prompt_line = true;
    auto is_text_segment = [&] {
        if (prompt_line && noise == 0 && text == 1 && rest.front() == ' ') {
            return false;
        }
        return text > 0 && noise * 4 <= text;
    };
    for (char c : rest) {
        if (c == '\r' || c == '\n') {
            if (is_text_segment()) {
                return false;
            }
            text = noise = 0;
            prompt_line = false;
        } else if ((c >= 0x20 && c < 0x7f) || c == '\t') {
            ++text;
        } else {
            ++noise;
        }
    }
    return !is_text_segment();
}

bool prompt_ends_text(std::string_view output, std::string_view prompt) {
    for (std::size_t at = output.find(prompt); at != std::string_view::npos; at = output.find(prompt, at + 1)) {
        if (ends_text_at(output, at, prompt)) {
            return true;
        }
    }
    return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) {
        return 0;
    }
    const std::string_view script(reinterpret_cast<const char*>(data) + 1, size - 1);
    const auto budget = std::chrono::milliseconds(1000 + 1000 * (data[0] % 8));
    {
        ScriptedConsole console(script);
        console.preload();
        birdcage::ConsoleSynchroniser sync(
            console, birdcage::console_sync_settings(birdcage::profile(birdcage::VariantId::carryout_g2), budget), {},
            birdcage::DishClock::manual([] { return birdcage::Clock::time_point{}; }));
        const auto synced = sync.synchronise();
        if (synced && !synced.value.prompt.empty() && !prompt_ends_text(console.output(), synced.value.prompt)) {
            std::abort();  // a prompt that console text came after
        }
    }
    {
        ScriptedConsole console(script);
        console.preload();
        (void)birdcage::detect_variant(console, {}, budget);
    }
    return 0;
}
