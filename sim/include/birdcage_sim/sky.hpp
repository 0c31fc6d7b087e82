// Ku-band RSSI the G2's DVB `rssi` command would read at a pointing direction.
#pragma once

#include <cstdint>
#include <random>

namespace birdcage::sim {

class SkyModel {
public:
    explicit SkyModel(std::uint32_t seed, double floor = 401.0);

    // Noise-free model value (ADC counts) at displayed azimuth/elevation.
    double expected_rssi(double az, double el) const;
    // One read: model value plus a little noise, rounded like the firmware's integer counts.
    int read(double az, double el);

private:
    double floor_;
    std::mt19937 rng_;
};

}  // namespace birdcage::sim
