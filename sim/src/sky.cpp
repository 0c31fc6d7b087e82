// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The sky a G2 sees, from Davidson's real scan (docs/firmware.md §11.2):
//
// - 13 V (`lnbdc odu`), the setting the scan was taken with: inside the scanned grid (AZ 110..240,
//   EL 18..58, 1 degree) the value is the measurement itself, bilinearly interpolated, so a scan of
//   the emulator reproduces the real heatmap, noise floor and beam shapes included. Outside it: the
//   floor plus the satellite belt, a Gaussian beam (sigma 2.9 degrees on sky, the ~7 degree FWHM
//   of §11.2) per catalogue satellite with the amplitude a least-squares fit to the scan gave it.
// - 18 V (`lnbdc stb`, the boot default): the LNB receives the other polarisation, which nobody
//   has scanned. The model keeps the floor and the satellites' positions and swaps what is strong:
//   a satellite strong at 13 V (>= 30 counts) leaks a fifth of it (cross-polar isolation ~7 dB of
//   a small dish), and a slot (satellites within 3 degrees) the 13 V fit found weak or silent
//   carries 60 counts. An
//   invented but explicit rule: the point is that the voltage visibly changes the sky, and a test
//   can tell which polarisation the dish listens to.
// - Each 20 ms read adds Gaussian noise of 8 counts, so `rssi 10` scatters by ~2.5 counts like
//   the real averages; deterministic per seed.
//
// The real sky over a station (`--lat/--lon`) replaces all of that but the floor and the noise:
// - every slot of tools/sky/data/geostationary.csv at its exact topocentric look angles, a
//   Gaussian beam of the same sigma in the angle between the beam and the satellite (not az/el
//   differences: the belt is seen at any elevation). Its amplitude is drawn from the seed and its
//   name, so a slot keeps its strength whatever else the table lists: 40% strong (60-160 counts),
//   30% weak (5-30), 30% silent (INVENTED proportions, a mix like the scan's fit). The scan's
//   two-polarisation rule in spirit: a slot is strong on one polarisation, drawn, and leaks a
//   fifth of it on the other;
// - the Sun where it is at the emulated UTC: its 0.53-degree disc seen through the beam, a
//   Gaussian whose variance is the beam's plus the disc's (radius^2 / 4 per axis), 200 counts at
//   the centre on either supply (unpolarised; INVENTED level, a few times a strong satellite);
// - sources below the horizon are hidden by the ground.
#include "birdcage_sim/sky.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace birdcage::sim {
namespace sky_data {
extern const char* const scan;
extern const char* const catalogue;
extern const char* const belt;
}  // namespace sky_data

namespace {

struct Bump {
    double az;
    double el;
    double amplitude;  // counts above the floor
};

// Non-negative least-squares fit of Gaussian beams at the catalogue positions plus a 401-count
// floor to scan_data.txt (5371 points, rms residual 8.6 counts). Satellites the fit gave no power
// are absent (amplitude 0 at 13 V).
constexpr Bump fitted_13v[] = {
    {124.12, 26.21, 27.6}, {124.26, 26.30, 49.2}, {124.41, 26.40, 52.7}, {135.69, 33.44, 88.4}, {140.22, 35.71, 79.8},
    {145.15, 37.73, 13.3}, {146.83, 38.37, 18.0}, {150.57, 40.01, 10.5}, {159.26, 41.90, 3.3},  {159.32, 41.85, 14.0},
    {171.56, 43.61, 83.3}, {176.95, 43.95, 73.7}, {177.07, 43.91, 9.1},  {188.22, 43.61, 44.8}, {188.59, 43.58, 49.2},
    {201.61, 41.71, 58.7}, {201.85, 41.66, 45.4}, {204.63, 41.00, 18.5}, {212.71, 38.53, 18.7}, {215.27, 37.59, 10.9},
    {224.66, 30.18, 14.7}, {237.42, 25.10, 4.7},
};
constexpr double scan_floor = 401.0;  // the fitted floor of scan_data.txt
constexpr double beam_sigma_deg = 2.9;
constexpr double strong_13v = 30.0;
constexpr double cross_polar_fraction = 0.2;
constexpr double slot_radius_deg = 3.0;
constexpr double other_polarisation_amplitude = 60.0;
constexpr double sample_noise = 8.0;
constexpr double strong_share = 0.4, weak_share = 0.3;  // the rest of the belt is silent
constexpr double strong_min = 60.0, strong_max = 160.0;
constexpr double weak_min = 5.0, weak_max = 30.0;
constexpr double sun_radius_deg = 0.265;

struct Grid {
    std::vector<double> az, el;  // ascending axes
    std::vector<double> value;   // az-major: value[i * el.size() + j]

    double at(std::size_t i, std::size_t j) const { return value[i * el.size() + j]; }
    bool contains(double a, double e) const {
        return !az.empty() && a >= az.front() && a <= az.back() && e >= el.front() && e <= el.back();
    }
    double interpolate(double a, double e) const {
        const auto cell = [](const std::vector<double>& axis, double x) {
            const auto upper = std::upper_bound(axis.begin(), axis.end(), x);
            const std::size_t hi =
                std::clamp<std::size_t>(static_cast<std::size_t>(upper - axis.begin()), 1, axis.size() - 1);
            const double t = (x - axis[hi - 1]) / (axis[hi] - axis[hi - 1]);
            return std::pair{hi - 1, std::clamp(t, 0.0, 1.0)};
        };
        const auto [i, ta] = cell(az, a);
        const auto [j, te] = cell(el, e);
        const double low = at(i, j) * (1 - te) + at(i, j + 1) * te;
        const double high = at(i + 1, j) * (1 - te) + at(i + 1, j + 1) * te;
        return low * (1 - ta) + high * ta;
    }
};

Grid parse_grid() {
    std::map<std::pair<double, double>, double> points;
    std::istringstream in(sky_data::scan);
    double a = 0, e = 0, v = 0;
    while (in >> a >> e >> v) {
        points[{a, e}] = v;
    }
    Grid grid;
    for (const auto& [key, value] : points) {
        if (grid.az.empty() || grid.az.back() != key.first)
            grid.az.push_back(key.first);
        if (std::find(grid.el.begin(), grid.el.end(), key.second) == grid.el.end())
            grid.el.push_back(key.second);
    }
    std::sort(grid.el.begin(), grid.el.end());
    if (grid.az.size() < 2 || grid.el.size() < 2 || points.size() != grid.az.size() * grid.el.size()) {
        throw std::runtime_error("sky model: the embedded scan is not a complete grid");
    }
    for (const auto& entry : points)
        grid.value.push_back(entry.second);  // map order is az-major
    return grid;
}

const Grid& measured() {
    static const Grid grid = parse_grid();
    return grid;
}

std::vector<Satellite> parse_catalogue() {
    std::vector<Satellite> out;
    std::istringstream in(sky_data::catalogue);
    std::string line;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        const auto second = line.rfind(',');
        const auto first = second == std::string::npos ? std::string::npos : line.rfind(',', second - 1);
        if (first == std::string::npos)
            continue;
        Satellite s;
        s.name = line.substr(0, first);
        s.az = std::stod(line.substr(first + 1, second - first - 1));
        s.el = std::stod(line.substr(second + 1));
        for (const Bump& b : fitted_13v) {
            if (std::abs(b.az - s.az) < 0.005 && std::abs(b.el - s.el) < 0.005)
                s.amplitude_13v = b.amplitude;
        }
        out.push_back(std::move(s));
    }
    // Co-located satellites share one orbital slot (one beam): a slot with a strong satellite is
    // strong on that polarisation, so all its satellites only leak on the other one.
    for (Satellite& s : out) {
        const bool strong_slot = std::any_of(out.begin(), out.end(), [&](const Satellite& other) {
            return other.amplitude_13v >= strong_13v && std::hypot(other.az - s.az, other.el - s.el) <= slot_radius_deg;
        });
        s.amplitude_18v = strong_slot ? cross_polar_fraction * s.amplitude_13v : other_polarisation_amplitude;
    }
    return out;
}

double beam(double az, double el, const Satellite& s) {
    double daz = std::remainder(az - s.az, 360.0) * std::cos(s.el * std::numbers::pi / 180.0);
    const double del = el - s.el;
    return std::exp(-(daz * daz + del * del) / (2.0 * beam_sigma_deg * beam_sigma_deg));
}

double gaussian(double angle_deg, double sigma_deg) {
    return std::exp(-angle_deg * angle_deg / (2.0 * sigma_deg * sigma_deg));
}

std::vector<GeostationarySlot> parse_belt() {
    std::vector<GeostationarySlot> out;
    std::istringstream in(sky_data::belt);
    std::string line;
    bool header_seen = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        if (line.empty() || line.front() == '#')
            continue;
        if (!header_seen) {
            header_seen = true;
            continue;
        }
        const auto comma = line.rfind(',');
        if (comma == std::string::npos)
            throw std::runtime_error("sky model: bad line in the embedded geostationary catalogue: " + line);
        out.push_back({line.substr(0, comma), std::stod(line.substr(comma + 1))});
    }
    return out;
}

// FNV-1a: a slot's draw depends on its name only, not on its place in the table.
std::uint32_t name_hash(const std::string& name) {
    std::uint32_t hash = 2166136261u;
    for (const char c : name) {
        hash ^= static_cast<unsigned char>(c);
        hash *= 16777619u;
    }
    return hash;
}

// {13 V, 18 V} amplitudes of a belt slot.
std::pair<double, double> drawn_amplitudes(std::uint32_t seed, const std::string& name) {
    std::seed_seq sequence{seed, name_hash(name)};
    std::mt19937 rng(sequence);
    const auto uniform = [&rng] { return static_cast<double>(rng()) / 4294967296.0; };
    const double kind = uniform(), level = uniform(), vertical = uniform();
    const double main = kind < strong_share                ? strong_min + (strong_max - strong_min) * level
                        : kind < strong_share + weak_share ? weak_min + (weak_max - weak_min) * level
                                                           : 0.0;
    const double leak = cross_polar_fraction * main;
    return vertical < 0.5 ? std::pair{main, leak} : std::pair{leak, main};
}

}  // namespace

const std::vector<Satellite>& SkyModel::satellites() {
    static const std::vector<Satellite> catalogue = parse_catalogue();
    return catalogue;
}

bool SkyModel::inside_measured_grid(double az, double el) {
    return measured().contains(az, el);
}

const std::vector<GeostationarySlot>& geostationary_catalogue() {
    static const std::vector<GeostationarySlot> slots = parse_belt();
    return slots;
}

SkyModel::SkyModel(std::uint32_t seed, double floor) : floor_(floor), rng_(seed) {}

SkyModel::SkyModel(std::uint32_t seed, double floor, const Station& station)
    : floor_(floor), rng_(seed), station_(station) {
    for (const GeostationarySlot& slot : geostationary_catalogue()) {
        const AzEl look = geostationary_direction(station, slot.longitude_deg);
        const auto [amplitude_13v, amplitude_18v] = drawn_amplitudes(seed, slot.name);
        belt_.push_back({slot.name, look.az, look.el, amplitude_13v, amplitude_18v});
    }
}

double SkyModel::real_sky_rssi(AzEl beam_direction, LnbSupply supply, double utc) const {
    double value = floor_;
    for (const Satellite& s : belt_) {
        if (s.el < 0.0)
            continue;
        const double amplitude = supply == LnbSupply::odu_13v ? s.amplitude_13v : s.amplitude_18v;
        if (amplitude > 0.0)
            value += amplitude * gaussian(angular_distance(beam_direction, {s.az, s.el}), beam_sigma_deg);
    }
    const AzEl sun = sun_direction(*station_, utc);
    if (sun.el >= 0.0) {
        const double sun_sigma = std::sqrt(beam_sigma_deg * beam_sigma_deg + sun_radius_deg * sun_radius_deg / 4.0);
        value += sun_amplitude * gaussian(angular_distance(beam_direction, sun), sun_sigma);
    }
    return value;
}

double SkyModel::expected_rssi(double az, double el, LnbSupply supply, double utc) const {
    if (station_)
        return real_sky_rssi({az, el}, supply, utc);
    az = std::fmod(std::fmod(az, 360.0) + 360.0, 360.0);
    if (supply == LnbSupply::odu_13v && measured().contains(az, el)) {
        return measured().interpolate(az, el) - scan_floor + floor_;
    }
    double value = floor_;
    for (const Satellite& s : satellites()) {
        value += (supply == LnbSupply::odu_13v ? s.amplitude_13v : s.amplitude_18v) * beam(az, el, s);
    }
    return value;
}

int SkyModel::read(double az, double el, LnbSupply supply, double utc) {
    std::normal_distribution<double> noise(0.0, sample_noise);
    return static_cast<int>(std::lround(expected_rssi(az, el, supply, utc) + noise(rng_)));
}

}  // namespace birdcage::sim
