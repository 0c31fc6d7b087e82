# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-align's picture: the scan in the dish's axes, the catalogue where an unaligned dish
expects it (before) and where the fitted mount puts it (after), and the peaks measured."""

from __future__ import annotations

import numpy as np

from .mount import sky_to_dish


def render(path, scan, sources, result, title: str, arc=None) -> str | None:
    """Writes a PNG; returns its path, or None when matplotlib (python3-matplotlib) is missing."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    fig, ax = plt.subplots(figsize=(11, 5.5), dpi=110)
    import matplotlib.tri as mtri

    tri = mtri.Triangulation(scan.az, scan.el)
    # The band's outline is not convex: no triangles across what was not scanned.
    x, y = scan.az[tri.triangles], scan.el[tri.triangles]
    edges = np.hypot(x - np.roll(x, 1, axis=1), y - np.roll(y, 1, axis=1)).max(axis=1)
    tri.set_mask(edges > 2.5 * np.median(edges))
    sc = ax.tripcolor(tri, scan.value, shading="gouraud", cmap="viridis")
    fig.colorbar(sc, ax=ax, label="RSSI")
    terms = tuple(result.terms)
    if arc is not None:
        ax.plot(arc[0] % 360.0, arc[1], "w--", lw=0.8, label="geostationary arc, unaligned")
        a, e = sky_to_dish(terms, arc[0], arc[1])
        ax.plot(np.asarray(a) % 360.0, e, "w-", lw=0.8, label="geostationary arc, fitted mount")
    sa = np.array([s.az for s in sources])
    se = np.array([s.el for s in sources])
    ax.scatter(sa % 360.0, se, marker="x", c="orange", s=30, label="catalogue, unaligned (before)")
    fa, fe = sky_to_dish(terms, sa, se)
    ax.scatter(np.asarray(fa) % 360.0, fe, marker="o", facecolors="none", edgecolors="red", s=60,
               label="catalogue through the fitted mount (after)")
    measured = [s for s in result.sources if s.residual is not None]
    if measured:
        ax.scatter([s.dish_az for s in measured], [s.dish_el for s in measured], marker="+", c="white", s=80,
                   label="peaks measured")
        for s in measured:
            ax.annotate(f"{s.source.members[0][:14]} {s.residual:.2f}°", (s.dish_az, s.dish_el), fontsize=6,
                        color="white", xytext=(4, 4), textcoords="offset points")
    lo, hi = np.percentile(scan.az, [0, 100])
    ax.set_xlim(lo - 2, hi + 2)
    ax.set_ylim(scan.el.min() - 2, scan.el.max() + 2)
    ax.set_xlabel("dish azimuth (deg)")
    ax.set_ylabel("dish elevation (deg)")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=6, loc="upper right", framealpha=0.4)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return str(path)
