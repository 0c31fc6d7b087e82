#include "birdcage_sim/sky.hpp"

#include <cmath>
#include <numbers>

namespace birdcage::sim {
namespace {

struct Bump {
    double az;
    double el;
    double amplitude;  // counts above the floor
};

// Positions: winegard-sky-scan example/satellite_data.csv (Gpredict look angles at
// Davidson's site). Amplitudes: non-negative least-squares fit of Gaussian beams (sigma 2.9 deg
// on sky, i.e. the ~7 deg FWHM of firmware.md §11.2) plus a 401-count floor to scan_data.txt
// (5371 points, rms residual 8.6 counts). Satellites the fit gave no power are omitted.
constexpr Bump sky_bumps[] = {
    {124.12, 26.21, 27.6}, {124.26, 26.30, 49.2}, {124.41, 26.40, 52.7}, {135.69, 33.44, 88.4},
    {140.22, 35.71, 79.8}, {145.15, 37.73, 13.3}, {146.83, 38.37, 18.0}, {150.57, 40.01, 10.5},
    {159.26, 41.90, 3.3},  {159.32, 41.85, 14.0}, {171.56, 43.61, 83.3}, {176.95, 43.95, 73.7},
    {177.07, 43.91, 9.1},  {188.22, 43.61, 44.8}, {188.59, 43.58, 49.2}, {201.61, 41.71, 58.7},
    {201.85, 41.66, 45.4}, {204.63, 41.00, 18.5}, {212.71, 38.53, 18.7}, {215.27, 37.59, 10.9},
    {224.66, 30.18, 14.7}, {237.42, 25.10, 4.7},
};
constexpr double beam_sigma_deg = 2.9;

}  // namespace

SkyModel::SkyModel(std::uint32_t seed, double floor) : floor_(floor), rng_(seed) {}

double SkyModel::expected_rssi(double az, double el) const
{
    double value = floor_;
    for (const Bump& bump : sky_bumps) {
        double daz = std::remainder(az - bump.az, 360.0);
        daz *= std::cos(bump.el * std::numbers::pi / 180.0);
        const double del = el - bump.el;
        value += bump.amplitude * std::exp(-(daz * daz + del * del) / (2.0 * beam_sigma_deg * beam_sigma_deg));
    }
    return value;
}

int SkyModel::read(double az, double el)
{
    std::normal_distribution<double> noise(0.0, 1.5);
    return static_cast<int>(std::lround(expected_rssi(az, el) + noise(rng_)));
}

}  // namespace birdcage::sim
