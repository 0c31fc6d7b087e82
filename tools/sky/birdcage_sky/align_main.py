# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-align: measures how a dish's axes sit against the sky (docs/sky.md sections 1 and 3)
from a scan of the geostationary arc (or of the Sun) through rotctld, and prints the conf that
corrects it."""

from __future__ import annotations

import math
import signal
import sys
import time
from pathlib import Path

from . import cli

DESCRIPTION = """\
Scans the geostationary arc (or the Sun, --sun) with the dish behind rotctld, reading the
receiver's signal (`v RSSI`, the birdcage backend's Carryout G2), finds the satellites in the scan,
fits the four mount terms of docs/sky.md (az_index, el_index, tilt_north, tilt_east) and prints
the -C lines that correct the dish. --from-scan fits a scan taken before instead.
"""


def build_parser(version: str) -> cli.Parser:
    p = cli.Parser(prog="birdcage-align", usage="birdcage-align [options]", description=DESCRIPTION, version=version)
    g = p.add_argument_group("what to scan")
    g.add_argument("--from-scan", metavar="FILE",
                   help="fit this scan instead of scanning: upstream `az el rssi` lines or birdcage-skyscan's CSV")
    g.add_argument("--catalogue", metavar="FILE",
                   help="the sources as `name,az,el` look angles at the site (no header); default: the "
                        "geostationary table for --lat/--lon")
    g.add_argument("--sun", action="store_true", help="cross-scan the Sun instead of the geostationary arc")
    g.add_argument("--with-sun", choices=("auto", "yes", "no"), default="auto", metavar="auto|yes|no",
                   help="after the arc, cross-scan the Sun too and fit both together: its direction, off the arc, "
                        "tells the tilts from the index terms (auto: when the Sun is 5 deg above the floor)")
    g.add_argument("--sun-fixes", type=int, default=1, metavar="N",
                   help="Sun measurements, --sun-interval apart (1-2: index terms only; 3 or more: all four)")
    g.add_argument("--sun-interval", type=float, default=20.0, metavar="MIN", help="minutes between Sun measurements")
    g.add_argument("--az-error", type=float, default=15.0, metavar="DEG",
                   help="the azimuth error the scan must cover (default 15)")
    g.add_argument("--el-error", type=float, default=4.0, metavar="DEG",
                   help="the elevation error the scan must cover (default 4)")
    g.add_argument("--step", type=float, default=2.0, metavar="DEG", help="the scan's grid step (default 2)")
    g.add_argument("--samples", type=int, metavar="N", help="RSSI reads averaged per point (the backend's RSSI_SAMPLES)")
    g.add_argument("--lnb", choices=("13", "18", "keep"), default="13", metavar="13|18|keep",
                   help="LNB supply: 13 V (vertical, the default), 18 V, or keep what it is")
    g = p.add_argument_group("the fit and its output")
    g.add_argument("--index-only", action="store_true", help="fit az_index and el_index only (tilts 0)")
    g.add_argument("--lag", choices=("auto", "yes", "no"), default="auto", metavar="auto|yes|no",
                   help="fit the share of a step each reading lags its label (auto: for serpentine scans)")
    g.add_argument("--save-scan", metavar="FILE", help="write the scan as CSV az,el,value,time")
    g.add_argument("--plot", metavar="FILE", default="birdcage-align.png", help="the picture, PNG (default birdcage-align.png)")
    g.add_argument("--no-plot", action="store_true", help="no picture")
    g.add_argument("--name", default="<name>", help="the dish's name in the service file's path")
    cli.add_common(p)
    return p


class Reporter:
    def __init__(self, json_mode: bool):
        self.json_mode = json_mode
        self.last = 0.0

    def progress(self, done: int, total: int, phase: str) -> None:
        if self.json_mode:
            cli.print_json({"event": "progress", "done": done, "total": total, "phase": phase})
        elif time.monotonic() - self.last > 2.0 or done == total:
            self.last = time.monotonic()
            print(f"birdcage-align: {phase} {done}/{total}", file=sys.stderr, flush=True)

    def phase(self, name: str) -> None:
        if self.json_mode:
            cli.print_json({"event": "progress", "done": 0, "total": 1, "phase": name})
        else:
            print(f"birdcage-align: {name}...", file=sys.stderr, flush=True)


def conf_lines(terms) -> list[str]:
    from .mount import TERMS

    return [f"-C {name}={value:.2f}" for name, value in zip(TERMS, terms)]


def main(argv: list[str], version: str = "", started: float | None = None) -> int:
    parser = build_parser(version)
    args = parser.parse_args(argv)
    try:
        if args.step <= 0 or args.az_error < 0 or args.el_error < 0:
            raise cli.UsageError("--step must be positive and the errors not negative")
        if args.from_scan and args.sun:
            raise cli.UsageError("--from-scan and --sun are alternatives")
        if args.samples is not None and not 1 <= args.samples <= 100:
            raise cli.UsageError("--samples is 1..100")
        station = cli.station_from(args, required=not (args.from_scan and args.catalogue))
        clock = cli.clock_from(args, started)
    except cli.UsageError as error:
        parser.error(str(error))
    report = Reporter(args.json)
    from .rotctld import Rotctld, RotctldError
    from .scanner import ScanError

    rot = Rotctld(args.host, args.port)
    state = {"scanner": None}

    def on_signal(signum, frame):
        if state["scanner"] is not None:
            state["scanner"].stop_requested = True
        else:
            raise KeyboardInterrupt

    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)
    try:
        if args.sun:
            result = align_sun(args, station, clock, rot, report, state)
        else:
            result = align_arc(args, station, clock, rot, report, state)
    except KeyboardInterrupt:
        try:
            rot.stop()
        except RotctldError:
            pass
        return fail(args, "interrupted: the dish was sent S (stop)")
    except (ScanError, RotctldError, FileNotFoundError, ValueError, ConnectionError, LookupError) as error:
        return fail(args, str(error))
    finally:
        rot.close()
    emit_result(args, result)
    return 0


def fail(args, message: str) -> int:
    print(f"birdcage-align: {message}", file=sys.stderr)
    if args.json:
        cli.print_json({"event": "error", "reason": message})
    return 1


def catalogue_sources(args, station, clock, el_floor: float):
    from . import geo

    if args.catalogue:
        sources = geo.read_look_angles(Path(args.catalogue))
    elif args.tle or args.fetch:
        sources = geo.from_tles(station, cli.tle_loader(args)(), clock.now())
        if not sources:
            raise ValueError("no geostationary satellite (about one revolution a day) in the TLEs")
    else:
        sources = geo.from_longitudes(station, geo.read_longitudes())
    return [s for s in sources if s.el >= el_floor]


def align_arc(args, station, clock, rot, report, state) -> dict:
    from . import align, geo, scanio
    from .mount import sky_to_dish
    from .rotctld import mount_from_info
    from .scanner import Scanner, arc_curve, plan_band

    scan_seconds = None
    points_planned = None
    if args.from_scan:
        scan = scanio.read(Path(args.from_scan))
        sources = catalogue_sources(args, station, clock, el_floor=0.0)
    else:
        limits = rot.limits()
        scanner = Scanner(rot, clock, report.progress)
        state["scanner"] = scanner
        scanner.check_rssi()
        if args.lnb != "keep":
            rot.set_level("LNB", args.lnb)
        if args.samples:
            rot.set_level("RSSI_SAMPLES", args.samples)
        margin = align.BEAM_SIGMA_DEG
        sources = catalogue_sources(args, station, clock, el_floor=limits.el_min - args.el_error - margin)
        band = plan_band(station, limits, [s.az for s in sources], args.az_error, args.el_error, args.step, margin)
        points_planned = len(band.points)
        begun = clock.now()
        scan = scanner.scan(band.points)
        sun_note = add_sun(args, station, clock, limits, scanner, scan)
        scan_seconds = clock.now() - begun
        state["scanner"] = None
        configured = mount_from_info(rot.info())
        if configured is not None:
            # The backend answered in the sky of the terms it was given: back to the dish's axes,
            # so that the fit finds the whole mount, not what is left of it.
            scan.az, scan.el = sky_to_dish(configured, scan.az, scan.el)
            scan.az = scan.az % 360.0
    if args.save_scan:
        scan.save(Path(args.save_scan))
    # Only sources at the same place (a shared slot) become one; neighbours a beam apart stay
    # apart in the fit, which shares the signal among them (measure_sources groups them).
    clusters = geo.cluster(sources, radius_deg=0.1)
    # A scan of our own reads each point at rest, where `p` said the dish was: no lag to fit.
    lag = {"auto": None if args.from_scan else False, "yes": True, "no": False}[args.lag]
    moving = []
    if station is not None and scan.time is not None:
        # The Sun is the strongest thing a Ku-band dish hears: where it crosses the band, it is
        # part of the model, at its place at each reading's time.
        from .targets import no_satellites, resolve

        sun = resolve("sun", no_satellites)
        az, el = sun.look(station, scan.time)
        if el.max() > 0:
            moving.append(("sun", az, el))
    result = align.fit(scan, clusters, fit_tilts=not args.index_only, fit_lag=lag, progress=report.phase,
                       moving=moving)
    floor, peaks = align.find_peaks(scan)
    plot = None
    if not args.no_plot:
        arc = arc_curve(station) if station is not None else None
        title = (f"birdcage-align: {', '.join(conf_lines(result.terms))}; residual "
                 f"{result.rms_residual_deg if result.rms_residual_deg is not None else float('nan'):.2f} deg RMS")
        from .plot import render

        plot = render(args.plot, scan, clusters, result, title, arc)
    out = assemble(result, scan_seconds, len(scan), points_planned, plot, peaks, clusters)
    if not args.from_scan:
        out["sun"] = sun_note
        out["configured_mount"] = None if configured is None else dict(zip(("az_index", "el_index", "tilt_north",
                                                                            "tilt_east"), configured))
    return out


def add_sun(args, station, clock, limits, scanner, scan) -> str:
    """Appends a Sun cross-scan to the arc's readings (the fit models the Sun where it is at each
    reading). Returns what was done, for the result."""
    import numpy as np

    from .scanner import ScanError, sun_fix
    from .targets import no_satellites, resolve

    if args.with_sun == "no":
        return "not asked"
    _, el = resolve("sun", no_satellites).look_one(station, clock.now())
    if el < limits.el_min + 5 and args.with_sun == "auto":
        return f"below the dish's floor (el {el:.1f})"
    try:
        fix = sun_fix(scanner, station, limits, min(args.az_error, 10.0), args.el_error, step=args.step)
    except ScanError as error:
        if args.with_sun == "yes":
            raise
        return f"not found: {error}"
    for name in ("az", "el", "value", "time"):
        setattr(scan, name, np.concatenate([getattr(scan, name), getattr(fix.scan, name)]))
    return f"cross-scanned at az {fix.sky_az:.1f} el {fix.sky_el:.1f} ({fix.readings} readings)"


def assemble(result, scan_seconds, points, planned, plot, peaks, clusters) -> dict:
    from .mount import TERMS, sky_to_dish

    r2 = lambda x, n=3: None if x is None or (isinstance(x, float) and not math.isfinite(x)) else round(float(x), n)
    sources = []
    for s in result.sources:
        if s.residual is None:
            continue
        sources.append({"name": s.source.name, "sky_az": r2(s.source.az), "sky_el": r2(s.source.el),
                        "dish_az": r2(s.dish_az), "dish_el": r2(s.dish_el), "residual_deg": r2(s.residual),
                        "amplitude": r2(s.amplitude, 1), "uncertainty_deg": r2(s.uncertainty)})
    peak_rows = []
    for value, az, el in peaks:
        best = None
        for c in clusters:
            a, e = sky_to_dish(tuple(result.terms), c.az, c.el)
            d = math.hypot((((az - a + 180) % 360) - 180) * math.cos(math.radians(el)), el - e)
            if best is None or d < best[0]:
                best = (d, c.name)
        peak_rows.append({"az": az, "el": el, "value": value,
                          "nearest": best[1] if best and best[0] <= 4.0 else None})
    return {"event": "result", **{name: r2(v) for name, v in zip(TERMS, result.terms)},
            "sigma": {name: r2(v) for name, v in zip(TERMS, result.sigma_terms)},
            "residual_rms_deg": r2(result.rms_residual_deg), "n_sources": len(sources), "sources": sources,
            "conf_lines": conf_lines(result.terms), "scan_seconds": r2(scan_seconds, 1), "plot": plot,
            # Extensions: the scan's size, the beam fitted, what was fitted, the raw peaks.
            "scan_points": points, "scan_points_planned": planned, "beam_sigma_deg": r2(result.beam_sigma),
            "lag": r2(result.lag), "fitted": result.fitted, "peaks": peak_rows}


def align_sun(args, station, clock, rot, report, state) -> dict:
    from .scanner import Scanner, fit_fixes, sun_fix

    limits = rot.limits()
    scanner = Scanner(rot, clock, report.progress)
    state["scanner"] = scanner
    scanner.check_rssi()
    if args.samples:
        rot.set_level("RSSI_SAMPLES", args.samples)
    fixes = []
    begun = clock.now()
    for k in range(args.sun_fixes):
        if k:
            clock.sleep_until(fixes[-1].time + args.sun_interval * 60)
        fixes.append(sun_fix(scanner, station, limits, args.az_error, args.el_error, step=args.step))
    scan_seconds = clock.now() - begun
    state["scanner"] = None
    from .mount import sky_to_dish
    from .rotctld import mount_from_info

    configured = mount_from_info(rot.info())
    if configured is not None:  # back to the dish's axes, as in align_arc
        for f in fixes:
            f.dish_az, f.dish_el = sky_to_dish(configured, f.dish_az, f.dish_el)
            f.dish_az %= 360.0
    fit_tilts = len(fixes) >= 3 and not args.index_only
    terms, sigma, residuals = fit_fixes(fixes, fit_tilts)
    from .align import Result, SourceFit
    from .geo import Source

    fits = []
    for f, res in zip(fixes, residuals):
        name = f"sun {time.strftime('%H:%M:%S', time.gmtime(f.time))}Z"
        fits.append(SourceFit(Source(name, f.sky_az, f.sky_el, ["sun"]), f.peak, f.dish_az, f.dish_el, f.sky_az,
                              f.sky_el, float(res), None))
    fitted = ["az_index", "el_index"] + (["tilt_north", "tilt_east"] if fit_tilts else [])
    # Each fix gives two numbers: with no more of them than terms fitted, the residuals are 0 by
    # construction and say nothing.
    rms = math.sqrt(sum(r * r for r in residuals) / len(residuals)) if 2 * len(fixes) > len(fitted) else None
    result = Result(terms, sigma, float("nan"), 0.0, None, fits, rms, 0.0, fitted)
    return assemble(result, scan_seconds, sum(f.readings for f in fixes), None, None, [], [])


def emit_result(args, result: dict) -> None:
    if args.json:
        cli.print_json(result)
        return
    if result["scan_seconds"] is not None:
        print(f"scan: {result['scan_points']} points in {result['scan_seconds'] / 60:.1f} min of the dish's time")
    print(f"fitted: {', '.join(result['fitted'])}")
    for name in ("az_index", "el_index", "tilt_north", "tilt_east"):
        print(f"  {name:<11} {result[name]:+7.3f} deg  ± {result['sigma'][name]:.3f}")
    print(f"sources ({result['n_sources']}): residual = distance from where the fitted mount puts them")
    for s in result["sources"]:
        print(f"  {s['name'][:40]:<40} sky {s['sky_az']:7.2f} {s['sky_el']:6.2f}   dish {s['dish_az']:7.2f} "
              f"{s['dish_el']:6.2f}   residual {s['residual_deg']:.3f}")
    rms = result["residual_rms_deg"]
    print(f"residual RMS {rms:.3f} deg" if rms is not None else "residual RMS: no source measured")
    if result["plot"]:
        print(f"plot: {result['plot']}")
    print(f"For the dish's service, /etc/default/birdcage-rotctld-{args.name} (docs/usage.md):")
    print(f"  OPTIONS=\"{' '.join(result['conf_lines'])}\"")
    print("  (added to any options already there; then systemctl restart "
          f"birdcage-rotctld@{args.name}; on a rotctld command line: {' '.join(result['conf_lines'])})")
