#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Helpers of scripts/gpredict-loop.sh (real Gpredict against the emulated dish).

    gpredict_loop.py tle                                        the TLE of bench/passes/iss-45.csv
    gpredict_loop.py proxy --listen P --upstream P --log F --poll-log F
    gpredict_loop.py analyse --tle F --offset S --log F --poll-log F --from S --to S --threshold D
                             [--limits dish|wide --min-el D --max-el D]

`proxy` sits between Gpredict and rotctld: it forwards every byte unchanged and logs each line with
the wall-clock time it passed (">" Gpredict to rotctld, "<" the answer). A second connection of
its own asks rotctld `p` five times a second, so the dish's path is known between Gpredict's polls
(rotctld serves each client on its own thread; the backend answers `p` from its position model
without touching the serial line, README "What the backend does", so the extra client does not
change what the dish does).

`analyse` puts the satellite where SGP4 (python3-sgp4, the same propagation and site maths as
bench/generate_passes.py) says it is at Gpredict's clock, and compares it with the dish.

Debian's python3, python3-sgp4 and python3-numpy only.
"""
import argparse
import json
import math
import os
import select
import signal
import socket
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "bench"))

# 2024-06-01T00:00:00Z, the epoch of every synthetic element set of bench/generate_passes.py.
EPOCH_UNIX = 1717200000
PASS_NAME = "iss-45"
CATALOG_NUMBER = 99045  # not a real object: the elements are synthetic


# ---------------------------------------------------------------------------------------- tle
def tle_checksum(line):
    return sum(int(c) if c.isdigit() else (1 if c == "-" else 0) for c in line[:68]) % 10


def make_tle():
    """Two-line elements of the synthetic iss-45 pass, from the numbers its CSV header records."""
    import generate_passes as gp  # needs python3-sgp4 and python3-numpy

    header = open(os.path.join(ROOT, "bench", "passes", PASS_NAME + ".csv")).readline
    raan = None
    for _ in range(4):
        line = header()
        if "raan" in line:
            raan = float(line.split("raan")[1].split()[0])
    if raan is None:
        raise SystemExit("no raan in the pass header")
    alt, incl, ecc, argp = gp.ORBITS["iss"]
    revs_per_day = gp.mean_motion_rad_per_min(alt) * 1440.0 / (2.0 * math.pi)
    day_of_year = time.gmtime(EPOCH_UNIX).tm_yday
    line1 = (f"1 {CATALOG_NUMBER:05d}U 24999A   24{day_of_year:03d}.00000000  .00000000  00000-0  "
             f"00000-0 0  999")
    line2 = (f"2 {CATALOG_NUMBER:05d} {incl:8.4f} {raan:8.4f} {round(ecc * 1e7):07d} {argp:8.4f} "
             f"{0.0:8.4f} {revs_per_day:11.8f}    1")
    assert len(line1) == 68 and len(line2) == 68, (len(line1), len(line2))
    return (f"BIRDCAGE {PASS_NAME.upper()}", line1 + str(tle_checksum(line1)),
            line2 + str(tle_checksum(line2)))


def cmd_tle(_args):
    print("\n".join(make_tle()))


# -------------------------------------------------------------------------------------- proxy
class Log:
    def __init__(self, path):
        self.out = open(path, "w", buffering=1)
        self.lock = threading.Lock()

    def write(self, text):
        with self.lock:
            self.out.write(f"{time.time():.3f} {text}\n")


def relay(src, dst, log, mark):
    pending = b""
    while True:
        try:
            data = src.recv(4096)
        except OSError:
            data = b""
        if not data:
            try:
                dst.shutdown(socket.SHUT_WR)
            except OSError:
                pass
            return
        dst.sendall(data)
        pending += data
        while b"\n" in pending:
            line, pending = pending.split(b"\n", 1)
            log.write(f"{mark} {line.decode(errors='replace')}")


def serve_client(client, upstream_port, log):
    upstream = socket.create_connection(("127.0.0.1", upstream_port))
    log.write("# client connected")
    threads = [threading.Thread(target=relay, args=(client, upstream, log, ">"), daemon=True),
               threading.Thread(target=relay, args=(upstream, client, log, "<"), daemon=True)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    log.write("# client disconnected")
    client.close()
    upstream.close()


def poll_position(upstream_port, poll_log, period_s):
    while True:
        try:
            sock = socket.create_connection(("127.0.0.1", upstream_port))
            reader = sock.makefile("rb")
            while True:
                sock.sendall(b"p\n")
                first = reader.readline().decode().strip()
                if first.startswith("RPRT"):
                    poll_log.write(f"error {first}")
                else:
                    second = reader.readline().decode().strip()
                    poll_log.write(f"{first} {second}")
                time.sleep(period_s)
        except (OSError, ValueError) as e:
            poll_log.write(f"# poll: {e}")
            time.sleep(0.5)


def cmd_proxy(args):
    signal.signal(signal.SIGTERM, lambda *_: os._exit(0))
    log = Log(args.log)
    poll_log = Log(args.poll_log)
    threading.Thread(target=poll_position, args=(args.upstream, poll_log, args.poll_period),
                     daemon=True).start()
    server = socket.socket()
    server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    server.bind(("127.0.0.1", args.listen))
    server.listen(4)
    while True:
        ready, _, _ = select.select([server], [], [], 1.0)
        if ready:
            client, _ = server.accept()
            threading.Thread(target=serve_client, args=(client, args.upstream, log),
                             daemon=True).start()


# ------------------------------------------------------------------------------------ analyse
def sky_separation_deg(az1, el1, az2, el2):
    """Angle on the sky between two pointings: what a dish's beam notices, unlike the azimuth
    difference, which grows as 1/cos(el) and jumps at north."""
    a1, e1, a2, e2 = map(math.radians, (az1, el1, az2, el2))
    c = math.sin(e1) * math.sin(e2) + math.cos(e1) * math.cos(e2) * math.cos(a1 - a2)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def read_proxy_log(path):
    commands = []  # (wall time, az, el) of each P Gpredict sent
    for line in open(path):
        parts = line.split()
        if len(parts) >= 5 and parts[1] == ">" and parts[2] == "P":
            commands.append((float(parts[0]), float(parts[3]), float(parts[4])))
    return commands


def read_poll_log(path):
    samples = []
    for line in open(path):
        parts = line.split()
        if len(parts) == 3 and parts[1] != "error" and not parts[1].startswith("#"):
            try:
                samples.append((float(parts[0]), float(parts[1]), float(parts[2])))
            except ValueError:
                pass
    return samples


def motor_starts(path, keep):
    """How often the emulated dish started moving (the truth file's `moving` column going 0 -> 1),
    over the rows whose wall time `keep` accepts."""
    import csv
    from datetime import datetime

    moving = []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            wall = datetime.fromisoformat(row["utc"].replace("Z", "+00:00")).timestamp()
            if keep(wall):
                moving.append(row["moving"] == "1")
    return sum(1 for before, now in zip(moving, moving[1:]) if now and not before)


def cmd_analyse(args):
    from sgp4.api import WGS72, Satrec
    import generate_passes as gp

    lines = [l.strip() for l in open(args.tle) if l.strip()]
    sat = Satrec.twoline2rv(lines[-2], lines[-1], WGS72)

    def since_epoch(wall):
        return wall + args.offset - EPOCH_UNIX

    def in_window(wall):
        return args.t_from <= since_epoch(wall) <= args.t_to

    samples = [s for s in read_poll_log(args.poll_log) if in_window(s[0])]
    commands = read_proxy_log(args.log)
    in_pass = [c for c in commands if in_window(c[0])]
    if not samples:
        raise SystemExit("analyse: no dish positions inside the window")
    sat_az, sat_el = gp.az_el(sat, [since_epoch(s[0]) for s in samples])
    errors = [sky_separation_deg(s[1], s[2], a, e) for s, a, e in zip(samples, sat_az, sat_el)]
    # How far ahead of the satellite Gpredict aims: its lead, up to one threshold.
    leads = []
    if in_pass:
        cmd_az, cmd_el = gp.az_el(sat, [since_epoch(c[0]) for c in in_pass])
        leads = [sky_separation_deg(c[1], c[2], a, e) for c, a, e in zip(in_pass, cmd_az, cmd_el)]
    # Azimuth travel, dish against satellite: a cable unwind inside the window shows as 360 deg more.
    def az_travel(azimuths):
        return sum(abs((b - a + 180.0) % 360.0 - 180.0) for a, b in zip(azimuths, azimuths[1:]))
    rms = math.sqrt(sum(e * e for e in errors) / len(errors))
    ordered = sorted(errors)
    result = {
        "threshold_deg": args.threshold,
        "limits": args.limits,
        "limits_el_deg": [args.min_el, args.max_el],
        "window_s": [args.t_from, args.t_to],
        "window_sat_el_deg": [round(float(min(sat_el)), 1), round(float(max(sat_el)), 1)],
        "samples": len(errors),
        "p_commands": len(in_pass),
        "p_commands_total": len(commands),
        "rms_deg": round(rms, 3),
        "max_deg": round(ordered[-1], 3),
        "p95_deg": round(ordered[int(0.95 * (len(ordered) - 1))], 3),
        "dish_az_travel_deg": round(az_travel([s[1] for s in samples]), 1),
        "sat_az_travel_deg": round(az_travel([float(a) for a in sat_az]), 1),
        "mean_lead_deg": round(sum(leads) / len(leads), 3) if leads else None,
    }
    if args.truth:
        result["motor_starts"] = motor_starts(args.truth, in_window)
        result["motor_starts_total"] = motor_starts(args.truth, lambda wall: True)
    if args.out:
        with open(args.out, "w") as out:
            json.dump(result, out, indent=1)
    limits = f"{args.limits} {args.min_el:g}–{args.max_el:g}°"
    print(f"{args.threshold:>8g}° {limits:<12} {result['p_commands']:>8d} {result['rms_deg']:>7.2f}° "
          f"{result['max_deg']:>7.2f}° {result['p95_deg']:>7.2f}° {result['mean_lead_deg'] or 0:>9.2f}° "
          f"{result['window_sat_el_deg'][0]:>5.1f}–{result['window_sat_el_deg'][1]:.1f}° "
          f"{result['dish_az_travel_deg']:>7.1f}° / {result['sat_az_travel_deg']:.1f}°"
          + (f" {result['motor_starts']:>6d}" if "motor_starts" in result else ""))
    problems = []
    # Counted over the whole run: Gpredict engaged and kept sending. In the window itself a dish
    # that stays on the satellite gives Gpredict little to send (2-3 P at 5 deg with the orbit
    # model), which is the point.
    if args.min_p is not None and result["p_commands_total"] < args.min_p:
        problems.append(f"only {result['p_commands_total']} P commands in the run (expected >= {args.min_p})")
    if args.max_error is not None and result["max_deg"] > args.max_error:
        problems.append(f"max error {result['max_deg']} deg > {args.max_error}")
    if args.series:
        with open(args.series, "w") as out:
            out.write("t,dish_az,dish_el,sat_az,sat_el,error_deg\n")
            for s, a, e, err in zip(samples, sat_az, sat_el, errors):
                out.write(f"{since_epoch(s[0]):.2f},{s[1]:.2f},{s[2]:.2f},{a:.3f},{e:.3f},{err:.3f}\n")
    if problems:
        print(f"analyse: threshold {args.threshold} deg, {args.limits} limits: " + "; ".join(problems),
              file=sys.stderr)
        sys.exit(1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("tle")
    p = sub.add_parser("proxy")
    p.add_argument("--listen", type=int, required=True)
    p.add_argument("--upstream", type=int, required=True)
    p.add_argument("--log", required=True)
    p.add_argument("--poll-log", required=True)
    p.add_argument("--poll-period", type=float, default=0.2)
    a = sub.add_parser("analyse")
    a.add_argument("--tle", required=True)
    a.add_argument("--offset", type=float, required=True, help="Gpredict's clock minus the wall clock, s")
    a.add_argument("--log", required=True)
    a.add_argument("--poll-log", required=True)
    a.add_argument("--from", dest="t_from", type=float, required=True, help="s after the TLE epoch")
    a.add_argument("--to", dest="t_to", type=float, required=True)
    a.add_argument("--threshold", type=float, required=True)
    a.add_argument("--limits", default="dish", help="the name of the rotator limits Gpredict was given")
    a.add_argument("--min-el", type=float, default=18.0, help="Gpredict's MinEl (deg)")
    a.add_argument("--max-el", type=float, default=65.0, help="Gpredict's MaxEl (deg)")
    a.add_argument("--out")
    a.add_argument("--series")
    a.add_argument("--truth", help="the emulator's truth file: count the dish's motor starts")
    a.add_argument("--min-p", type=int, help="fail with fewer P commands in the whole run")
    a.add_argument("--max-error", type=float, help="fail when the dish is ever further off (deg)")
    args = parser.parse_args()
    {"tle": cmd_tle, "proxy": cmd_proxy, "analyse": cmd_analyse}[args.command](args)


if __name__ == "__main__":
    main()
