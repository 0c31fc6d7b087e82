# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-track: find, list and follow satellites, the Sun, the Moon, planets and fixed
positions with a dish behind rotctld (docs/sky.md; the JSON is the contract the MCP server and
the TUI read)."""

from __future__ import annotations

import math
import signal
import sys

from . import cli
from .clock import iso
from .rotctld import Limits, Rotctld, RotctldError

DESCRIPTION = """\
Follows TARGET with the dish behind rotctld, or lists what can be followed. TARGET: a satellite
(name, unique prefix or NORAD number from the TLEs), sun, moon, a planet (mercury .. neptune),
radec:RA,DEC (J2000, degrees) or azel:AZ,EL (degrees). Positions are geometric (no refraction);
satellites by SGP4, the rest by PyEphem. Passes are where TARGET enters and leaves the dish's
window (el_min..el_max as rotctld reports them), not the horizon.
"""

STALE_DAYS = 30.0


def build_parser(version: str) -> cli.Parser:
    p = cli.Parser(prog="birdcage-track", usage="birdcage-track [options] [TARGET]", description=DESCRIPTION,
                   version=version)
    p.add_argument("target", nargs="?", metavar="TARGET", help="what to follow or list passes of")
    g = p.add_argument_group("what to do (default: follow TARGET)")
    g.add_argument("--search", metavar="TEXT", help="list the satellites whose name contains TEXT")
    g.add_argument("--passes", action="store_true", help="list TARGET's passes through the dish's window")
    g.add_argument("--visible", action="store_true", help="list what is above the dish's floor now")
    g.add_argument("--hours", type=float, default=24.0, help="how far ahead passes are looked for (default 24)")
    g.add_argument("--count", type=int, help="at most this many passes")
    g = p.add_argument_group("following")
    g.add_argument("--duration", type=float, metavar="S", help="stop after S seconds (of the clock)")
    g.add_argument("--park-at-los", action="store_true", help="park the dish (rotctld K) at LOS")
    g.add_argument("--threshold", type=float, default=0.2, metavar="DEG",
                   help="send a new target when the led one has moved this far on the sky (default 0.2)")
    g.add_argument("--response", type=float, metavar="S",
                   help="the dish's response to a target, seconds, instead of learning it (0: no lead at all)")
    g.add_argument("--log", metavar="FILE", help="write every poll as CSV: time,target_az,target_el,dish_az,dish_el,"
                                                 "sent_az,sent_el,response_s,error_deg")
    g.add_argument("--el-min", type=float, metavar="DEG", help="narrow the window's floor (default: rotctld's)")
    g.add_argument("--el-max", type=float, metavar="DEG", help="narrow the window's cap (default: rotctld's)")
    cli.add_common(p)
    return p


def read_limits(args, rot: Rotctld, required: bool) -> Limits:
    try:
        limits = rot.limits()
    except RotctldError:
        if required:
            raise
        limits = Limits()  # rotctld unreachable: the horizon to the zenith, and said so
    if args.el_min is not None:
        limits.el_min = max(limits.el_min, args.el_min)
    if args.el_max is not None:
        limits.el_max = min(limits.el_max, args.el_max)
    return limits


def limits_json(limits: Limits) -> dict:
    return {"limits": limits.as_json(), "limits_source": "default" if limits.source == "default" else "rotctld"}


def do_search(args, loader) -> int:
    from . import tle as tlemod
    found = tlemod.search(loader(), args.search)
    if args.json:
        cli.print_json({"satellites": [t.as_json() for t in found]})
    else:
        for t in found:
            print(f"{t.norad:>6}  {t.name:<28} epoch {iso(t.epoch)}  {t.source}")
        if not found:
            print(f"no satellite matches {args.search!r}")
    return 0


def do_passes(args, station, target, rot: Rotctld, clock) -> int:
    from . import passes as passmod

    limits = read_limits(args, rot, required=False)
    now = clock.now()
    found = passmod.find_passes(target, station, now, now + args.hours * 3600, limits.el_min, limits.el_max,
                                count=args.count)
    if args.json:
        cli.print_json({"target": target.name, "station": station.as_json(), **limits_json(limits),
                        "passes": [p.as_json() for p in found]})
        return 0
    print(f"{target.describe()} from {station.lat:.4f}, {station.lon:.4f}: passes through el "
          f"{limits.el_min:g}..{limits.el_max:g}" + (" (rotctld unreachable: default limits)"
                                                     if limits.source == "default" else ""))
    for p in found:
        j = p.as_json()
        clamp = f"  above the cap {j['above_max_s']:.0f} s" if p.above_max else ""
        print(f"  AOS {j['aos'] or '(before the search)'}  az {fmt(j['aos_az'])}   TCA {j['tca'] or '-'}  "
              f"max el {j['max_el']:.1f}   LOS {j['los'] or '(after the search)'}  az {fmt(j['los_az'])}"
              f"   {fmt(j['duration_s'], '.0f')} s{clamp}")
    if not found:
        print(f"  none within {args.hours:g} h")
    return 0


def fmt(x, spec=".1f") -> str:
    return "-" if x is None else format(x, spec)


def do_visible(args, station, rot: Rotctld, clock, loader) -> int:
    from . import targets as targetmod

    limits = read_limits(args, rot, required=False)
    now = clock.now()
    rows = []
    candidates = targetmod.solar_system()
    stale = 0
    sats = []
    try:
        sats = loader()
    except FileNotFoundError:
        if args.tle:
            raise
    for t in sats:
        if abs(now - t.epoch) > STALE_DAYS * 86400:
            stale += 1
            continue
        candidates.append(targetmod.Satellite(t))
    for target in candidates:
        az, el = target.look_one(station, now)
        if math.isnan(el) or el < limits.el_min:
            continue
        rows.append({"name": target.name, "kind": "satellite" if target.kind == "satellite" else target.kind,
                     "az": round(az, 2), "el": round(el, 2), "in_window": el <= limits.el_max})
    rows.sort(key=lambda r: -r["el"])
    if args.json:
        cli.print_json({"time": iso(now), "station": station.as_json(), **limits_json(limits),
                        "targets": rows, "stale_tles_skipped": stale})
        return 0
    print(f"{iso(now)}: above the dish's floor (el {limits.el_min:g}; cap {limits.el_max:g})")
    for r in rows:
        print(f"  {r['name']:<28} {r['kind']:<9} az {r['az']:6.1f}  el {r['el']:5.1f}"
              + ("" if r["in_window"] else "  (above the cap)"))
    if stale:
        print(f"  ({stale} satellites skipped: elements more than {STALE_DAYS:g} days from now; --fetch a group)")
    return 0


class Output:
    """Events as JSON lines, or as words."""

    def __init__(self, json_mode: bool):
        self.json_mode = json_mode
        self.last_progress = -math.inf

    def __call__(self, event: dict) -> None:
        if self.json_mode:
            cli.print_json(event)
            return
        kind = event["event"]
        if kind == "plan":
            if event["aos"] is None and event["los"] is None:
                print(f"{event['target']}: in the window now, no end in sight", flush=True)
            else:
                print(f"{event['target']}: AOS {event['aos'] or 'now'}, LOS {event['los'] or '-'}, "
                      f"max el {fmt(event['max_el'])}", flush=True)
        elif kind == "wait":
            print(f"{event['now']}  waiting at az {event['aim']['az']:.1f} el {event['aim']['el']:.1f}, "
                  f"AOS in {event['seconds_to_aos']:.0f} s", flush=True)
        elif kind == "progress":
            los = event["seconds_to_los"]
            print(f"{event['now']}  target az {event['target']['az']:7.2f} el {event['target']['el']:6.2f}   "
                  f"dish az {event['dish']['az']:7.2f} el {event['dish']['el']:6.2f}   error "
                  f"{event['error_deg']:.2f} deg" + ("" if los is None else f"   LOS in {los:.0f} s"), flush=True)
        elif kind == "end":
            rms = event["rms_error_deg"]
            print(f"{event['outcome']}: {event['reason']}" +
                  ("" if rms is None else f"; pointing error {rms:.3f} deg RMS, {event['max_error_deg']:.3f} max "
                                          f"over {event['samples']} readings") +
                  f"; {event['commands_sent']} targets sent", flush=True)


def main(argv: list[str], version: str = "", started: float | None = None) -> int:
    parser = build_parser(version)
    args = parser.parse_args(argv)
    actions = sum(bool(x) for x in (args.search is not None, args.passes, args.visible))
    try:
        if actions > 1:
            raise cli.UsageError("--search, --passes and --visible are alternatives")
        if args.threshold <= 0:
            raise cli.UsageError("--threshold must be positive")
        if (args.passes or not actions) and not args.target:
            raise cli.UsageError("TARGET is required (e.g. sun, or a satellite's name)")
        if args.visible and args.target:
            raise cli.UsageError("--visible takes no TARGET")
        station = None if args.search is not None else cli.station_from(args)
        clock = cli.clock_from(args, started)
    except cli.UsageError as error:
        parser.error(str(error))
    # The scientific stack only from here: --help and --version (help2man at build time) need none.
    from . import targets as targetmod

    loader = cli.tle_loader(args)
    rot = Rotctld(args.host, args.port)
    tracking = not actions
    try:
        if args.search is not None:
            return do_search(args, loader)
        if args.visible:
            return do_visible(args, station, rot, clock, loader)
        target = targetmod.resolve(args.target, loader)
        if args.passes:
            return do_passes(args, station, target, rot, clock)
        return track(args, station, target, rot, clock)
    except (LookupError, FileNotFoundError, ConnectionError, RotctldError, ValueError) as error:
        message = str(error).strip("'\"") if isinstance(error, LookupError) else str(error)
        print(f"birdcage-track: {message}", file=sys.stderr)
        if args.json:
            if tracking:
                cli.print_json({"event": "end", "outcome": "error", "reason": message, "rms_error_deg": None,
                                "max_error_deg": None, "samples": 0, "commands_sent": rot.sent_moves,
                                "parked": False})
            else:
                cli.print_json({"error": message})
        return 1
    finally:
        rot.close()


def track(args, station, target, rot: Rotctld, clock) -> int:
    from .tracker import Options, Tracker

    limits = read_limits(args, rot, required=True)
    out = Output(args.json)
    options = Options(threshold=args.threshold, park_at_los=args.park_at_los, duration=args.duration,
                      horizon_s=args.hours * 3600, fixed_response=args.response, progress_real_s=1.0 if args.json else 5.0)
    if args.log:
        options.log = open(args.log, "w")
        options.log.write("time,target_az,target_el,dish_az,dish_el,sent_az,sent_el,response_s,error_deg\n")
    tracker = Tracker(rot, clock, station, target, limits, out, options)

    def on_signal(signum, frame):
        tracker.stop_requested = True

    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)
    if target.kind == "satellite":
        age = abs(clock.now() - target.tle.epoch) / 86400
        if age > STALE_DAYS and not args.json:
            print(f"birdcage-track: warning: {target.name}'s elements are {age:.0f} days from now; "
                  f"positions are unreliable (--fetch a group)", file=sys.stderr)
    end = tracker.run()
    return 0 if end["outcome"] != "error" else 1
