#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Heatmap of a sky scan with the geostationary arc and a satellite catalogue, and a peak finder.

    /usr/bin/python3 tools/skyscan_plot.py SCAN --out PNG [--catalogue CSV] [--lat DEG --lon DEG]
                                           [--title TEXT] [--peaks N]

SCAN is birdcage-skyscan's CSV (az,el,value,time) or the upstream `az el rssi` format. The arc
is drawn for the site latitude (its shape depends on nothing else; --lon only labels the
longitudes along it). The catalogue is `NAME,AZIMUTH,ELEVATION` (look angles at the site).
The peak finder prints the strongest local maxima, the catalogue satellite nearest to each and
the offset (scan minus catalogue): a consistent offset is the dish's pointing error.
Needs Debian's python3-matplotlib and python3-numpy (not needed by the test suite).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

EARTH_RATIO = 0.1513  # Earth radius / geostationary orbit radius
MATCH_RADIUS_DEG = 4.0  # a peak farther from every catalogue entry is not attributed (about a beamwidth)


def read_scan(path):
    points = {}
    with open(path, newline="") as f:
        for line in f:
            line = line.strip()
            fields = line.split(",") if "," in line else line.split()
            try:
                az, el, value = float(fields[0]), float(fields[1]), float(fields[2])
            except (ValueError, IndexError):
                continue  # header or a cut-off row
            points[(round(az, 2), round(el, 2))] = value
    if not points:
        sys.exit(f"skyscan_plot: no rows in {path}")
    azs = sorted({a for a, _ in points})
    els = sorted({e for _, e in points})
    grid = np.full((len(els), len(azs)), np.nan)
    for (a, e), v in points.items():
        grid[els.index(e), azs.index(a)] = v
    return np.array(azs), np.array(els), grid


def read_catalogue(path):
    sats = []
    with open(path, newline="") as f:
        for row in csv.reader(f):
            if len(row) == 3:
                try:
                    sats.append((row[0].strip(), float(row[1]), float(row[2])))
                except ValueError:
                    pass
    return sats


def geostationary_arc(lat, lon, span=81.0, step=0.25):
    """Look angles of the geostationary belt from (lat, lon): (sat_lon, az, el) above the horizon."""
    phi = math.radians(lat)
    out = []
    for k in np.arange(-span, span + step, step):
        d = math.radians(k)
        c = math.cos(d) * math.cos(phi)
        el = math.degrees(math.atan((c - EARTH_RATIO) / math.sqrt(max(1e-12, 1 - c * c))))
        az = 180.0 - math.degrees(math.atan2(math.tan(d), math.sin(phi)))
        if lat < 0:
            az = (360.0 - az) % 360.0
        if el > 0:
            out.append((lon + k, az, el))
    return out


def find_peaks(azs, els, grid, count, radius_deg=4.0):
    floor = np.nanmedian(grid)
    spread = np.nanmedian(np.abs(grid - floor)) * 1.4826
    threshold = floor + max(10.0, 6.0 * spread)
    step_az = azs[1] - azs[0] if len(azs) > 1 else 1.0
    step_el = els[1] - els[0] if len(els) > 1 else 1.0
    ra, re = max(1, round(radius_deg / step_az)), max(1, round(radius_deg / step_el))
    peaks = []
    for i in range(len(els)):
        for j in range(len(azs)):
            v = grid[i, j]
            if np.isnan(v) or v < threshold:
                continue
            window = grid[max(0, i - re): i + re + 1, max(0, j - ra): j + ra + 1]
            if v >= np.nanmax(window):
                peaks.append((v, azs[j], els[i]))
    peaks.sort(reverse=True)
    # One peak per plateau: drop those within the radius of a stronger one.
    kept = []
    for p in peaks:
        if all(abs(p[1] - q[1]) > radius_deg or abs(p[2] - q[2]) > radius_deg for q in kept):
            kept.append(p)
    return floor, kept[:count]


def nearest(sats, az, el):
    best = None
    for name, a, e in sats:
        d = math.hypot((a - az) * math.cos(math.radians(el)), e - el)
        if best is None or d < best[0]:
            best = (d, name, a, e)
    return best


def group_labels(sats):
    """Co-located satellites (within 1 degree) share one label."""
    groups = []
    for name, a, e in sorted(sats, key=lambda s: s[1]):
        for g in groups:
            if abs(g[1] - a) < 1.0 and abs(g[2] - e) < 1.0:
                g[0].append(name)
                break
        else:
            groups.append([[name], a, e])
    return groups


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scan")
    ap.add_argument("--out", required=True)
    ap.add_argument("--catalogue")
    ap.add_argument("--lat", type=float)
    ap.add_argument("--lon", type=float, default=0.0)
    ap.add_argument("--title", default="")
    ap.add_argument("--peaks", type=int, default=8)
    args = ap.parse_args()

    azs, els, grid = read_scan(args.scan)
    sats = read_catalogue(args.catalogue) if args.catalogue else []
    floor, peaks = find_peaks(azs, els, grid, args.peaks)

    fig, ax = plt.subplots(figsize=(10, 4.6), dpi=110)
    lo, hi = np.nanpercentile(grid, 1), np.nanmax(grid)
    mesh = ax.pcolormesh(azs, els, grid, shading="nearest", cmap="inferno", vmin=lo, vmax=hi)
    fig.colorbar(mesh, ax=ax, label="RSSI (counts)", pad=0.01)
    if args.lat is not None:
        arc = [(lon, a, e) for lon, a, e in geostationary_arc(args.lat, args.lon)
               if azs[0] - 5 <= a <= azs[-1] + 5]
        ax.plot([a for _, a, _ in arc], [e for _, _, e in arc], "--", color="cyan", lw=1,
                label=f"geostationary arc, site {args.lat:.2f}, {args.lon:.2f}")
    inside = [s for s in sats if azs[0] <= s[1] <= azs[-1] and els[0] <= s[2] <= els[-1]]
    if inside:
        ax.scatter([s[1] for s in inside], [s[2] for s in inside], s=12, marker="o", facecolors="none",
                   edgecolors="white", linewidths=0.8, label="catalogue")
        for k, (names, a, e) in enumerate(group_labels(inside)):
            label = names[0] + (f" +{len(names) - 1}" if len(names) > 1 else "")
            ax.annotate(label, (a, e), xytext=(0, 9 if k % 2 == 0 else -12), textcoords="offset points",
                        ha="center", fontsize=6, color="white")
    if peaks:
        ax.scatter([p[1] for p in peaks], [p[2] for p in peaks], marker="+", s=80, color="lime", label="peaks found")
    ax.set_xlabel("azimuth (deg)")
    ax.set_ylabel("elevation (deg)")
    ax.set_xlim(azs[0] - 0.5, azs[-1] + 0.5)
    ax.set_ylim(els[0] - 0.5, els[-1] + 0.5)
    ax.set_title(args.title)
    ax.legend(loc="upper right", fontsize=7, framealpha=0.4)
    fig.tight_layout()
    fig.savefig(args.out)

    print(f"floor (median) {floor:.0f}; {len(peaks)} peaks")
    print(f"{'rank':>4} {'value':>6} {'az':>7} {'el':>6}  nearest catalogue satellite      d_az   d_el")
    offsets = []
    for rank, (v, a, e) in enumerate(peaks, 1):
        line = f"{rank:>4} {v:>6.0f} {a:>7.2f} {e:>6.2f}"
        near = nearest(sats, a, e) if sats else None
        if near and near[0] > MATCH_RADIUS_DEG:
            line += f"  (no catalogue satellite within {MATCH_RADIUS_DEG:.0f} deg)"
        elif near:
            _, name, ca, ce = near
            offsets.append((a - ca, e - ce))
            line += f"  {name:<30} {a - ca:+6.2f} {e - ce:+6.2f}"
        print(line)
    if offsets:
        print(f"median pointing offset (scan - catalogue): az {np.median([o[0] for o in offsets]):+.2f}, "
              f"el {np.median([o[1] for o in offsets]):+.2f} deg")


if __name__ == "__main__":
    main()
