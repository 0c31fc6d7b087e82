// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Console transcripts (docs/transcripts.md): a recorded session between a host and a dish, one
// chunk per line with its direction, optional timing and C-style escapes. This is the emulator's
// own reader and writer; like the rest of sim/ it shares no code with the core.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace birdcage::sim {

enum class Direction { host_to_dish, dish_to_host };  // `>` and `<`

struct TranscriptEntry {
    Direction direction;
    std::string bytes;
    double delay_ms = 0.0;       // `@+Nms`: time since the previous chunk (either direction)
    bool reconstructed = false;  // `~` marker: not captured from a real dish
    std::size_t line_number = 0;
};

struct Transcript {
    std::vector<std::pair<std::string, std::string>> headers;  // `# Key: value`, in file order
    std::vector<TranscriptEntry> entries;

    // The first header with this key (case-sensitive), if any.
    std::optional<std::string> header(std::string_view key) const;
};

// A malformed transcript; what() names the line.
class TranscriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

Transcript parse_transcript(std::string_view text);   // throws TranscriptError
Transcript load_transcript(const std::string& path);  // throws TranscriptError (also for I/O)

// `\r`, `\n`, `\t`, `\\`, `\xNN` for every other byte outside printable ASCII. A leading or
// trailing space is written `\x20` so that it survives editors that trim lines.
std::string escape_chunk(std::string_view bytes);
// Inverse of escape_chunk; also accepts `\0`, `\e`. Throws TranscriptError on a bad escape.
std::string unescape_chunk(std::string_view text);

// Formats one chunk line: `> mot\r`, `< @+12ms \r\nMOT>`, `<~ ...` for a reconstructed chunk.
std::string format_entry(const TranscriptEntry& entry);

// Builds a transcript line by line as a session runs (the recorder and the drafting tools).
class TranscriptRecorder {
public:
    // `headers` are written first, in order, as `# Key: value`.
    explicit TranscriptRecorder(std::vector<std::pair<std::string, std::string>> headers);

    // `seconds`: any monotonic time; the first chunk gets no delay. `reconstructed` marks a chunk
    // that did not come from a real dish (drafts made against the emulator).
    void add(Direction direction, std::string_view bytes, double seconds, bool reconstructed = false);
    void comment(std::string_view text);
    const std::string& text() const { return text_; }

private:
    std::string text_;
    std::optional<double> last_seconds_;
};

}  // namespace birdcage::sim
