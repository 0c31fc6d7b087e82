// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The transcript format and the emulator's replay modes. Uses only the emulator's side plus the
// core's FdTransport as a client, the way the regression tests drive it.
#include <catch2/catch.hpp>

#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "birdcage_sim/emulator.hpp"
#include "birdcage_sim/transcript.hpp"
#include "console/fd_transport.hpp"
#include "dish/controller.hpp"
#include "golden.hpp"

namespace sim = birdcage::sim;
using namespace std::chrono_literals;

namespace {

constexpr auto reply_deadline = 3s;

const char* const g2_two_queries =
    "# Variant: g2\n"
    "# Source: test\n"
    ">~ \\r\n"
    "<~ \\r\\nTRK>\n"
    ">~ mot\\r\n"
    "<~ @+20ms mot\\r\\nMOT>\n"
    "# a comment between chunks\n"
    ">~ a\\r\n"
    "<~ a\\r\\nAngle[0] = 180.00\\r\\nAngle[1] = 45.00\\r\\nMOT>\n";

struct TempTranscript {
    explicit TempTranscript(const std::string& text)
        : path(std::filesystem::temp_directory_path() /
               ("birdcage-replay-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".log")) {
        std::ofstream(path) << text;
    }
    ~TempTranscript() { std::filesystem::remove(path); }
    std::filesystem::path path;
    static inline int counter = 0;
};

struct Client {
    explicit Client(const std::string& device)
        : transport(std::move(birdcage::FdTransport::open(device, 115200).value)) {}

    void send(std::string_view bytes) { REQUIRE(transport->write(bytes, birdcage::Clock::now() + 1s)); }

    // Reads until `ending` arrives or the deadline passes; returns everything read.
    std::string read_until(std::string_view ending, std::chrono::milliseconds patience = reply_deadline) {
        std::string text;
        const auto deadline = birdcage::Clock::now() + patience;
        char buffer[256];
        while (text.find(ending) == std::string::npos) {
            const auto got = transport->read(buffer, sizeof buffer, deadline);
            if (!got)
                break;
            text.append(buffer, got.value);
        }
        return text;
    }

    // The recorded G2 sessions' opening: a poke at the root, then `mot`.
    void enter_motor_menu() {
        send("\r");
        read_until("TRK>");
        send("mot\r");
        read_until("MOT>");
    }

    std::unique_ptr<birdcage::FdTransport> transport;
};

sim::Options replay_options(const TempTranscript& transcript, sim::ReplayMode mode) {
    sim::Options options;
    options.variant = sim::Variant::carryout_g2;
    options.transcript_path = transcript.path.string();
    options.replay = mode;
    options.time_scale = 10.0;
    return options;
}

template <class Predicate>
bool eventually(Predicate predicate) {
    const auto deadline = std::chrono::steady_clock::now() + reply_deadline;
    while (!predicate()) {
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(5ms);
    }
    return true;
}

}  // namespace

TEST_CASE("transcript: headers, directions, timing, markers and line numbers are parsed") {
    const auto transcript = sim::parse_transcript(g2_two_queries);
    CHECK(transcript.header("Variant") == "g2");
    CHECK_FALSE(transcript.header("Operations"));
    REQUIRE(transcript.entries.size() == 6);
    CHECK(transcript.entries[0].direction == sim::Direction::host_to_dish);
    CHECK(transcript.entries[0].bytes == "\r");
    CHECK(transcript.entries[0].reconstructed);
    CHECK(transcript.entries[3].delay_ms == 20.0);
    CHECK(transcript.entries[3].bytes == "mot\r\nMOT>");
    CHECK(transcript.entries[4].line_number == 8);
}

TEST_CASE("transcript: escapes round-trip every byte value") {
    std::string all;
    for (int byte = 0; byte < 256; ++byte)
        all += static_cast<char>(byte);
    CHECK(sim::unescape_chunk(sim::escape_chunk(all)) == all);
    CHECK(sim::escape_chunk(" Saving ... ") == "\\x20Saving ...\\x20");
    CHECK(sim::escape_chunk("a\\b\r\n\x01") == "a\\\\b\\r\\n\\x01");
}

TEST_CASE("transcript: a malformed line is reported with its line number") {
    CHECK_THROWS_WITH(sim::parse_transcript("# Variant: g2\n> ok\\r\nhello\n"), Catch::Contains("line 3"));
    CHECK_THROWS_WITH(sim::parse_transcript("> bad \\q escape\n"), Catch::Contains("line 1"));
    CHECK_THROWS_WITH(sim::parse_transcript("< @+fast x\n"), Catch::Contains("timing"));
}

TEST_CASE("transcript: what the fuzzer found formats back to the same entry (timing-like bytes, huge delays)") {
    sim::TranscriptEntry entry;
    entry.direction = sim::Direction::host_to_dish;
    entry.bytes = "@+0mss cade:";
    const auto again = sim::parse_transcript(sim::format_entry(entry) + "\n");
    REQUIRE(again.entries.size() == 1);
    CHECK(again.entries[0].bytes == entry.bytes);
    CHECK(again.entries[0].delay_ms == 0.0);
    // A delay no recording can have is a malformed line, not a number printed back differently.
    CHECK_THROWS_WITH(sim::parse_transcript("> @+96655555555555560604613273883s x\n"), Catch::Contains("timing"));
    CHECK(sim::parse_transcript("< @+86400s x\n").entries.at(0).delay_ms == 86400000.0);
}

TEST_CASE("transcript: the recorder writes what the parser reads back") {
    sim::TranscriptRecorder recorder(std::vector<std::pair<std::string, std::string>>{{"Variant", "g2"}});
    recorder.add(sim::Direction::host_to_dish, "a\r", 1.0);
    recorder.add(sim::Direction::dish_to_host, "a\r\nMOT>", 1.25, true);
    const auto transcript = sim::parse_transcript(recorder.text());
    REQUIRE(transcript.entries.size() == 2);
    CHECK_FALSE(transcript.entries[0].reconstructed);
    CHECK(transcript.entries[1].reconstructed);
    CHECK(transcript.entries[1].delay_ms == 250.0);
    CHECK(transcript.entries[1].bytes == "a\r\nMOT>");
}

TEST_CASE("emulator: strict mode answers each expected command with the recorded bytes") {
    const TempTranscript transcript(g2_two_queries);
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.send("\r");
    CHECK(client.read_until("TRK>") == "\r\nTRK>");
    client.send("mo");  // a command split over two writes is still one command
    client.send("t\r");
    CHECK(client.read_until("MOT>") == "mot\r\nMOT>");
    client.send("a\r");
    CHECK(client.read_until("MOT>").find("Angle[1] = 45.00") != std::string::npos);
    CHECK(eventually([&] { return dish.replay_complete(); }));
    CHECK_FALSE(dish.replay_failure());
}

TEST_CASE("emulator: strict mode stops at a wrong command with a diff naming the line") {
    const TempTranscript transcript(g2_two_queries);
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.send("\r");
    client.read_until("TRK>");
    client.send("a 0 90.00\r");  // the transcript expects `mot` first
    REQUIRE(eventually([&] { return dish.replay_failure().has_value(); }));
    const std::string failure = *dish.replay_failure();
    CHECK_THAT(failure, Catch::Contains("line 5"));
    CHECK_THAT(failure, Catch::Contains("expected:  > mot\\r"));
    CHECK_THAT(failure, Catch::Contains("received:  > a 0 90.00\\r"));
    CHECK_THAT(failure, Catch::Contains("<~ \\r\\nTRK>"));  // context before the divergence
    CHECK(client.read_until("MOT>", 300ms).empty());        // and the dish says nothing more
    CHECK_FALSE(dish.replay_complete());
}

TEST_CASE("emulator: strict mode fails on bytes after the end of the transcript") {
    const TempTranscript transcript("# Variant: g2\n> \\r\n< \\r\\nTRK>\n");
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.send("\r");
    client.read_until("TRK>");
    client.send("mot\r");
    REQUIRE(eventually([&] { return dish.replay_failure().has_value(); }));
    CHECK_THAT(*dish.replay_failure(), Catch::Contains("after the last line"));
}

TEST_CASE("emulator: strict mode answers unrecorded pokes as the firmware does and goes on") {
    // How many line endings a synchronising client sends depends on timing, not on the dish.
    const TempTranscript transcript("# Variant: g2\n> \\r\n< \\r\\nTRK>\n> mot\\r\n< mot\\r\\nMOT>\n");
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.send("\r");
    client.read_until("TRK>");
    client.send("\r");  // not recorded: the prompt again (docs/firmware.md 6.1)
    client.read_until("TRK>");
    client.send("?\r");  // not recorded: ignored, never answered from nothing
    client.send("mot\r");
    client.read_until("MOT>");
    CHECK_FALSE(dish.replay_failure().has_value());
    CHECK(dish.replay_complete());
}

TEST_CASE("emulator: strict mode answers a position read repeated at rest with its recorded reply") {
    // A client that wants two readings a span apart reads again where the recorded one moved on.
    const std::string text = std::string(g2_two_queries) + "> a 0 90.00\\r\n< a 0 90.00\\r\\nMOT>\n";
    const TempTranscript transcript(text);
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.enter_motor_menu();
    client.send("a\r");
    CHECK(client.read_until("MOT>").find("Angle[0] = 180.00") != std::string::npos);
    client.send("a\r");  // not recorded: the same reading again (its `a` shares a byte with `a 0 90.00`)
    CHECK(client.read_until("MOT>").find("Angle[0] = 180.00") != std::string::npos);
    client.send("a 0 90.00\r");
    CHECK(client.read_until("MOT>").find("a 0 90.00") != std::string::npos);
    CHECK(eventually([&] { return dish.replay_complete(); }));
    CHECK_FALSE(dish.replay_failure());
}

TEST_CASE("emulator: strict mode does not repeat a command that is not a position read") {
    const TempTranscript transcript(g2_two_queries);
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    Client client(dish.device_path());
    client.enter_motor_menu();
    client.send("mot\r");  // a menu word changes the console's state: never answered from nothing
    REQUIRE(eventually([&] { return dish.replay_failure().has_value(); }));
    CHECK_THAT(*dish.replay_failure(), Catch::Contains("received:  > mot\\r"));
}

TEST_CASE("emulator: lenient mode hands a wrong command to the model console") {
    const TempTranscript transcript(g2_two_queries);
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::lenient));
    Client client(dish.device_path());
    client.send("\r");
    client.read_until("TRK>");
    client.send("dvb\r");
    CHECK(client.read_until("DVB>").find("DVB>") != std::string::npos);
    CHECK(dish.replay_fell_back());
    CHECK_FALSE(dish.replay_failure());
}

TEST_CASE("emulator: recorded timing is divided by the time scale") {
    // An hour recorded: unscaled, the reply could never arrive within the read's patience (30 s,
    // far beyond any scheduling delay); divided by 3600 it takes a second. The only tight bound
    // is a lower one: the reply must not come before its scaled delay.
    const TempTranscript transcript("# Variant: g2\n> \\r\n< @+3600s \\r\\nTRK>\n");
    auto options = replay_options(transcript, sim::ReplayMode::strict);
    options.time_scale = 3600.0;
    sim::Emulator dish(options);
    Client client(dish.device_path());
    const auto start = std::chrono::steady_clock::now();
    client.send("\r");
    CHECK(client.read_until("TRK>", 30s) == "\r\nTRK>");
    CHECK(std::chrono::steady_clock::now() - start >= 900ms);
}

TEST_CASE("emulator: a broken transcript is refused when the emulator starts") {
    const TempTranscript transcript("# Variant: g2\nnot a chunk\n");
    CHECK_THROWS_AS(sim::Emulator(replay_options(transcript, sim::ReplayMode::strict)), sim::TranscriptError);
}

TEST_CASE("events: a replayed G2 session yields the menus reached and a parsed position per reply, in order") {
    // The regression tests' golden files print these between the `sent:` lines; a reply the core
    // stopped reporting would vanish from them unnoticed were it not checked here as well.
    const TempTranscript transcript(std::string(g2_two_queries) +
                                    ">~ a\\r\n"
                                    "<~ a\\r\\nAngle[0] = 180.25\\r\\nAngle[1] = 45.10\\r\\nMOT>\n");
    sim::Emulator dish(replay_options(transcript, sim::ReplayMode::strict));
    auto device = birdcage::FdTransport::open(dish.device_path(), 115200);
    REQUIRE(device);
    std::vector<std::string> events;
    birdcage::ControllerOptions options;
    options.variant = birdcage::VariantId::carryout_g2;
    options.console_events = [&events](const birdcage::ConsoleEvent& event) {
        events.push_back(birdcage::golden::event_line(event));
    };
    birdcage::Controller controller(*device.value, options);
    REQUIRE(controller.initialize());
    REQUIRE(controller.query_position());

    CHECK(events == std::vector<std::string>{
                        "reached: menu=\"root\" prompt=\"TRK>\"",
                        "reached: menu=\"mot\" prompt=\"MOT>\"",
                        "parsed: position az=180.00 el=45.00",
                        "parsed: position az=180.25 el=45.10",
                    });
    CHECK(eventually([&] { return dish.replay_complete(); }));
    CHECK_FALSE(dish.replay_failure());
}
