// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// libFuzzer target: every reply parser on arbitrary lines, and the hazard guard on arbitrary
// commands. Properties: no crash; a parsed position is finite; a refused command is refused with
// a hazard/not_homed code and a message; format_degrees output parses back to within 0.005.
#include "firmware/protocol.hpp"
#include "firmware/variants.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

std::vector<std::string> split_lines(std::string_view text) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t nl = text.find('\n', start);
        const std::size_t end = nl == std::string_view::npos ? text.size() : nl;
        lines.emplace_back(text.substr(start, end - start));
        if (nl == std::string_view::npos) {
            break;
        }
        start = nl + 1;
    }
    return lines;
}

void require(bool ok) {
    if (!ok) {
        std::abort();
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const std::vector<std::string> lines = split_lines(text);

    for (const birdcage::FirmwareProfile& profile : birdcage::all_profiles()) {
        const auto pos = birdcage::parse_position(profile, lines);
        if (pos) {
            require(std::isfinite(pos.value.az) && std::isfinite(pos.value.el));
        }
        for (const char* menu : {"", "root", "mot", "nvs", "adc"}) {
            for (bool unhomed : {false, true}) {
                const birdcage::Status st =
                    birdcage::hazard_check(profile, text, birdcage::HazardContext{menu, false, unhomed});
                require(st || ((st.code == birdcage::Errc::hazard || st.code == birdcage::Errc::not_homed) &&
                               !st.message.empty()));
            }
        }
    }
    if (const auto ack = birdcage::parse_g2_move_ack(lines)) {
        require(std::isfinite(ack.value));
    }
    (void)birdcage::parse_g2_rssi(lines);
    for (const std::string& line : lines) {
        (void)birdcage::parse_g2_nvs_line(line);
    }

    // Round trip: any finite double from the input formats to text the G2 parser reads back.
    if (size >= sizeof(double)) {
        double value = 0;
        std::memcpy(&value, data, sizeof value);
        if (std::isfinite(value) && std::fabs(value) < 1e6) {
            const std::string reply = "Angle = " + birdcage::format_degrees(value);
            const auto back = birdcage::parse_g2_move_ack(std::vector<std::string>{reply});
            require(static_cast<bool>(back) && std::fabs(back.value - value) <= 0.005 + 1e-9);
        }
    }
    return 0;
}
