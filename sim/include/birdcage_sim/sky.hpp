// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Ku-band RSSI the G2's DVB `rssi` command would read at a pointing direction, built from a real
// G2 scan (sim/data/g2-ku-skyscan, embedded at build time). See sky.cpp for the model.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace birdcage::sim {

// `lnbdc odu` = 13 V (the LNB receives vertical polarisation), `lnbdc stb` = 18 V (horizontal,
// the boot default), docs/firmware.md §6.3.
enum class LnbSupply { odu_13v, stb_18v };

struct Satellite {
    std::string name;
    double az = 0.0, el = 0.0;   // look angles at the scan's site
    double amplitude_13v = 0.0;  // counts above the floor at the beam centre
    double amplitude_18v = 0.0;
};

class SkyModel {
public:
    explicit SkyModel(std::uint32_t seed, double floor = 401.0);

    // Noise-free model value (ADC counts) at displayed azimuth/elevation.
    double expected_rssi(double az, double el, LnbSupply supply) const;
    // One 20 ms read: model value plus sample noise, rounded like the firmware's integer counts.
    // Averaging n reads (`rssi n`) leaves noise ~ 1/sqrt(n).
    int read(double az, double el, LnbSupply supply);

    // The catalogue with the model's amplitudes (tests compare scans against it).
    static const std::vector<Satellite>& satellites();
    // True where the 13 V value comes from the measured grid rather than the belt model.
    static bool inside_measured_grid(double az, double el);
    double floor() const { return floor_; }

private:
    double floor_;
    std::mt19937 rng_;
};

}  // namespace birdcage::sim
