// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// birdcage-regress: runs the core's operation sequence for a transcript against the emulator
// replaying that transcript in strict mode, and compares what the core did with the golden file
// beside it (gpsd's regress-driver, docs/transcripts.md).
//
//   birdcage-regress check TRANSCRIPT        compare with TRANSCRIPT's .chk (missing = failure)
//   birdcage-regress update TRANSCRIPT...    rewrite the .chk files
//   birdcage-regress draft --variant V --operations "OPS" [--booting] [--search] [--time-scale X]
//                                            run OPS against the model console and print the
//                                            session as a transcript (every chunk marked `~`)
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"
#include "console/fd_transport.hpp"
#include "console/session.hpp"
#include "dish/controller.hpp"
#include "firmware/protocol.hpp"
#include "firmware/variants.hpp"
#include "golden.hpp"

namespace {

using namespace std::chrono_literals;
namespace sim = birdcage::sim;

constexpr auto move_deadline = 30s;         // real time for one `move`, however the replay is paced
constexpr auto pump_period = 5ms;           // how often `move` calls Controller::service()
constexpr auto send_timeout = 3000ms;       // one `send` through the core's session
constexpr auto replay_drain_deadline = 3s;  // for the last recorded dish chunks to go out

// What the core wrote and what it learnt from the replies, in the order it happened: the golden
// file shows the knowledge between the commands that brought it.
struct JournalEntry {
    bool written = false;  // `text` is bytes the core wrote; otherwise a golden event line
    std::string text;
};

// Keeps every write the core makes, so the golden file can show the exact bytes it sent.
class RecordingTransport final : public birdcage::Transport {
public:
    RecordingTransport(birdcage::Transport& inner, std::vector<JournalEntry>& journal)
        : inner_(inner), journal_(journal) {}

    birdcage::Status write(std::string_view bytes, birdcage::Deadline deadline) override {
        journal_.push_back({true, std::string(bytes)});
        return inner_.write(bytes, deadline);
    }
    birdcage::Result<std::size_t> read(char* buf, std::size_t n, birdcage::Deadline deadline) override {
        return inner_.read(buf, n, deadline);
    }
    void discard_input() override { inner_.discard_input(); }

private:
    birdcage::Transport& inner_;
    std::vector<JournalEntry>& journal_;
};

// `init position move 180 45 send "d 20"`: whitespace-separated, double quotes group words and
// take the transcript escapes.
std::vector<std::string> split_operations(const std::string& text) {
    std::vector<std::string> tokens;
    std::size_t i = 0;
    while (i < text.size()) {
        if (text[i] == ' ' || text[i] == '\t') {
            ++i;
            continue;
        }
        if (text[i] == '"') {
            const std::size_t close = text.find('"', i + 1);
            if (close == std::string::npos)
                throw std::runtime_error("unterminated quote in operations: " + text);
            tokens.push_back(sim::unescape_chunk(text.substr(i + 1, close - i - 1)));
            i = close + 1;
            continue;
        }
        const std::size_t end = text.find_first_of(" \t", i);
        tokens.push_back(text.substr(i, end == std::string::npos ? std::string::npos : end - i));
        i = end == std::string::npos ? text.size() : end;
    }
    return tokens;
}

double number_token(const std::vector<std::string>& tokens, std::size_t index) {
    if (index >= tokens.size())
        throw std::runtime_error("operation needs more arguments");
    std::size_t used = 0;
    const double value = std::stod(tokens[index], &used);
    if (used != tokens[index].size())
        throw std::runtime_error("not a number: " + tokens[index]);
    return value;
}

using birdcage::golden::status_field;

// Runs the operations over `transport` and reports, one event a line, what the core did and saw.
class OperationRunner {
public:
    // `stop` is asked between operations and while a move runs: once the replay has failed the dish
    // is silent, and waiting out every timeout would only make the failure slow.
    OperationRunner(birdcage::Transport& transport, birdcage::VariantId variant, std::function<bool()> stop = {})
        : stop_(std::move(stop)),
          recorder_(transport, journal_),
          profile_(birdcage::profile(variant)),
          controller_(recorder_, make_options(variant, journal_sink())),
          session_(recorder_, profile_, {}) {
        session_.set_event_sink(journal_sink());
    }

    std::string run(const std::vector<std::string>& tokens) {
        std::ostringstream out;
        for (std::size_t i = 0; i < tokens.size();) {
            if (stop_ && stop_()) {
                out << "stopped: replay_failed\n";
                break;
            }
            const std::string& op = tokens[i++];
            if (op == "init") {
                out << "op init: " << status_field(controller_.initialize()) << '\n';
            } else if (op == "position") {
                const auto position = controller_.query_position();
                out << "op position: " << status_field(position.status);
                if (position)
                    out << " az=" << birdcage::format_degrees(position.value.az)
                        << " el=" << birdcage::format_degrees(position.value.el);
                out << '\n';
            } else if (op == "move") {
                const double az = number_token(tokens, i++);
                const double el = number_token(tokens, i++);
                out << "op move " << birdcage::format_degrees(az) << ' ' << birdcage::format_degrees(el) << ": "
                    << move(az, el) << '\n';
            } else if (op == "send") {
                if (i >= tokens.size())
                    throw std::runtime_error("send needs a command");
                const std::string command = tokens[i++];
                const auto reply = session_.transact(command, send_timeout);
                out << "op send " << birdcage::golden::quoted(command) << ": " << status_field(reply.status) << '\n';
                for (const auto& line : reply.value.lines)
                    out << "  line: " << birdcage::golden::quoted(line) << '\n';
                if (!reply.value.prompt.empty())
                    out << "  prompt: " << birdcage::golden::quoted(reply.value.prompt) << '\n';
            } else if (op == "resync") {
                const auto synced = session_.resync(send_timeout);
                out << "op resync: " << status_field(synced) << " menu=" << birdcage::golden::quoted(session_.menu())
                    << '\n';
            } else if (op == "home") {
                out << "op home: " << status_field(controller_.home()) << '\n';
            } else if (op == "request-moves") {
                session_.set_requests(session_.requests() | birdcage::request_move);
                out << "op request-moves\n";
            } else if (op == "allow-nvs-write") {
                session_.set_allow_nvs_write(true);
                out << "op allow-nvs-write\n";
            } else {
                throw std::runtime_error("unknown operation: " + op);
            }
            // How many pokes (bare line endings, `?`) the synchroniser needs depends on timing, not
            // on the dish: a run of them is one event in the golden file.
            // A `send` is the transcript's own command, written as it is.
            bool poking = false;
            for (const auto& entry : std::exchange(journal_, {})) {
                if (!entry.written) {
                    out << "  " << entry.text << '\n';
                    poking = false;
                    continue;
                }
                const std::string& bytes = entry.text;
                const bool poke = op != "send" && (bytes == "\r" || bytes == "\n" || bytes == "\r\n" ||
                                                   bytes == "?\r" || bytes == "?\n");
                if (poke && poking)
                    continue;
                poking = poke;
                out << "  sent: " << (poke ? std::string("pokes (\\r or ?\\r, one or more)") : sim::escape_chunk(bytes))
                    << '\n';
            }
        }
        for (const auto& line : birdcage::golden::state_lines(controller_))
            out << line << '\n';
        return out.str();
    }

private:
    birdcage::ConsoleEventSink journal_sink() {
        return [this](const birdcage::ConsoleEvent& event) {
            journal_.push_back({false, birdcage::golden::event_line(event)});
        };
    }

    static birdcage::ControllerOptions make_options(birdcage::VariantId variant, birdcage::ConsoleEventSink events) {
        birdcage::ControllerOptions options;
        options.variant = variant;
        options.console_events = std::move(events);
        // A replayed boot is paced by the transcript; a dish that never finishes should fail fast.
        options.boot_timeout = 20s;
        return options;
    }

    std::string move(double az, double el) {
        if (const auto accepted = controller_.set_target({az, el}); !accepted)
            return status_field(accepted);
        const auto deadline = std::chrono::steady_clock::now() + move_deadline;
        std::optional<birdcage::Status> first_failure;
        while (!controller_.idle()) {
            if (std::chrono::steady_clock::now() > deadline)
                return "error=not_idle_by_test_deadline";
            if (stop_ && stop_())
                return "stopped: replay_failed";
            if (const auto status = controller_.service(); !status && !first_failure)
                first_failure = status;
            std::this_thread::sleep_for(pump_period);
        }
        return first_failure ? status_field(*first_failure) : "ok";
    }

    std::function<bool()> stop_;
    std::vector<JournalEntry> journal_;
    RecordingTransport recorder_;
    const birdcage::FirmwareProfile& profile_;
    birdcage::Controller controller_;
    // For `send`/`resync`: the core's session (hazard guard, framer) without the controller.
    birdcage::ConsoleSession session_;
};

birdcage::VariantId variant_of(const std::string& name) {
    const auto variant = birdcage::variant_from_name(name);
    if (!variant)
        throw std::runtime_error("unknown variant \"" + name + "\"");
    return *variant;
}

std::unique_ptr<birdcage::FdTransport> open_device(const std::string& path, int baud) {
    auto opened = birdcage::FdTransport::open(path, baud);
    if (!opened)
        throw std::runtime_error("cannot open " + path + ": " + opened.status.message);
    return std::move(opened.value);
}

std::filesystem::path golden_path(const std::filesystem::path& transcript) {
    auto golden = transcript;
    return golden.replace_extension(".chk");
}

// What the golden file holds for one transcript; `failed` when the replay itself went wrong.
struct Outcome {
    std::string text;
    bool failed = false;
};

Outcome replay(const std::filesystem::path& transcript_path) {
    const sim::Transcript transcript = sim::load_transcript(transcript_path.string());
    const auto variant_name = transcript.header("Variant");
    const auto operations = transcript.header("Operations");
    if (!variant_name || !operations)
        throw std::runtime_error(transcript_path.string() + ": needs # Variant: and # Operations: headers");
    const auto sim_variant = sim::parse_variant(*variant_name);
    if (!sim_variant)
        throw std::runtime_error("the emulator does not know variant " + *variant_name);

    sim::Options options;
    options.variant = *sim_variant;
    options.transcript_path = transcript_path.string();
    options.replay = sim::ReplayMode::strict;
    options.time_scale = transcript.header("Time-Scale") ? std::stod(*transcript.header("Time-Scale")) : 1.0;
    sim::Emulator emulator(options);

    const auto variant = variant_of(*variant_name);
    auto device = open_device(emulator.device_path(), birdcage::profile(variant).baud);
    OperationRunner runner(*device, variant, [&emulator] { return emulator.replay_failure().has_value(); });

    Outcome outcome;
    outcome.text = "# birdcage-regress events for " + transcript_path.filename().string() +
                   " (format: docs/transcripts.md). Lines starting with # are notes, kept by\n"
                   "# regress-update; regenerate with that target and explain every change in the commit message.\n";
    outcome.text += "operations: " + *operations + "\n";
    outcome.text += runner.run(split_operations(*operations));

    const auto drain_until = std::chrono::steady_clock::now() + replay_drain_deadline;
    while (!emulator.replay_complete() && !emulator.replay_failure() && std::chrono::steady_clock::now() < drain_until)
        std::this_thread::sleep_for(10ms);
    if (const auto failure = emulator.replay_failure()) {
        // The emulator's report (which line, what was expected) goes to stderr: it is for the
        // person reading the failure, not for comparison.
        outcome.text += "replay: failed\n";
        std::cerr << *failure;
        outcome.failed = true;
    } else if (!emulator.replay_complete()) {
        // The core sent fewer commands than the transcript holds.
        outcome.text += "replay: incomplete\n";
        outcome.failed = true;
    } else {
        outcome.text += "replay: complete\n";
    }
    return outcome;
}

std::string read_file(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    std::ostringstream contents;
    contents << file.rdbuf();
    return contents.str();
}

void print_difference(const std::string& expected, const std::string& actual) {
    const auto want = birdcage::golden::content_lines(expected);
    const auto got = birdcage::golden::content_lines(actual);
    for (std::size_t i = 0; i < std::max(want.size(), got.size()); ++i) {
        const std::string* w = i < want.size() ? &want[i] : nullptr;
        const std::string* g = i < got.size() ? &got[i] : nullptr;
        if (w && g && *w == *g)
            continue;
        std::cerr << "first difference at event " << i + 1 << " of the golden file (# lines not counted):\n"
                  << "  golden: " << (w ? *w : "<end of file>") << '\n'
                  << "  now:    " << (g ? *g : "<end of file>") << '\n';
        break;
    }
    std::cerr << "--- full output now ---\n" << actual;
}

int check(const std::filesystem::path& transcript) {
    const Outcome outcome = replay(transcript);
    const auto golden = golden_path(transcript);
    if (!std::filesystem::exists(golden)) {
        std::cerr << "missing golden file " << golden << " (a missing file is a failure); create it with "
                  << "`cmake --build <build dir> --target regress-update` and say why in the commit message\n"
                  << "--- output now ---\n"
                  << outcome.text;
        return 1;
    }
    const std::string expected = read_file(golden);
    // Notes (`#` lines) are the reader's; only the events are compared.
    if (birdcage::golden::content_lines(expected) != birdcage::golden::content_lines(outcome.text)) {
        std::cerr << "regression: " << transcript.filename().string() << " differs from " << golden.filename().string()
                  << '\n';
        print_difference(expected, outcome.text);
        return 1;
    }
    if (outcome.failed)
        return 1;
    std::cout << outcome.text;
    return 0;
}

int update(const std::vector<std::filesystem::path>& transcripts) {
    int status = 0;
    for (const auto& transcript : transcripts) {
        const Outcome outcome = replay(transcript);
        if (outcome.failed) {
            std::cerr << "not updating " << golden_path(transcript) << ": the replay failed\n";
            status = 1;
            continue;
        }
        std::string text = outcome.text;
        if (std::filesystem::exists(golden_path(transcript))) {
            std::vector<std::string> dropped;
            text = birdcage::golden::keep_annotations(read_file(golden_path(transcript)), outcome.text, dropped);
            for (const auto& note : dropped)
                std::cerr << golden_path(transcript).string()
                          << ": note dropped, the event it preceded is gone: " << note << '\n';
        }
        std::ofstream(golden_path(transcript), std::ios::binary) << text;
        std::cout << "wrote " << golden_path(transcript).string() << '\n';
    }
    return status;
}

int draft(int argc, char** argv) {
    sim::Options options;
    std::string variant_name, operations;
    options.time_scale = 1.0;
    for (int i = 0; i < argc; ++i) {
        const std::string arg = argv[i];
        const bool has_value = i + 1 < argc;
        if (arg == "--variant" && has_value)
            variant_name = argv[++i];
        else if (arg == "--operations" && has_value)
            operations = argv[++i];
        else if (arg == "--time-scale" && has_value)
            options.time_scale = std::stod(argv[++i]);
        else if (arg == "--booting")
            options.already_booted = false;
        else if (arg == "--search")
            options.search_running = true;
        else
            throw std::runtime_error("draft: unknown argument " + arg);
    }
    const auto sim_variant = sim::parse_variant(variant_name);
    if (!sim_variant)
        throw std::runtime_error("draft: --variant is required");
    options.variant = *sim_variant;

    const auto variant = variant_of(variant_name);
    const auto& profile = birdcage::profile(variant);
    std::mutex mutex;
    sim::TranscriptRecorder recorder({{"Variant", variant_name},
                                      {"Firmware", std::string(profile.display_name)},
                                      {"Serial", std::to_string(profile.baud) + " 8N1"},
                                      {"Source", "drafted with birdcage-regress draft against the emulator model"},
                                      {"Reconstructed", "every chunk (`~`)"},
                                      {"Operations", operations},
                                      {"Time-Scale", std::to_string(options.time_scale)}});
    const auto start = std::chrono::steady_clock::now();
    const double scale = options.time_scale;
    options.trace = [&](bool from_client, std::string_view bytes) {
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * scale;
        std::lock_guard lock(mutex);
        recorder.add(from_client ? sim::Direction::host_to_dish : sim::Direction::dish_to_host, bytes, seconds, true);
    };
    {
        sim::Emulator emulator(options);
        auto device = open_device(emulator.device_path(), profile.baud);
        OperationRunner runner(*device, variant);
        std::cerr << runner.run(split_operations(operations));
        std::this_thread::sleep_for(300ms);
    }
    std::cout << recorder.text();
    return 0;
}

void usage() {
    std::cerr << "usage: birdcage-regress check TRANSCRIPT | update TRANSCRIPT... |\n"
                 "       draft --variant V --operations OPS [--booting] [--search] [--time-scale X]\n";
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        usage();
        return 2;
    }
    const std::string mode = argv[1];
    try {
        if (mode == "check" && argc == 3)
            return check(argv[2]);
        if (mode == "update" && argc >= 3)
            return update({argv + 2, argv + argc});
        if (mode == "draft")
            return draft(argc - 2, argv + 2);
    } catch (const std::exception& error) {
        std::cerr << "birdcage-regress: " << error.what() << '\n';
        return 1;
    }
    usage();
    return 2;
}
