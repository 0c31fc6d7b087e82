// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// The real sky over a station (--lat/--lon) and a dish set against it (--mount): the belt and the
// Sun in the RSSI, a scan of an emulated G2 peaking at sky -> dish of a satellite, the sky clock,
// and the truth rows. tests/sim/test_sky.cpp keeps the scan's sky, unchanged.
#include <birdcage_sim/console.hpp>
#include <birdcage_sim/emulator.hpp>
#include <birdcage_sim/sky.hpp>
#include <birdcage_sim/sky_geometry.hpp>

#include <catch2/catch.hpp>

#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <optional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "pty_client.hpp"

using namespace birdcage::sim;

namespace {

const Station honolulu{21.31, -157.86, 5.0};
const Station boulder{40.0, -105.27, 1655.0};
const Mount skewed{6.0, -1.5, 1.0, -0.7};

double strongest(const Satellite& s) {
    return std::max(s.amplitude_13v, s.amplitude_18v);
}

double amplitude_on(const Satellite& s, LnbSupply supply) {
    return supply == LnbSupply::odu_13v ? s.amplitude_13v : s.amplitude_18v;
}

// A strong satellite no other audible one comes within 12 degrees of (so that neighbours do not
// pull its peak), high enough for a G2 scan around it through the mount.
struct Isolated {
    std::uint32_t seed;
    Satellite satellite;
    LnbSupply supply;
};

std::optional<Isolated> isolated_satellite(const Station& station) {
    for (std::uint32_t seed = 1; seed < 200; ++seed) {
        const SkyModel sky(seed, 401.0, station);
        for (const Satellite& s : sky.belt()) {
            const LnbSupply supply = s.amplitude_13v > s.amplitude_18v ? LnbSupply::odu_13v : LnbSupply::stb_18v;
            const AzEl dish = sky_to_dish(skewed, {s.az, s.el});
            if (amplitude_on(s, supply) < 80.0 || dish.el < 27.0 || dish.el > 56.0)
                continue;
            bool alone = true;
            for (const Satellite& other : sky.belt()) {
                if (&other != &s && amplitude_on(other, supply) > 0.0 && other.el > 0.0 &&
                    angular_distance({s.az, s.el}, {other.az, other.el}) < 12.0)
                    alone = false;
            }
            if (alone)
                return Isolated{seed, s, supply};
        }
    }
    return std::nullopt;
}

std::string send(Console& console, std::string_view bytes, double then_advance = 0.0) {
    console.feed(bytes);
    if (then_advance > 0.0)
        console.advance(then_advance);
    return console.take_output();
}

void settle(Console& console) {
    for (int i = 0; i < 2000 && console.moving(); ++i)
        console.advance(0.05);
}

// Moves the G2 (in MOT>) and reads `rssi 100` in DVB>, back in MOT>.
double average_rssi_at(Console& console, double az, double el) {
    char move[64];
    std::snprintf(move, sizeof move, "a 0 %.2f\ra 1 %.2f\r", az, el);
    send(console, move);
    settle(console);
    const std::string reply = send(console, "q\rdvb\rrssi 100\r", 2.1);
    send(console, "q\rmot\r");
    std::smatch match;
    REQUIRE(std::regex_search(reply, match, std::regex("RSSI\\[avg: ([0-9]+)")));
    return std::stod(match[1]);
}

// Vertex of a Gaussian fitted to the samples clearly above the floor (a parabola in log).
double gaussian_peak(const std::vector<double>& x, const std::vector<double>& value, double floor) {
    double peak = 0.0;
    for (const double v : value)
        peak = std::max(peak, v - floor);
    double s[5] = {}, t[3] = {};  // sums of x^k and of ln(v) x^k
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double height = value[i] - floor;
        if (height < 0.3 * peak)
            continue;
        const double l = std::log(height);
        double power = 1.0;
        for (int k = 0; k < 5; ++k) {
            s[k] += power;
            if (k < 3)
                t[k] += l * power;
            power *= x[i];
        }
    }
    // Normal equations of ln(v) = a + b x + c x^2, by Cramer's rule.
    const auto det3 = [](double a, double b, double c, double d, double e, double f, double g, double h, double i) {
        return a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
    };
    const double d = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    const double b = det3(s[0], t[0], s[2], s[1], t[1], s[3], s[2], t[2], s[4]) / d;
    const double c = det3(s[0], s[1], t[0], s[1], s[2], t[1], s[2], s[3], t[2]) / d;
    return -b / (2.0 * c);
}

std::vector<std::string> lines_of(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);)
        lines.push_back(line);
    return lines;
}

std::vector<std::string> fields_of(const std::string& line) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    for (std::string field; std::getline(in, field, ',');)
        fields.push_back(field);
    return fields;
}

}  // namespace

TEST_CASE("real sky: the catalogue's belt at the station, amplitudes a seeded mix by name", "[sim][sky]") {
    const SkyModel sky(1, 401.0, boulder);
    REQUIRE(sky.belt().size() == geostationary_catalogue().size());
    REQUIRE(geostationary_catalogue().size() > 80);
    CHECK(geostationary_catalogue().front().name == "GALAXY 18");
    CHECK(geostationary_catalogue().front().longitude_deg == -123.0);
    int strong = 0, weak = 0, silent = 0, strong_13v = 0, strong_18v = 0;
    for (std::size_t i = 0; i < sky.belt().size(); ++i) {
        const Satellite& s = sky.belt()[i];
        const AzEl look = geostationary_direction(boulder, geostationary_catalogue()[i].longitude_deg);
        CHECK(s.name == geostationary_catalogue()[i].name);
        CHECK(s.az == look.az);
        CHECK(s.el == look.el);
        const double main = strongest(s);
        // One polarisation carries the slot, the other hears a fifth of it.
        CHECK(std::min(s.amplitude_13v, s.amplitude_18v) == Approx(0.2 * main));
        if (main >= 60.0) {
            CHECK(main <= 160.0);
            ++strong;
            (s.amplitude_13v > s.amplitude_18v ? strong_13v : strong_18v) += 1;
        } else if (main > 0.0) {
            CHECK(main >= 5.0);
            CHECK(main <= 30.0);
            ++weak;
        } else {
            ++silent;
        }
    }
    const double n = static_cast<double>(sky.belt().size());
    CHECK(strong / n == Approx(0.4).margin(0.15));
    CHECK(weak / n == Approx(0.3).margin(0.15));
    CHECK(silent / n == Approx(0.3).margin(0.15));
    CHECK(strong_13v > 5);
    CHECK(strong_18v > 5);

    // The draw is the seed's and the name's: the same elsewhere, different for another seed.
    const SkyModel elsewhere(1, 401.0, honolulu), other_seed(2, 401.0, boulder);
    int differ = 0;
    for (std::size_t i = 0; i < sky.belt().size(); ++i) {
        CHECK(elsewhere.belt()[i].amplitude_13v == sky.belt()[i].amplitude_13v);
        CHECK(elsewhere.belt()[i].amplitude_18v == sky.belt()[i].amplitude_18v);
        differ += other_seed.belt()[i].amplitude_13v != sky.belt()[i].amplitude_13v ? 1 : 0;
    }
    CHECK(differ > static_cast<int>(n / 2));
}

TEST_CASE("real sky: a strong satellite's beam peaks at its look angles, in angle on the sky", "[sim][sky]") {
    const auto found = isolated_satellite(honolulu);
    REQUIRE(found);
    const SkyModel sky(found->seed, 401.0, honolulu);
    const Satellite& s = found->satellite;
    // A night-time instant, the Sun far from the belt.
    const double utc = *parse_utc("2026-06-21T10:00:00Z");
    REQUIRE(sun_direction(honolulu, utc).el < -20.0);
    const double at_peak = sky.expected_rssi(s.az, s.el, found->supply, utc);
    CHECK(at_peak == Approx(401.0 + amplitude_on(s, found->supply)).margin(2.0));
    double best = 0.0, best_az = 0.0, best_el = 0.0;
    for (double daz = -1.0; daz <= 1.0; daz += 0.01) {
        for (double del = -1.0; del <= 1.0; del += 0.01) {
            const double v = sky.expected_rssi(s.az + daz, s.el + del, found->supply, utc);
            if (v > best) {
                best = v;
                best_az = s.az + daz;
                best_el = s.el + del;
            }
        }
    }
    CHECK(best_az == Approx(s.az).margin(0.02));
    CHECK(best_el == Approx(s.el).margin(0.02));
    // Sigma 2.9 degrees of angle: at 2.9 degrees off in elevation exp(-1/2); the same angle off in
    // azimuth takes 2.9 / cos(el) degrees of azimuth.
    const double amplitude = amplitude_on(s, found->supply);
    CHECK(sky.expected_rssi(s.az, s.el + 2.9, found->supply, utc) - 401.0 == Approx(amplitude * 0.6065).margin(2.0));
    constexpr double degree = std::numbers::pi / 180.0;
    const double daz = 2.0 * std::asin(std::sin(1.45 * degree) / std::cos(s.el * degree)) / degree;
    CHECK(sky.expected_rssi(s.az + daz, s.el, found->supply, utc) - 401.0 == Approx(amplitude * 0.6065).margin(2.0));
}

TEST_CASE("real sky: the Sun is a 200-count source on both supplies, where it is at the UTC", "[sim][sky]") {
    const SkyModel sky(1, 401.0, boulder);
    const double noon = *parse_utc("2026-06-21T19:00:00Z");  // local noon: the Sun high, far from the belt
    const AzEl sun = sun_direction(boulder, noon);
    REQUIRE(sun.el > 60.0);
    for (const LnbSupply supply : {LnbSupply::odu_13v, LnbSupply::stb_18v}) {
        CHECK(sky.expected_rssi(sun.az, sun.el, supply, noon) == Approx(401.0 + SkyModel::sun_amplitude).margin(1.0));
        // An hour later it has moved on (~14 degrees): the same direction hears the floor.
        CHECK(sky.expected_rssi(sun.az, sun.el, supply, noon + 3600.0) == Approx(401.0).margin(1.0));
    }
    // The disc widens the beam a little: sigma sqrt(2.9^2 + 0.265^2 / 4).
    const double sigma = std::sqrt(2.9 * 2.9 + 0.265 * 0.265 / 4.0);
    const double expected_off = 401.0 + SkyModel::sun_amplitude * std::exp(-0.5 * 9.0 / (sigma * sigma));
    CHECK(sky.expected_rssi(sun.az, sun.el - 3.0, LnbSupply::odu_13v, noon) == Approx(expected_off).margin(0.01));
}

TEST_CASE("real sky: a G2 scan through the mount peaks at sky -> dish of the satellite", "[sim][sky][mount]") {
    const auto found = isolated_satellite(honolulu);
    REQUIRE(found);
    const Satellite& s = found->satellite;
    Options options;
    options.variant = Variant::carryout_g2;
    options.seed = found->seed;
    options.station = honolulu;
    options.mount = skewed;
    options.epoch = *parse_utc("2026-06-21T10:00:00Z");  // night in Hawaii
    Console console(options);
    send(console, "mot\r");
    if (found->supply == LnbSupply::odu_13v)
        send(console, "q\rdvb\rlnbdc odu\rq\rmot\r");

    const AzEl expected = sky_to_dish(skewed, {s.az, s.el});
    INFO(s.name << " at sky " << s.az << "/" << s.el << ", dish " << expected.az << "/" << expected.el);
    std::vector<double> offsets, az_cut, el_cut;
    for (double d = -6.0; d <= 6.01; d += 0.5)
        offsets.push_back(d);
    for (const double d : offsets)
        az_cut.push_back(average_rssi_at(console, expected.az + d, expected.el));
    const double peak_az = expected.az + gaussian_peak(offsets, az_cut, 401.0);
    for (const double d : offsets)
        el_cut.push_back(average_rssi_at(console, peak_az, expected.el + d));
    const double peak_el = expected.el + gaussian_peak(offsets, el_cut, 401.0);
    CHECK(peak_az == Approx(expected.az).margin(0.1));
    CHECK(peak_el == Approx(expected.el).margin(0.1));
    // The mount moved the peak well away from the satellite's own look angles.
    CHECK(angular_distance({peak_az, peak_el}, {s.az, s.el}) > 4.0);
    CHECK(console.hazards() == 0);
}

TEST_CASE("real sky: the sky clock is the epoch plus emulated seconds", "[sim][sky]") {
    Options options;
    options.variant = Variant::carryout_g2;
    options.station = boulder;
    options.epoch = *parse_utc("2026-06-21T14:30:00Z");  // mid-morning in Colorado
    Console console(options);
    send(console, "mot\r");
    CHECK(console.epoch() == *options.epoch);
    // Aim where the Sun will be an hour on (~13 degrees away): the floor now, the Sun then.
    const AzEl sun_later = sun_direction(boulder, *options.epoch + 3600.0);
    REQUIRE(sun_later.el > 18.0);
    REQUIRE(sun_later.el < 65.0);
    CHECK(average_rssi_at(console, sun_later.az, sun_later.el) < 401.0 + 0.1 * SkyModel::sun_amplitude);
    console.advance(3600.0 - console.time());
    CHECK(average_rssi_at(console, sun_later.az, sun_later.el) ==
          Approx(401.0 + SkyModel::sun_amplitude).margin(0.05 * SkyModel::sun_amplitude));
}

TEST_CASE("real sky: without a station the scan's sky, at the beam's direction through the mount",
          "[sim][sky][mount]") {
    Options options;
    options.variant = Variant::carryout_g2;
    options.mount = {6.0, 0.0, 0.0, 0.0};
    options.epoch = 0.0;
    Console console(options);
    send(console, "dvb\rlnbdc odu\rq\rmot\r");
    // scan_data.txt: `174.0 43.0 562`. The dish reading 168 looks at 174.
    CHECK(average_rssi_at(console, 168.0, 43.0) == Approx(562.0).margin(3.0));
    CHECK(console.beam_direction().az == Approx(174.0).margin(0.02));
    // The same reading without the mount hears the scan at 168.
    Options plain = options;
    plain.mount = {};
    Console unmounted(plain);
    send(unmounted, "dvb\rlnbdc odu\rq\rmot\r");
    const SkyModel scan(1);
    CHECK(average_rssi_at(unmounted, 168.0, 43.0) ==
          Approx(scan.expected_rssi(168.0, 43.0, LnbSupply::odu_13v)).margin(3.0));
}

TEST_CASE("truth: a row every 0.1 s and at each start and end of motion, the beam through the mount", "[sim][truth]") {
    Options options;
    options.variant = Variant::carryout_g2;
    options.mount = skewed;
    options.epoch = 0.0;
    options.truth_path = "kept";  // a Console keeps the rows; only the Emulator writes the file
    Console console(options);
    send(console, "mot\ra 0 200\r");
    settle(console);
    console.advance(1.0);
    const std::vector<TruthRow> rows = console.take_truth();
    REQUIRE(rows.size() > 10);
    CHECK(rows.front().t == 0.0);
    CHECK_FALSE(rows.front().moving);
    int starts = 0, stops = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        CHECK(rows[i].t - rows[i - 1].t <= 0.1 + 0.02 + 1e-9);  // the first 20 ms step past each mark
        CHECK(rows[i].t > rows[i - 1].t);
        starts += !rows[i - 1].moving && rows[i].moving ? 1 : 0;
        stops += rows[i - 1].moving && !rows[i].moving ? 1 : 0;
        const AzEl sky = dish_to_sky(skewed, {rows[i].dish_az, rows[i].dish_el});
        CHECK(std::remainder(rows[i].sky_az - sky.az, 360.0) == Approx(0.0).margin(1e-9));
        CHECK(rows[i].sky_el == Approx(sky.el).margin(1e-9));
    }
    CHECK(starts == 1);
    CHECK(stops == 1);
    CHECK(rows.back().dish_az == Approx(200.0).margin(0.02));
    CHECK(console.take_truth().empty());
}

TEST_CASE("truth: the emulator writes the CSV as the dish moves, readable during and after the run", "[sim][truth]") {
    using namespace birdcage::sim::testing;
    const std::string path = "/tmp/birdcage-sim-truth-" + std::to_string(::getpid()) + ".csv";
    Options options;
    options.variant = Variant::carryout_g2;
    options.time_scale = 20.0;
    options.mount = skewed;
    options.epoch = *parse_utc("2026-06-21T12:00:00Z");
    options.truth_path = path;
    double end_time = 0.0;
    {
        Emulator dish(options);
        PtyClient client(dish.device_path());
        CHECK(client.command("mot", "MOT>").ends_with("MOT>"));
        client.command("a 0 220", "MOT>");
        // Flushed while running: a row that shows the motion appears before the emulator ends.
        REQUIRE(wait_for([&] {
            for (const std::string& line : lines_of(path)) {
                const auto fields = fields_of(line);
                if (fields.size() == 7 && fields[6] == "1")
                    return true;
            }
            return false;
        }));
        REQUIRE(wait_for([&] { return !dish.moving(); }));
        end_time = dish.sim_time();
        CHECK(dish.epoch() == *options.epoch);
    }
    const std::vector<std::string> lines = lines_of(path);
    std::remove(path.c_str());
    REQUIRE(lines.size() > 20);
    CHECK(lines.front() == "utc,t,dish_az,dish_el,sky_az,sky_el,moving");
    double last_t = -1.0;
    for (std::size_t i = 1; i < lines.size(); ++i) {
        const auto fields = fields_of(lines[i]);
        REQUIRE(fields.size() == 7);
        const double t = std::stod(fields[1]);
        CHECK(t >= last_t);  // printed to the millisecond: a motion's start may share its row's t
        last_t = t;
        // The sky clock: epoch + emulated seconds, whatever the time scale (both columns are
        // rounded to the millisecond, each on its own).
        const auto utc = parse_utc(fields[0]);
        REQUIRE(utc);
        CHECK(*utc - *options.epoch == Approx(t).margin(0.0011));
        CHECK(fields[0] == format_utc(*utc));
        const AzEl sky = dish_to_sky(skewed, {std::stod(fields[2]), std::stod(fields[3])});
        CHECK(std::remainder(std::stod(fields[4]) - sky.az, 360.0) == Approx(0.0).margin(2e-4));
        CHECK(std::stod(fields[5]) == Approx(sky.el).margin(2e-4));
    }
    // The rows at exit reach the emulator's last moments, the dish at rest on its target.
    CHECK(last_t >= end_time - 0.12);
    const auto final_row = fields_of(lines.back());
    CHECK(final_row[6] == "0");
    CHECK(std::stod(final_row[2]) == Approx(220.0).margin(0.02));
}
