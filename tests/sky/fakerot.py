# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""A stand-in for rotctld and a dish with a receiver, for testing the sky tools quickly and
without the emulator: rotctld's text protocol (the commands the tools send), a dish whose axes
sit against the sky by a known mount (docs/sky.md section 1, written here again, independently of
tools/sky), axes that move at a set speed after a set delay, and a sky of Gaussian beams on a
floor for `v RSSI`. Its clock runs time_scale times faster than real time from `epoch`, anchored
at the wall-clock moment `anchor` (pass the same to the tools' --at/--at-wall)."""

from __future__ import annotations

import math
import random
import socket
import threading
import time



def mount_dish_to_sky(terms, az_d, el_d):
    """docs/sky.md section 1, dish axes -> sky."""
    az_index, el_index, tilt_north, tilt_east = (math.radians(t) for t in terms)
    a = math.radians(az_d) + az_index
    e = math.radians(el_d) + el_index
    x, y, z = math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e)
    # R_N(tilt_east): up turns toward east.
    x, z = x * math.cos(tilt_east) + z * math.sin(tilt_east), -x * math.sin(tilt_east) + z * math.cos(tilt_east)
    # R_E(tilt_north): up turns toward north.
    y, z = y * math.cos(tilt_north) + z * math.sin(tilt_north), -y * math.sin(tilt_north) + z * math.cos(tilt_north)
    return math.degrees(math.atan2(x, y)) % 360.0, math.degrees(math.asin(max(-1.0, min(1.0, z))))


def separation_deg(az1, el1, az2, el2):
    a1, e1, a2, e2 = map(math.radians, (az1, el1, az2, el2))
    c = math.sin(e1) * math.sin(e2) + math.cos(e1) * math.cos(e2) * math.cos(a1 - a2)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


class FakeRotctld:
    def __init__(self, *, mount=(0.0, 0.0, 0.0, 0.0), sources=(), floor=400.0, sigma=2.9, noise=0.0,
                 el_limits=(18.0, 65.0), speed=30.0, delay=0.1, epoch=0.0, time_scale=1.0, start=(180.0, 40.0),
                 sun=None, pointing="none", seed=1):
        self.mount = mount
        self.sources = list(sources)  # (sky az, sky el, amplitude)
        self.floor, self.sigma, self.noise = floor, sigma, noise
        self.el_limits = el_limits
        self.speed, self.delay = speed, delay
        self.epoch, self.time_scale = epoch, time_scale
        self.sun = sun  # a function sky time -> (az, el), and its amplitude: (fn, amplitude)
        self.pointing = pointing
        self.rng = random.Random(seed)
        self.lock = threading.Lock()
        self.pos = list(start)
        self.target = list(start)
        self.leg_start = None
        self.leg_from = list(start)
        self.commands: list[str] = []
        self.moves: list[tuple[float, float, float]] = []
        self.anchor = time.time()
        self._mono0 = time.monotonic()
        self.sock = socket.socket()
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        self.sock.bind(("127.0.0.1", 0))
        self.sock.listen(4)
        self.port = self.sock.getsockname()[1]
        self.closed = False
        threading.Thread(target=self.serve, daemon=True).start()

    # ---- the clock and the dish ----

    def now(self) -> float:
        return self.epoch + (time.monotonic() - self._mono0) * self.time_scale

    def position(self) -> tuple[float, float]:
        t = self.now()
        if self.leg_start is None:
            return tuple(self.pos)
        moved = max(0.0, t - self.leg_start - self.delay) * self.speed
        out = []
        for i in range(2):
            d = self.target[i] - self.leg_from[i]
            if i == 0:
                d = ((d + 180.0) % 360.0) - 180.0
            step = max(-moved, min(moved, d))
            out.append((self.leg_from[i] + step) % 360.0 if i == 0 else self.leg_from[i] + step)
        return out[0], out[1]

    def move(self, az: float, el: float) -> None:
        self.pos = list(self.position())
        self.leg_from = list(self.pos)
        self.target = [az % 360.0, min(max(el, self.el_limits[0]), self.el_limits[1])]
        self.leg_start = self.now()
        self.moves.append((self.now(), az, el))

    def rssi(self) -> float:
        az, el = self.position()
        saz, sel = mount_dish_to_sky(self.mount, az, el)
        value = self.floor
        for a, e, amp in self.sources:
            value += amp * math.exp(-0.5 * (separation_deg(saz, sel, a, e) / self.sigma) ** 2)
        if self.sun is not None:
            fn, amp = self.sun
            a, e = fn(self.now())
            value += amp * math.exp(-0.5 * (separation_deg(saz, sel, a, e) / self.sigma) ** 2)
        return value + self.rng.gauss(0.0, self.noise)

    # ---- the protocol ----

    def serve(self) -> None:
        while not self.closed:
            try:
                conn, _ = self.sock.accept()
            except OSError:
                return
            threading.Thread(target=self.client, args=(conn,), daemon=True).start()

    def client(self, conn: socket.socket) -> None:
        f = conn.makefile("rw")
        try:
            for line in f:
                line = line.strip()
                if not line:
                    continue
                with self.lock:
                    self.commands.append(line)
                    reply = self.answer(line)
                f.write(reply)
                f.flush()
        except (OSError, ValueError):
            pass
        finally:
            conn.close()

    def answer(self, line: str) -> str:
        if line == "\\dump_state":
            return ("1\n90105\nmin_az=-180.000000\nmax_az=540.000000\nmin_el=0.000000\nmax_el=90.000000\n"
                    "south_zero=0\nrot_type=AzEl\ndone\n")
        extended = line.startswith("+")
        words = line.lstrip("+").split()
        cmd, args = words[0], words[1:]
        if cmd == "p":
            az, el = self.position()
            return f"get_pos:\nAzimuth: {az:.2f}\nElevation: {el:.2f}\nRPRT 0\n"
        if cmd == "P":
            self.move(float(args[0]), float(args[1]))
            return "set_pos: {} {}\nRPRT 0\n".format(*args)
        if cmd == "S":
            self.pos = list(self.position())
            self.target = list(self.pos)
            self.leg_start = None
            return "stop:\nRPRT 0\n"
        if cmd == "K":
            self.move(0.0, 45.0)
            return "park:\nRPRT 0\n"
        if cmd == "_":
            az, el = self.position()
            return (f"get_info:\nInfo: Fake dish: idle; position az {az:.2f} el {el:.2f}; el limits "
                    f"{self.el_limits[0]:.2f}..{self.el_limits[1]:.2f}; pointing {self.pointing}\nRPRT 0\n")
        if cmd == "s":
            return "get_status:\nStatus flags: \nRPRT 0\n"
        if cmd == "v" and args == ["?"]:
            return "get_level: ?\nRSSI RSSI_SAMPLES LNB \nRPRT 0\n"
        if cmd == "v" and args == ["RSSI"]:
            return f"get_level: RSSI\n{self.rssi():.6f}\nRPRT 0\n"
        if cmd == "V":
            return "set_level: {}\nRPRT 0\n".format(" ".join(args))
        return "RPRT -1\n" if extended else "RPRT -1\n"

    def stopped(self) -> bool:
        return any(c.lstrip("+") == "S" for c in self.commands)

    def close(self) -> None:
        self.closed = True
        self.sock.close()
