// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Ku-band RSSI the G2's DVB `rssi` command would read at a pointing direction on the sky: by
// default the sky of a real G2 scan (sim/data/g2-ku-skyscan, embedded at build time); for a
// station given with --lat/--lon, the real sky over it (the geostationary belt of
// tools/sky/data/geostationary.csv and the Sun). See sky.cpp for the models.
#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "birdcage_sim/sky_geometry.hpp"

namespace birdcage::sim {

// `lnbdc odu` = 13 V (the LNB receives vertical polarisation), `lnbdc stb` = 18 V (horizontal,
// the boot default), docs/firmware.md §6.3.
enum class LnbSupply { odu_13v, stb_18v };

struct Satellite {
    std::string name;
    double az = 0.0, el = 0.0;   // look angles at the scan's site (the real sky: at the station)
    double amplitude_13v = 0.0;  // counts above the floor at the beam centre
    double amplitude_18v = 0.0;
};

// One row of tools/sky/data/geostationary.csv (docs/sky.md §2), embedded at build time.
struct GeostationarySlot {
    std::string name;
    double longitude_deg = 0.0;  // east positive
};
const std::vector<GeostationarySlot>& geostationary_catalogue();

class SkyModel {
public:
    // The sky of the real scan, at its site.
    explicit SkyModel(std::uint32_t seed, double floor = 401.0);
    // The real sky over `station`: the catalogue's belt, each slot with amplitudes drawn from the
    // seed and its name, and the Sun.
    SkyModel(std::uint32_t seed, double floor, const Station& station);

    // Noise-free model value (ADC counts) where the beam points on the sky. `utc` (Unix seconds)
    // places the Sun of the real sky; the scan's sky has no time.
    double expected_rssi(double az, double el, LnbSupply supply, double utc = 0.0) const;
    // One 20 ms read: model value plus sample noise, rounded like the firmware's integer counts.
    // Averaging n reads (`rssi n`) leaves noise ~ 1/sqrt(n).
    int read(double az, double el, LnbSupply supply, double utc = 0.0);

    // The scan's catalogue with the model's amplitudes (tests compare scans against it).
    static const std::vector<Satellite>& satellites();
    // True where the 13 V value comes from the measured grid rather than the belt model.
    static bool inside_measured_grid(double az, double el);
    double floor() const { return floor_; }

    // The real sky's belt as seen from the station (empty for the scan's sky).
    const std::vector<Satellite>& belt() const { return belt_; }
    const std::optional<Station>& station() const { return station_; }
    // The Sun's peak above the floor on either supply (it is unpolarised).
    static constexpr double sun_amplitude = 200.0;

private:
    double real_sky_rssi(AzEl beam, LnbSupply supply, double utc) const;

    double floor_;
    std::mt19937 rng_;
    std::optional<Station> station_;
    std::vector<Satellite> belt_;
};

}  // namespace birdcage::sim
