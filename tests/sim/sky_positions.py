#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""The emulator's sky (birdcage-sim --sky-at) against independent implementations.

- The Sun: PyEphem (python3-ephem: VSOP87, nutation, aberration, topocentric parallax), refraction
  off (pressure 0), within 0.02 degrees in azimuth and in elevation at several dates and sites.
- The geostationary belt: the emulator computes Earth-fixed vectors on the WGS84 ellipsoid; this
  test uses the textbook spherical look-angle formula instead (central angle and great-circle
  azimuth from the station's geocentric latitude and radius), then corrects for the ellipsoid by
  turning the geocentric horizon onto the geodetic one. Within 0.02 degrees.
- The dish columns: docs/sky.md section 1's sky -> dish map, written here from the text, within
  0.0001 degrees (the printed precision).

Usage: sky_positions.py BIRDCAGE_SIM
"""
import csv
import io
import math
import subprocess
import sys
from datetime import datetime, timezone

import ephem

SUN_TOLERANCE_DEG = 0.02
BELT_TOLERANCE_DEG = 0.02
MOUNT_TOLERANCE_DEG = 1e-4

# (UTC, lat, lon east, height m): summer and winter, both hemispheres, high and low Sun, the
# Sun below the horizon, heights from sea level to 1.8 km, dates across the solar theory's span.
CASES = [
    ("2026-06-21T12:00:00Z", 52.0, 5.0, 0.0),
    ("2026-12-21T03:30:00Z", -33.87, 151.21, 50.0),
    ("2030-03-20T16:45:12.5Z", 40.0, -105.27, 1655.0),
    ("2041-09-01T06:10:00Z", 64.84, -147.72, 136.0),
    ("2001-01-15T09:00:00Z", 0.0, 36.8, 1795.0),
    ("2048-07-04T20:00:00Z", -54.8, -68.3, 0.0),
    ("2026-04-01T08:00:00Z", 35.68, 139.69, 40.0),
    ("2027-10-10T22:15:00Z", 47.37, 8.54, 408.0),
]
MOUNT = {"az_index": 6.5, "el_index": -1.2, "tilt_north": 0.8, "tilt_east": -0.6}

WGS84_A_KM = 6378.137
WGS84_F = 1.0 / 298.257223563
GEO_RADIUS_KM = 42164.17


def sky_at(sim, utc, lat, lon, alt, mount=None):
    command = [*sim, "--sky-at", utc, "--lat", str(lat), "--lon", str(lon), "--alt", str(alt)]
    if mount:
        command += ["--mount", ",".join(f"{k}={v}" for k, v in mount.items())]
    text = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    return list(csv.DictReader(io.StringIO(text)))


def az_difference(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


def ephem_sun(utc, lat, lon, alt):
    when = datetime.fromisoformat(utc.replace("Z", "+00:00")).astimezone(timezone.utc)
    observer = ephem.Observer()
    observer.lat = str(lat)
    observer.lon = str(lon)
    observer.elevation = alt
    observer.pressure = 0  # geometric: no refraction
    observer.date = ephem.Date(when.replace(tzinfo=None))
    sun = ephem.Sun(observer)
    return math.degrees(sun.az), math.degrees(sun.alt)


def spherical_look_angles(lat, lon, alt, sat_lon):
    """Geostationary look angles by spherical trigonometry plus the ellipsoid's deflection."""
    phi = math.radians(lat)
    e2 = WGS84_F * (2.0 - WGS84_F)
    n = WGS84_A_KM / math.sqrt(1.0 - e2 * math.sin(phi) ** 2)
    h = alt / 1000.0
    # The station's geocentric radius and latitude.
    p = (n + h) * math.cos(phi)
    z = (n * (1.0 - e2) + h) * math.sin(phi)
    rho = math.hypot(p, z)
    psi = math.atan2(z, p)
    dlon = math.radians(sat_lon - lon)
    gamma = math.acos(math.cos(psi) * math.cos(dlon))  # central angle to the sub-satellite point
    azimuth = math.atan2(math.sin(dlon), -math.sin(psi) * math.cos(dlon))
    elevation = math.atan2(GEO_RADIUS_KM * math.cos(gamma) - rho, GEO_RADIUS_KM * math.sin(gamma))
    # In the geocentric horizon (east, north, up), then the geodetic vertical, which leans from
    # the radial one toward the pole by phi - psi.
    east = math.cos(elevation) * math.sin(azimuth)
    north = math.cos(elevation) * math.cos(azimuth)
    up = math.sin(elevation)
    d = phi - psi
    north, up = north * math.cos(d) - up * math.sin(d), up * math.cos(d) + north * math.sin(d)
    return math.degrees(math.atan2(east, north)) % 360.0, math.degrees(math.asin(max(-1.0, min(1.0, up))))


def sky_to_dish(az, el, mount):
    """docs/sky.md section 1: v = R_N(-tilt_east) . R_E(-tilt_north) . v', minus the indices."""
    a, e = math.radians(az), math.radians(el)
    x, y, z = math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)
    t = math.radians(-mount["tilt_north"])  # R_E(t)(x, y, z) = (x, y cos t + z sin t, -y sin t + z cos t)
    x, y, z = x, y * math.cos(t) + z * math.sin(t), -y * math.sin(t) + z * math.cos(t)
    t = math.radians(-mount["tilt_east"])  # R_N(t)(x, y, z) = (x cos t + z sin t, y, -x sin t + z cos t)
    x, y, z = x * math.cos(t) + z * math.sin(t), y, -x * math.sin(t) + z * math.cos(t)
    return (math.degrees(math.atan2(x, y)) - mount["az_index"]) % 360.0, math.degrees(math.asin(z)) - mount["el_index"]


def main():
    sim = sys.argv[1:]  # the emulator's command: its path, after qemu's words in a cross build
    failures = []
    sun_az = sun_el = belt_az = belt_el = mount_worst = 0.0
    belt_count = 0
    for utc, lat, lon, alt in CASES:
        rows = sky_at(sim, utc, lat, lon, alt)
        sun = rows[0]
        assert sun["name"] == "Sun", rows[0]
        reference_az, reference_el = ephem_sun(utc, lat, lon, alt)
        d_az = az_difference(float(sun["sky_az"]), reference_az)
        d_el = abs(float(sun["sky_el"]) - reference_el)
        sun_az, sun_el = max(sun_az, d_az), max(sun_el, d_el)
        print(f"{utc} {lat:+.2f} {lon:+.2f}: Sun az {float(sun['sky_az']):.4f} el {float(sun['sky_el']):.4f}, "
              f"ephem {reference_az:.4f} {reference_el:.4f} (d_az {d_az:.5f}, d_el {d_el:.5f})")
        if d_az > SUN_TOLERANCE_DEG or d_el > SUN_TOLERANCE_DEG:
            failures.append(f"Sun at {utc} {lat},{lon}: off ephem by az {d_az:.4f}, el {d_el:.4f}")
        belt = rows[1:]
        if len(belt) < 80:
            failures.append(f"only {len(belt)} belt satellites")
        for row in belt:
            az, el = spherical_look_angles(lat, lon, alt, float(row["longitude_deg"]))
            d_az = az_difference(float(row["sky_az"]), az)
            d_el = abs(float(row["sky_el"]) - el)
            belt_az, belt_el = max(belt_az, d_az), max(belt_el, d_el)
            belt_count += 1
            if d_az > BELT_TOLERANCE_DEG or d_el > BELT_TOLERANCE_DEG:
                failures.append(f"{row['name']} from {lat},{lon}: az {row['sky_az']} el {row['sky_el']}, "
                                f"spherical {az:.5f} {el:.5f}")

        mounted = sky_at(sim, utc, lat, lon, alt, MOUNT)
        for plain, row in zip(rows, mounted):
            if (plain["sky_az"], plain["sky_el"]) != (row["sky_az"], row["sky_el"]):
                failures.append(f"--mount moved the sky of {row['name']}")
            az, el = sky_to_dish(float(row["sky_az"]), float(row["sky_el"]), MOUNT)
            worst = max(az_difference(float(row["dish_az"]), az), abs(float(row["dish_el"]) - el))
            mount_worst = max(mount_worst, worst)
            if worst > MOUNT_TOLERANCE_DEG:
                failures.append(f"{row['name']}: dish {row['dish_az']} {row['dish_el']}, docs/sky.md {az:.6f} {el:.6f}")
        if any(row["dish_az"] == row["sky_az"] for row in mounted):
            failures.append("--mount left a dish azimuth equal to the sky's")

    print(f"Sun vs ephem, {len(CASES)} cases: max |d_az| {sun_az:.5f} deg, max |d_el| {sun_el:.5f} deg")
    print(f"belt vs the spherical formulation, {belt_count} look angles: max |d_az| {belt_az:.6f} deg, "
          f"max |d_el| {belt_el:.6f} deg")
    print(f"dish columns vs docs/sky.md section 1: max deviation {mount_worst:.7f} deg")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
