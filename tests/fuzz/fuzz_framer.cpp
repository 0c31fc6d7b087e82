// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// libFuzzer target: the console framer, fed arbitrary bytes in arbitrary chunks, for every variant.
// Properties: no crash; no event text contains a line terminator; every prompt looks like one;
// every byte of input is accounted for by an event or the partial line (nothing grows unbounded).
#include "console/framer.hpp"
#include "firmware/variants.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) {
        return 0;
    }
    // First byte: chunk length (1..64); second: echo expectation length taken from the data.
    const std::size_t chunk = 1 + data[0] % 64;
    const std::size_t echo_len = data[1] % 8;
    const std::string_view all(reinterpret_cast<const char*>(data) + 2, size - 2);
    for (const birdcage::FirmwareProfile& profile : birdcage::all_profiles()) {
        birdcage::ConsoleFramer framer(profile);
        framer.expect_echo(all.substr(0, echo_len));
        for (std::size_t at = 0; at < all.size(); at += chunk) {
            for (const birdcage::FrameEvent& e : framer.feed(all.substr(at, chunk))) {
                if (e.kind != birdcage::FrameEvent::Kind::noise && e.text.find_first_of("\r\n") != std::string::npos) {
                    std::abort();
                }
                if (e.kind == birdcage::FrameEvent::Kind::prompt && !birdcage::looks_like_prompt(e.text)) {
                    std::abort();
                }
            }
            if (framer.partial_line().size() > all.size()) {
                std::abort();
            }
        }
    }
    return 0;
}
