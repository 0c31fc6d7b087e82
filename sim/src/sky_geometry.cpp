// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

#include "birdcage_sim/sky_geometry.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace birdcage::sim {
namespace {

constexpr double degree = std::numbers::pi / 180.0;

// WGS84.
constexpr double earth_equatorial_km = 6378.137;
constexpr double earth_flattening = 1.0 / 298.257223563;
constexpr double earth_eccentricity_sq = earth_flattening * (2.0 - earth_flattening);
constexpr double geostationary_radius_km = 42164.17;
constexpr double astronomical_unit_km = 149597870.7;
// 2000-01-01T12:00:00 as a Unix time: the epoch J2000.0 on the TT scale for the solar theory (TT
// read as UTC + tt_minus_utc, the offset since 2017: 32.184 s + 37 leap seconds; an older offset
// would move the Sun by < 0.0001 deg) and on the UT scale for sidereal time, which takes UTC for
// UT1 (|UT1 - UTC| < 0.9 s, 0.004 deg of the Earth's turn).
constexpr double unix_j2000 = 946728000.0;
constexpr double tt_minus_utc = 69.184;

struct Vec {
    double x, y, z;
};

Vec unit(AzEl d) {
    const double az = d.az * degree, el = d.el * degree;
    return {std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)};
}

// docs/sky.md §1's R_E: turns up toward north.
Vec turn_up_toward_north(Vec v, double deg) {
    const double c = std::cos(deg * degree), s = std::sin(deg * degree);
    return {v.x, v.y * c + v.z * s, -v.y * s + v.z * c};
}

// docs/sky.md §1's R_N: turns up toward east.
Vec turn_up_toward_east(Vec v, double deg) {
    const double c = std::cos(deg * degree), s = std::sin(deg * degree);
    return {v.x * c + v.z * s, v.y, -v.x * s + v.z * c};
}

// The direction of an (east, north, up) vector, its azimuth on the branch of `branch_az`.
AzEl direction_of(Vec v, double branch_az) {
    const double horizontal = std::hypot(v.x, v.y);
    const double el = std::atan2(v.z, horizontal) / degree;
    if (horizontal < 1e-12)
        return {branch_az, el};
    const double az = std::atan2(v.x, v.y) / degree;
    return {branch_az + std::remainder(az - branch_az, 360.0), el};
}

Vec station_ecef(const Station& station) {
    const double lat = station.lat_deg * degree, lon = station.lon_deg * degree;
    const double h = station.alt_m / 1000.0;
    const double prime_vertical =
        earth_equatorial_km / std::sqrt(1.0 - earth_eccentricity_sq * std::sin(lat) * std::sin(lat));
    return {(prime_vertical + h) * std::cos(lat) * std::cos(lon), (prime_vertical + h) * std::cos(lat) * std::sin(lon),
            (prime_vertical * (1.0 - earth_eccentricity_sq) + h) * std::sin(lat)};
}

// Look angles from the station to an Earth-fixed point (km), in the station's geodetic horizon.
AzEl look_at(const Station& station, Vec target) {
    const Vec here = station_ecef(station);
    const double dx = target.x - here.x, dy = target.y - here.y, dz = target.z - here.z;
    const double lat = station.lat_deg * degree, lon = station.lon_deg * degree;
    const double east = -std::sin(lon) * dx + std::cos(lon) * dy;
    const double north = -std::sin(lat) * std::cos(lon) * dx - std::sin(lat) * std::sin(lon) * dy + std::cos(lat) * dz;
    const double up = std::cos(lat) * std::cos(lon) * dx + std::cos(lat) * std::sin(lon) * dy + std::sin(lat) * dz;
    double az = std::atan2(east, north) / degree;
    if (az < 0.0)
        az += 360.0;
    if (az >= 360.0)  // -0 and -1e-15 round to 360
        az -= 360.0;
    return {az, std::atan2(up, std::hypot(east, north)) / degree};
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's algorithm).
long days_from_civil(long y, unsigned m, unsigned d) {
    y -= m <= 2 ? 1 : 0;
    const long era = (y >= 0 ? y : y - 399) / 400;
    const auto yoe = static_cast<unsigned>(y - era * 400);
    const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
    const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + static_cast<long>(doe) - 719468;
}

struct Civil {
    long year;
    unsigned month, day;
};

Civil civil_from_days(long z) {
    z += 719468;
    const long era = (z >= 0 ? z : z - 146096) / 146097;
    const auto doe = static_cast<unsigned>(z - era * 146097);
    const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const unsigned mp = (5 * doy + 2) / 153;
    const unsigned day = doy - (153 * mp + 2) / 5 + 1;
    const unsigned month = mp < 10 ? mp + 3 : mp - 9;
    return {static_cast<long>(yoe) + era * 400 + (month <= 2 ? 1 : 0), month, day};
}

bool leap_year(long y) {
    return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
}

// Reads exactly `count` digits at `pos`.
std::optional<long> digits(std::string_view text, std::size_t& pos, std::size_t count) {
    if (pos + count > text.size())
        return std::nullopt;
    long value = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const char c = text[pos + i];
        if (c < '0' || c > '9')
            return std::nullopt;
        value = value * 10 + (c - '0');
    }
    pos += count;
    return value;
}

bool expect(std::string_view text, std::size_t& pos, char c) {
    if (pos >= text.size() || text[pos] != c)
        return false;
    ++pos;
    return true;
}

}  // namespace

AzEl dish_to_sky(const Mount& mount, AzEl dish) {
    if (mount.identity())
        return dish;
    const AzEl base{dish.az + mount.az_index, dish.el + mount.el_index};
    const Vec sky = turn_up_toward_north(turn_up_toward_east(unit(base), mount.tilt_east), mount.tilt_north);
    return direction_of(sky, base.az);
}

AzEl sky_to_dish(const Mount& mount, AzEl sky) {
    if (mount.identity())
        return sky;
    const Vec base = turn_up_toward_east(turn_up_toward_north(unit(sky), -mount.tilt_north), -mount.tilt_east);
    const AzEl d = direction_of(base, sky.az);
    return {d.az - mount.az_index, d.el - mount.el_index};
}

std::optional<double> parse_utc(std::string_view iso) {
    std::size_t pos = 0;
    const auto year = digits(iso, pos, 4);
    if (!year || !expect(iso, pos, '-'))
        return std::nullopt;
    const auto month = digits(iso, pos, 2);
    if (!month || !expect(iso, pos, '-'))
        return std::nullopt;
    const auto day = digits(iso, pos, 2);
    if (!day || *month < 1 || *month > 12)
        return std::nullopt;
    constexpr int month_days[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const long days_in_month = month_days[*month - 1] + (*month == 2 && leap_year(*year) ? 1 : 0);
    if (*day < 1 || *day > days_in_month)
        return std::nullopt;
    long hour = 0, minute = 0;
    double second = 0.0;
    if (pos < iso.size() && (iso[pos] == 'T' || iso[pos] == ' ')) {
        ++pos;
        const auto h = digits(iso, pos, 2);
        if (!h || !expect(iso, pos, ':'))
            return std::nullopt;
        const auto m = digits(iso, pos, 2);
        if (!m || *h > 23 || *m > 59)
            return std::nullopt;
        hour = *h;
        minute = *m;
        if (expect(iso, pos, ':')) {
            const auto s = digits(iso, pos, 2);
            if (!s || *s > 60)
                return std::nullopt;
            second = static_cast<double>(*s);
            if (expect(iso, pos, '.')) {
                double scale = 0.1;
                const std::size_t first = pos;
                while (pos < iso.size() && iso[pos] >= '0' && iso[pos] <= '9') {
                    second += scale * (iso[pos] - '0');
                    scale /= 10.0;
                    ++pos;
                }
                if (pos == first)
                    return std::nullopt;
            }
        }
    }
    long offset_minutes = 0;
    if (pos < iso.size() && (iso[pos] == 'Z' || iso[pos] == 'z')) {
        ++pos;
    } else if (pos < iso.size() && (iso[pos] == '+' || iso[pos] == '-')) {
        const long sign = iso[pos] == '-' ? -1 : 1;
        ++pos;
        const auto h = digits(iso, pos, 2);
        if (!h)
            return std::nullopt;
        expect(iso, pos, ':');
        const auto m = digits(iso, pos, 2);
        if (!m || *h > 23 || *m > 59)
            return std::nullopt;
        offset_minutes = sign * (*h * 60 + *m);
    }
    if (pos != iso.size())
        return std::nullopt;
    const long days = days_from_civil(*year, static_cast<unsigned>(*month), static_cast<unsigned>(*day));
    // In long long: a 32-bit long (armhf) holds the seconds only until 2038-01-19.
    return static_cast<double>(static_cast<long long>(days) * 86400 + (hour * 60 + minute - offset_minutes) * 60) +
           second;
}

std::string format_utc(double utc) {
    const auto total_ms = static_cast<long long>(std::floor(utc * 1000.0 + 0.5));
    long long days = total_ms / 86'400'000;
    long long ms_of_day = total_ms % 86'400'000;
    if (ms_of_day < 0) {
        ms_of_day += 86'400'000;
        --days;
    }
    const Civil date = civil_from_days(static_cast<long>(days));
    char text[40];
    std::snprintf(text, sizeof text, "%04ld-%02u-%02uT%02lld:%02lld:%02lld.%03lldZ", date.year, date.month, date.day,
                  ms_of_day / 3'600'000, ms_of_day / 60'000 % 60, ms_of_day / 1000 % 60, ms_of_day % 1000);
    return text;
}

AzEl geostationary_direction(const Station& station, double longitude_deg) {
    const double lon = longitude_deg * degree;
    return look_at(station, {geostationary_radius_km * std::cos(lon), geostationary_radius_km * std::sin(lon), 0.0});
}

AzEl sun_direction(const Station& station, double utc) {
    const double days_ut = (utc - unix_j2000) / 86400.0;
    const double t = (days_ut + tt_minus_utc / 86400.0) / 36525.0;  // Julian centuries of TT
    const auto sine = [](double deg) { return std::sin(deg * degree); };
    const auto cosine = [](double deg) { return std::cos(deg * degree); };
    // Meeus ch. 25: the mean orbit and the equation of the centre.
    const double mean_longitude = 280.46646 + 36000.76983 * t + 0.0003032 * t * t;
    const double mean_anomaly = 357.52911 + 35999.05029 * t - 0.0001537 * t * t;
    const double eccentricity = 0.016708634 - 0.000042037 * t - 0.0000001267 * t * t;
    const double centre = (1.914602 - 0.004817 * t - 0.000014 * t * t) * sine(mean_anomaly) +
                          (0.019993 - 0.000101 * t) * sine(2.0 * mean_anomaly) + 0.000289 * sine(3.0 * mean_anomaly);
    const double distance_au =
        1.000001018 * (1.0 - eccentricity * eccentricity) / (1.0 + eccentricity * cosine(mean_anomaly + centre));
    // The largest perturbations, by Venus, Jupiter and the Moon and the long-period inequality
    // (Meeus, Astronomical Formulae for Calculators ch. 18; arguments from 1900.0): they halve the
    // error, 0.0095 -> 0.0045 degrees at worst over 1990-2050 against ERFA's ephemeris.
    const double t1900 = t + 1.0;
    const double perturbations =
        0.00134 * cosine(153.23 + 22518.7541 * t1900) + 0.00154 * cosine(216.57 + 45037.5082 * t1900) +
        0.00200 * cosine(312.69 + 32964.3577 * t1900) +
        0.00179 * sine(350.74 + 445267.1142 * t1900 - 0.00144 * t1900 * t1900) + 0.00178 * sine(231.19 + 20.20 * t1900);
    // Nutation (Meeus ch. 22, the four largest terms) and annual aberration: apparent place.
    const double node = 125.04452 - 1934.136261 * t;
    const double moon_longitude = 218.3165 + 481267.8813 * t;
    const double nutation_longitude = (-17.20 * sine(node) - 1.32 * sine(2.0 * mean_longitude) -
                                       0.23 * sine(2.0 * moon_longitude) + 0.21 * sine(2.0 * node)) /
                                      3600.0;
    const double nutation_obliquity = (9.20 * cosine(node) + 0.57 * cosine(2.0 * mean_longitude) +
                                       0.10 * cosine(2.0 * moon_longitude) - 0.09 * cosine(2.0 * node)) /
                                      3600.0;
    const double aberration = -20.4898 / 3600.0 / distance_au;
    const double longitude = (mean_longitude + centre + perturbations + aberration + nutation_longitude) * degree;
    const double mean_obliquity = 23.4392911 - 0.0130042 * t - 1.64e-7 * t * t + 5.04e-7 * t * t * t;
    const double obliquity = (mean_obliquity + nutation_obliquity) * degree;

    // Equatorial of date (true equinox), then Earth-fixed through the apparent sidereal time.
    const double x = std::cos(longitude);
    const double y = std::cos(obliquity) * std::sin(longitude);
    const double z = std::sin(obliquity) * std::sin(longitude);
    const double centuries_ut = days_ut / 36525.0;
    const double mean_sidereal = 280.46061837 + 360.98564736629 * days_ut + 0.000387933 * centuries_ut * centuries_ut -
                                 centuries_ut * centuries_ut * centuries_ut / 38710000.0;
    const double sidereal = (mean_sidereal + nutation_longitude * std::cos(obliquity)) * degree;
    const double r = distance_au * astronomical_unit_km;
    return look_at(station, {r * (x * std::cos(sidereal) + y * std::sin(sidereal)),
                             r * (-x * std::sin(sidereal) + y * std::cos(sidereal)), r * z});
}

double angular_distance(AzEl a, AzEl b) {
    const Vec u = unit(a), v = unit(b);
    const Vec cross{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
    return std::atan2(std::sqrt(cross.x * cross.x + cross.y * cross.y + cross.z * cross.z),
                      u.x * v.x + u.y * v.y + u.z * v.z) /
           degree;
}

}  // namespace birdcage::sim
