// SPDX-License-Identifier: LGPL-2.1-or-later
// Copyright (C) 2026 the birdcage authors

// Where things are in the emulated dish's sky, written from docs/sky.md independently of the
// backend (the emulator is its test oracle): the mount model of docs/sky.md §1 that sets the
// dish's axes against the sky, UTC as ISO-8601 text, and the topocentric look angles of the Sun
// and of geostationary slots from a station on the WGS84 ellipsoid (geometric: no refraction).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace birdcage::sim {

struct AzEl {
    double az = 0.0;  // degrees from true north, east positive
    double el = 0.0;  // degrees above the horizon
};

// The four terms of docs/sky.md §1, in degrees. All zero: the dish's axes are the sky.
struct Mount {
    double az_index = 0.0;
    double el_index = 0.0;
    double tilt_north = 0.0;
    double tilt_east = 0.0;
    bool identity() const { return az_index == 0.0 && el_index == 0.0 && tilt_north == 0.0 && tilt_east == 0.0; }
};

// docs/sky.md §1, both ways. Azimuths are carried as differences, so the result stays on the
// cable-wrap branch of the input (dish 400 with az_index 6 is sky 406); at the zenith of the
// result the input's azimuth is kept. The identity mount returns its input unchanged.
AzEl dish_to_sky(const Mount& mount, AzEl dish);
AzEl sky_to_dish(const Mount& mount, AzEl sky);

// A station on the WGS84 ellipsoid: geodetic latitude, longitude (east positive), height in metres.
struct Station {
    double lat_deg = 0.0;
    double lon_deg = 0.0;
    double alt_m = 0.0;
};

// UTC instants are seconds since 1970-01-01T00:00:00Z (leap seconds not counted, like time_t).
// Parses YYYY-MM-DD[(T| )HH:MM[:SS[.fff...]]][Z|+HH:MM|-HH:MM]; no zone means UTC.
std::optional<double> parse_utc(std::string_view iso);
// YYYY-MM-DDTHH:MM:SS.mmmZ, rounded to the millisecond.
std::string format_utc(double utc);

// Topocentric look angles of a geostationary satellite at `longitude_deg` (east positive) on the
// equator at 42164.17 km from the Earth's centre.
AzEl geostationary_direction(const Station& station, double longitude_deg);
// Topocentric apparent position of the Sun's centre at `utc` (Meeus's solar coordinates with the
// largest perturbations, nutation and aberration, Greenwich apparent sidereal time, the station's
// parallax): within 0.005 degrees of ERFA's and PyEphem's Sun between 1990 and 2050.
AzEl sun_direction(const Station& station, double utc);

// Great-circle angle between two directions, degrees.
double angular_distance(AzEl a, AzEl b);

}  // namespace birdcage::sim
