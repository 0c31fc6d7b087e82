// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// libFuzzer target: the emulator's transcript reader (sim/src/transcript.cpp). Properties: no crash
// (malformed input throws TranscriptError only); every parsed entry formats back to a line that
// parses to the same direction, bytes and marker; escape/unescape round-trips arbitrary bytes.
#include "birdcage_sim/transcript.hpp"

#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

namespace {
void require(bool ok) {
    if (!ok) {
        std::abort();
    }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    using namespace birdcage::sim;

    require(unescape_chunk(escape_chunk(text)) == text);

    Transcript parsed;
    try {
        parsed = parse_transcript(text);
    } catch (const TranscriptError&) {
        return 0;
    }
    for (const TranscriptEntry& entry : parsed.entries) {
        const std::string line = format_entry(entry) + "\n";
        const Transcript again = parse_transcript(line);
        require(again.entries.size() == 1);
        require(again.entries[0].direction == entry.direction);
        require(again.entries[0].bytes == entry.bytes);
        require(again.entries[0].reconstructed == entry.reconstructed);
    }
    return 0;
}
