#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Generates the benchmark's satellite passes (bench/passes/*.csv) with SGP4.

The passes come from synthetic elements, not real TLEs, so that the set is reproducible and covers
exactly the cases the benchmark needs: ~420 km ISS-like and ~820 km sun-synchronous orbits, peak
elevations around 20, 45, 70 and 85 degrees, and passes whose azimuth crosses north while the
satellite is high enough for the dish to follow it. For each wanted pass the right-ascension of the
ascending node is searched (coarse scan, then bisection) until the pass peaks at the wanted
elevation over the observer; everything else in the elements stays fixed and is written into the
CSV header.

Needs Debian's python3-sgp4 and python3-numpy; run it with the system interpreter:
    /usr/bin/python3 bench/generate_passes.py [output-dir]
"""
import math
import os
import sys

import numpy as np
from sgp4.api import WGS72, Satrec, jday
from sgp4.propagation import gstime

# Observer: the site docs/tracking.md's SGP4 statistics use (45 N, 93 W), 250 m above the ellipsoid.
SITE_LAT_DEG, SITE_LON_DEG, SITE_ALT_KM = 45.0, -93.0, 0.25
# Epoch of every synthetic element set: 2024-06-01 00:00:00 UTC.
EPOCH = (2024, 6, 1, 0, 0, 0.0)

EARTH_MU = 398600.8  # km^3/s^2, WGS-72 (what SGP4 uses)
EARTH_RADIUS_KM = 6378.135

ORBITS = {
    # name: (altitude km, inclination deg, eccentricity, argument of perigee deg)
    "iss": (420.0, 51.64, 0.0005, 90.0),
    "sso": (820.0, 98.70, 0.0010, 90.0),
}
# What the set must contain besides a spread of peak elevations (docs/tracking.md §2.3): north crossings with the
# azimuth growing (iss-45, iss-85) and shrinking (sso-70), passes no branch of a dish's azimuth
# travel holds (Trav'ler 0..455: iss-85, sso-70; G2 -423.33..+23.33: iss-60, an ascending ISS pass
# north of the zenith, rising west of 296.67 and setting east of +23.33).
def crossing_north(info):
    return info["crosses_north"]


def not_crossing_north(info):
    return not info["crosses_north"]


def crossing_north_rising_west(info):
    return info["crosses_north"] and info["aos_az"] < 280.0


# (orbit, wanted peak elevation, what the pass must also be, or None for "don't care")
WANTED = [
    ("iss", 20.0, not_crossing_north), ("iss", 45.0, crossing_north), ("iss", 70.0, not_crossing_north),
    ("iss", 85.0, crossing_north), ("sso", 20.0, not_crossing_north), ("sso", 45.0, not_crossing_north),
    ("sso", 70.0, crossing_north), ("sso", 85.0, not_crossing_north),
    ("iss", 60.0, crossing_north_rising_west),
]
# A pass "crosses north" for the benchmark when its azimuth passes through 0 while the satellite is
# above the lowest elevation any benchmarked dish can reach (Trav'ler 15 deg).
NORTH_CROSSING_MIN_EL = 15.0
SAMPLE_STEP_S = 0.5  # linear interpolation between samples is good to < 0.01 deg on the sky


def mean_motion_rad_per_min(alt_km):
    a = EARTH_RADIUS_KM + alt_km
    return math.sqrt(EARTH_MU / a**3) * 60.0


def make_satellite(orbit, raan_deg):
    alt, incl, ecc, argp = ORBITS[orbit]
    jd, fr = jday(*EPOCH)
    epoch_days_since_1949 = jd + fr - 2433281.5
    sat = Satrec()
    sat.sgp4init(WGS72, "i", 99999, epoch_days_since_1949, 0.0, 0.0, 0.0, ecc,
                 math.radians(argp), math.radians(incl), 0.0, mean_motion_rad_per_min(alt),
                 math.radians(raan_deg))
    return sat


def site_ecef_km():
    lat, lon = math.radians(SITE_LAT_DEG), math.radians(SITE_LON_DEG)
    a, f = 6378.137, 1 / 298.257223563  # WGS-84 ellipsoid for the site
    e2 = f * (2 - f)
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    return np.array([(n + SITE_ALT_KM) * math.cos(lat) * math.cos(lon),
                     (n + SITE_ALT_KM) * math.cos(lat) * math.sin(lon),
                     (n * (1 - e2) + SITE_ALT_KM) * math.sin(lat)])


SITE = site_ecef_km()
LAT, LON = math.radians(SITE_LAT_DEG), math.radians(SITE_LON_DEG)
# Rows: east, north, up unit vectors of the site in ECEF.
ENU = np.array([[-math.sin(LON), math.cos(LON), 0.0],
                [-math.sin(LAT) * math.cos(LON), -math.sin(LAT) * math.sin(LON), math.cos(LAT)],
                [math.cos(LAT) * math.cos(LON), math.cos(LAT) * math.sin(LON), math.sin(LAT)]])


def az_el(sat, seconds):
    """Topocentric azimuth/elevation (deg) at `seconds` after the epoch. TEME is turned into
    Earth-fixed coordinates with the sidereal angle only (no polar motion): arc-seconds, far below
    anything a dish notices."""
    seconds = np.atleast_1d(np.asarray(seconds, dtype=float))
    jd0, fr0 = jday(*EPOCH)
    jd = np.full(seconds.shape, jd0)
    fr = fr0 + seconds / 86400.0
    err, r, _ = sat.sgp4_array(jd, fr)
    if np.any(err != 0):
        raise RuntimeError("sgp4 error")
    theta = np.array([gstime(j + f) for j, f in zip(jd, fr)])
    c, s = np.cos(theta), np.sin(theta)
    ecef = np.stack([c * r[:, 0] + s * r[:, 1], -s * r[:, 0] + c * r[:, 1], r[:, 2]], axis=1)
    enu = (ecef - SITE) @ ENU.T
    az = np.degrees(np.arctan2(enu[:, 0], enu[:, 1])) % 360.0
    el = np.degrees(np.arctan2(enu[:, 2], np.hypot(enu[:, 0], enu[:, 1])))
    return az, el


def passes_in(sat, horizon_s=3 * 3600, step_s=20.0):
    """(tca_s, peak_el) of every pass in the first hours after the epoch, coarsely."""
    t = np.arange(0.0, horizon_s, step_s)
    _, el = az_el(sat, t)
    found = []
    for i in range(1, len(t) - 1):
        if el[i] > 0 and el[i] >= el[i - 1] and el[i] > el[i + 1]:
            found.append((t[i], el[i]))
    return found


def refine_peak(sat, tca_guess):
    t = np.arange(tca_guess - 60.0, tca_guess + 60.0, 0.5)
    _, el = az_el(sat, t)
    i = int(np.argmax(el))
    return t[i], el[i]


def pass_near(orbit, raan, tca_guess):
    tca, peak = refine_peak(make_satellite(orbit, raan), tca_guess)
    return tca, peak


def find_raan(orbit, target, wanted):
    coarse = {}
    raans = np.arange(0.0, 360.0, 0.5)
    for raan in raans:
        coarse[raan] = passes_in(make_satellite(orbit, raan))
    candidates = []
    for r0, r1 in zip(raans[:-1], raans[1:]):
        for t0, e0 in coarse[r0]:
            for t1, e1 in coarse[r1]:
                if abs(t1 - t0) < 300 and (e0 - target) * (e1 - target) <= 0:
                    candidates.append((r0, r1, t0))
    results = []
    for r0, r1, t0 in candidates:
        lo, hi = r0, r1
        e_lo = pass_near(orbit, lo, t0)[1]
        tca = t0
        for _ in range(30):
            mid = 0.5 * (lo + hi)
            tca, e_mid = pass_near(orbit, mid, tca)
            if (e_mid - target) * (e_lo - target) <= 0:
                hi = mid
            else:
                lo, e_lo = mid, e_mid
        raan = 0.5 * (lo + hi)
        tca, peak = pass_near(orbit, raan, tca)
        if abs(peak - target) > 0.2:
            continue
        info = describe_pass(orbit, raan, tca)
        results.append((raan, info))
        if wanted is None or wanted(info):
            return raan, info
    if results:
        return results[0]
    raise RuntimeError(f"no {orbit} pass peaking at {target}")


def describe_pass(orbit, raan, tca):
    sat = make_satellite(orbit, raan)
    t = np.arange(tca - 1200.0, tca + 1200.0, 1.0)
    az, el = az_el(sat, t)
    up = np.where(el > 0)[0]
    # The visible stretch that contains the TCA.
    centre = int(np.argmin(abs(t - tca)))
    start = centre
    while start > 0 and el[start - 1] > 0:
        start -= 1
    end = centre
    while end < len(t) - 1 and el[end + 1] > 0:
        end += 1
    assert len(up) > 0
    aos, los = t[start], t[end]
    high = (el >= NORTH_CROSSING_MIN_EL) & (t >= aos) & (t <= los)
    high_az = az[high]
    crosses = bool(np.any(np.abs(np.diff(high_az)) > 180.0))
    return {"aos": aos, "los": los, "tca": tca, "crosses_north": crosses,
            "aos_az": az[start], "los_az": az[end], "peak": float(np.max(el))}


def write_pass(directory, name, orbit, raan, info):
    sat = make_satellite(orbit, raan)
    # From 30 s before AOS to LOS: the client points at the AOS azimuth before AOS, as Gpredict does.
    start = math.floor(info["aos"]) - 30.0
    t = np.arange(start, info["los"] + SAMPLE_STEP_S / 2, SAMPLE_STEP_S)
    az, el = az_el(sat, t)
    alt, incl, ecc, argp = ORBITS[orbit]
    path = os.path.join(directory, name + ".csv")
    with open(path, "w") as out:
        out.write(f"# pass {name}: SGP4 (python3-sgp4, WGS-72) from synthetic elements, generated by "
                  "bench/generate_passes.py\n")
        out.write(f"# site lat {SITE_LAT_DEG} lon {SITE_LON_DEG} alt_km {SITE_ALT_KM}; epoch "
                  "2024-06-01T00:00:00Z\n")
        out.write(f"# elements: mean-motion altitude {alt} km, incl {incl} deg, ecc {ecc}, argp {argp} deg, "
                  f"mean anomaly 0 deg, raan {raan:.6f} deg, bstar 0\n")
        out.write(f"# peak_el {info['peak']:.2f} tca_s {info['tca'] - start:.1f} aos_s {info['aos'] - start:.1f} "
                  f"los_s {info['los'] - start:.1f} aos_az {info['aos_az']:.2f} los_az {info['los_az']:.2f} "
                  f"crosses_north {int(info['crosses_north'])}\n")
        out.write("t,az,el\n")
        for ti, a, e in zip(t - start, az, el):
            out.write(f"{ti:.1f},{a:.4f},{e:.4f}\n")
    return path


def main():
    directory = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "passes")
    os.makedirs(directory, exist_ok=True)
    index = []
    for orbit, target, wanted in WANTED:
        raan, info = find_raan(orbit, target, wanted)
        name = f"{orbit}-{int(target)}"
        write_pass(directory, name, orbit, raan, info)
        index.append((name, orbit, raan, info))
        print(f"{name}: raan {raan:.4f} peak {info['peak']:.2f} duration {info['los'] - info['aos']:.0f} s "
              f"aos_az {info['aos_az']:.1f} los_az {info['los_az']:.1f} crosses_north {info['crosses_north']}")
    with open(os.path.join(directory, "index.csv"), "w") as out:
        out.write("name,orbit,altitude_km,inclination_deg,raan_deg,peak_el,duration_s,aos_az,los_az,crosses_north\n")
        for name, orbit, raan, info in index:
            alt, incl, _, _ = ORBITS[orbit]
            out.write(f"{name},{orbit},{alt},{incl},{raan:.4f},{info['peak']:.2f},{info['los'] - info['aos']:.0f},"
                      f"{info['aos_az']:.1f},{info['los_az']:.1f},{int(info['crosses_north'])}\n")


if __name__ == "__main__":
    main()
