#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""birdcage-sim --truth through the command line, as a test outside the process reads it.

The emulated G2 (--mount, --epoch, --time-scale 20) is moved over its pty; the truth file must be
readable while it runs (a row showing the motion appears before the emulator stops), every row's
utc must be --epoch + t and its sky columns docs/sky.md section 1's dish -> sky of its dish
columns, and at SIGTERM the last rows must be flushed: the dish at rest on its target.

Usage: truth_file.py BIRDCAGE_SIM
"""
import math
import os
import select
import signal
import subprocess
import sys
import tempfile
import time
import tty
from datetime import datetime

EPOCH = "2026-06-21T18:00:00Z"
MOUNT = {"az_index": 6.0, "el_index": -1.0, "tilt_north": 1.0, "tilt_east": -0.5}
HEADER = "utc,t,dish_az,dish_el,sky_az,sky_el,moving"
DEADLINE_S = 30.0  # a hung emulator fails the test instead of hanging it


def dish_to_sky(az, el, mount):
    """docs/sky.md section 1, written from the text."""
    a, e = math.radians(az + mount["az_index"]), math.radians(el + mount["el_index"])
    x, y, z = math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)
    t = math.radians(mount["tilt_east"])  # R_N
    x, y, z = x * math.cos(t) + z * math.sin(t), y, -x * math.sin(t) + z * math.cos(t)
    t = math.radians(mount["tilt_north"])  # R_E
    x, y, z = x, y * math.cos(t) + z * math.sin(t), -y * math.sin(t) + z * math.cos(t)
    return math.degrees(math.atan2(x, y)) % 360.0, math.degrees(math.asin(z))


def rows_of(path):
    with open(path) as f:
        lines = f.read().split("\n")
    return lines[0] if lines else "", [line.split(",") for line in lines[1:] if line.count(",") == 6]


def wait_until(condition, what):
    end = time.monotonic() + DEADLINE_S
    while not condition():
        if time.monotonic() > end:
            raise SystemExit(f"FAIL: timed out waiting for {what}")
        time.sleep(0.01)


def main():
    sim = sys.argv[1:]  # the emulator's command: its path, after qemu's words in a cross build
    fd, path = tempfile.mkstemp(prefix="birdcage-truth-", suffix=".csv")
    os.close(fd)
    mount = ",".join(f"{k}={v}" for k, v in MOUNT.items())
    emulator = subprocess.Popen([*sim, "--variant", "g2", "--time-scale", "20", "--epoch", EPOCH, "--mount", mount,
                                 "--truth", path], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    failures = []
    try:
        device = emulator.stdout.readline().strip().removeprefix("device: ")
        pty = os.open(device, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(pty)
        os.write(pty, b"mot\ra 0 200\r")
        wait_until(lambda: any(row[6] == "1" for row in rows_of(path)[1]), "a row with the dish moving, mid-run")
        # Drain what the dish says so it never blocks on a full pty.
        while select.select([pty], [], [], 0.1)[0]:
            os.read(pty, 4096)
        wait_until(lambda: rows_of(path)[1] and rows_of(path)[1][-1][6] == "0" and
                   abs(float(rows_of(path)[1][-1][2]) - 200.0) < 0.02, "the dish at rest on 200")
        os.close(pty)
    finally:
        emulator.send_signal(signal.SIGTERM)
        _, stderr = emulator.communicate(timeout=DEADLINE_S)
    if emulator.returncode != 0:
        failures.append(f"exit status {emulator.returncode}: {stderr}")
    if "hazards received: 0" not in stderr:
        failures.append(f"hazards: {stderr}")

    header, rows = rows_of(path)
    os.unlink(path)
    if header != HEADER:
        failures.append(f"header {header!r}")
    epoch = datetime.fromisoformat(EPOCH.replace("Z", "+00:00"))
    last_t, worst = -1.0, 0.0
    for row in rows:
        t = float(row[1])
        if t < last_t:  # printed to the millisecond: a motion's start may share its row's t
            failures.append(f"t going back at {row}")
        last_t = t
        # Both columns are rounded to the millisecond.
        utc = datetime.fromisoformat(row[0].replace("Z", "+00:00"))
        if not row[0].endswith("Z") or len(row[0]) != 24 or abs((utc - epoch).total_seconds() - t) > 0.0011:
            failures.append(f"utc {row[0]} is not {EPOCH} + {t} s")
        az, el = dish_to_sky(float(row[2]), float(row[3]), MOUNT)
        worst = max(worst, abs((float(row[4]) - az + 180.0) % 360.0 - 180.0), abs(float(row[5]) - el))
    if worst > 2e-4:
        failures.append(f"sky columns off dish -> sky by {worst:.6f} deg")
    if len(rows) < 10 or rows[-1][6] != "0" or abs(float(rows[-1][2]) - 200.0) > 0.02:
        failures.append(f"last row after SIGTERM: {rows[-1] if rows else None}")
    starts = sum(1 for a, b in zip(rows, rows[1:]) if a[6] == "0" and b[6] == "1")
    stops = sum(1 for a, b in zip(rows, rows[1:]) if a[6] == "1" and b[6] == "0")
    print(f"{len(rows)} rows over {last_t:.2f} emulated s; motion starts {starts}, stops {stops}; "
          f"sky columns vs docs/sky.md: max deviation {worst:.6f} deg")
    if (starts, stops) != (1, 1):
        failures.append(f"{starts} motion starts and {stops} stops, expected one each")
    for failure in failures:
        print("FAIL:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
