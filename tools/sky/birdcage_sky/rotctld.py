# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""A small client of rotctld's text protocol over TCP (Hamlib 4.5 and 4.6).

Single-letter commands go in the extended form (`+p`): rotctld echoes the command's name, prints
`Key: value` lines and always ends with `RPRT n`, so a reply's end is never guessed.
`\\dump_state` goes in the plain form and ends at its `done` line (the C client's rule,
src/client/rotctl_protocol.cpp). Only the words in ALLOWED are ever sent: rotctld 4.5.4 reads an
unknown long command one letter at a time, so a stray word could run `R` (reset) or `K` (park).
`v RSSI` is the birdcage backend's extension level (docs/receiver.md); `rotctl -m 2` cannot ask
for it, which is why this client speaks the protocol itself.
"""

from __future__ import annotations

import re
import socket
from dataclasses import dataclass

ALLOWED = {"p", "P", "S", "K", "_", "s", "v", "V", "\\dump_state"}

HAMLIB_ERRORS = {1: "invalid parameter", 2: "invalid configuration", 4: "not implemented", 5: "timed out",
                 6: "I/O error", 7: "internal error", 8: "protocol error", 9: "rejected by the rotator",
                 11: "not available", 17: "argument out of domain", 20: "rotator not powered on"}


class RotctldError(Exception):
    pass


class Unreachable(RotctldError):
    pass


class Refused(RotctldError):
    def __init__(self, command: str, code: int):
        self.code = code
        super().__init__(f"rotctld refused `{command}`: RPRT {code} ({HAMLIB_ERRORS.get(-code, 'error')})")


@dataclass
class Limits:
    az_min: float = 0.0
    az_max: float = 360.0
    el_min: float = 0.0
    el_max: float = 90.0
    source: str = "default"

    def as_json(self) -> dict:
        return {"az_min": self.az_min, "az_max": self.az_max, "el_min": self.el_min, "el_max": self.el_max}

    def clamp_el(self, el: float) -> float:
        return min(max(el, self.el_min), self.el_max)


_NUMBER = r"[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"


def parse_dump_state(lines: list[str]) -> Limits | None:
    """Hamlib 4's `min_az=...` lines (plain form, 4.5.4 and 4.6.2) or the extended form's
    `Minimum Azimuth: ...`; Hamlib 3's bare values (version, model, then the four limits)."""
    keys = {"min_az": "az_min", "max_az": "az_max", "min_el": "el_min", "max_el": "el_max",
            "minimum azimuth": "az_min", "maximum azimuth": "az_max", "minimum elevation": "el_min",
            "maximum elevation": "el_max"}
    found: dict[str, float] = {}
    for line in lines:
        m = re.match(r"^\s*([A-Za-z_ ]+?)\s*[=:]\s*(" + _NUMBER + r")\s*$", line)
        if m and m.group(1).lower() in keys:
            found[keys[m.group(1).lower()]] = float(m.group(2))
    if len(found) == 4:
        return Limits(**found, source="dump_state")
    if not found and len(lines) >= 6:
        try:
            values = [float(x) for x in lines[2:6]]
        except ValueError:
            return None
        return Limits(*values, source="dump_state")
    return None


def el_limits_from_info(info: str) -> tuple[float, float] | None:
    """The birdcage backend's `_` names the dish's own elevation range: "; el limits 18.00..65.00"."""
    m = re.search(r"el limits (" + _NUMBER + r")\.\.(" + _NUMBER + r")", info)
    return (float(m.group(1)), float(m.group(2))) if m else None


def mount_from_info(info: str) -> tuple[float, float, float, float] | None:
    """The mount terms the birdcage backend applies, as its `_` names them ("; mount az_index 6.00
    el_index 0.80 tilt_north 1.20 tilt_east -0.50"); None when it names none (all zero)."""
    m = re.search(r"mount az_index (" + _NUMBER + r") el_index (" + _NUMBER + r") tilt_north (" + _NUMBER +
                  r") tilt_east (" + _NUMBER + r")", info)
    return tuple(float(m.group(i)) for i in range(1, 5)) if m else None


class Rotctld:
    """One TCP connection to rotctld, opened on first use."""

    def __init__(self, host: str = "localhost", port: int = 4533, timeout: float = 15.0):
        self.host, self.port, self.timeout = host, port, timeout
        self._sock: socket.socket | None = None
        self._buffer = b""
        self.sent_moves = 0

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    def connect(self) -> None:
        if self._sock is not None:
            return
        try:
            self._sock = socket.create_connection((self.host, self.port), timeout=self.timeout)
            self._sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        except OSError as error:
            reason = error.strerror or str(error) or "no answer"
            raise Unreachable(f"cannot reach rotctld at {self.address} ({reason.lower()}); is rotctld running "
                              f"there (birdcage-rotctld -m <model> -r <device> -t {self.port})?") from None
        self._buffer = b""

    def close(self) -> None:
        if self._sock is not None:
            try:
                self._sock.close()
            finally:
                self._sock = None

    def _readline(self) -> str:
        while b"\n" not in self._buffer:
            try:
                chunk = self._sock.recv(4096)
            except socket.timeout:
                self.close()
                raise RotctldError(f"rotctld at {self.address} did not answer within {self.timeout:g} s") from None
            except OSError as error:
                self.close()
                raise Unreachable(f"rotctld at {self.address}: {error.strerror or error}") from None
            if not chunk:
                self.close()
                raise Unreachable(f"rotctld at {self.address} closed the connection")
            self._buffer += chunk
        line, _, self._buffer = self._buffer.partition(b"\n")
        return line.decode(errors="replace").rstrip("\r")

    def _send(self, text: str) -> None:
        self.connect()
        try:
            self._sock.sendall((text + "\n").encode())
        except OSError as error:
            self.close()
            raise Unreachable(f"rotctld at {self.address}: {error.strerror or error}") from None

    def ask(self, command: str, *args) -> list[str]:
        """`+command args`: the reply's lines between the echoed name and RPRT."""
        if command not in ALLOWED or command.startswith("\\"):
            raise ValueError(f"{command!r} is not a command this client sends")
        words = [f"{a:.2f}" if isinstance(a, float) else str(a) for a in args]
        for w in words:
            if not re.match(r"^[A-Za-z0-9_.?+-]+$", w):
                raise ValueError(f"argument {w!r} is not a plain word or number")
        line = " ".join(["+" + command, *words])
        self._send(line)
        lines = []
        first = True
        while True:
            text = self._readline()
            if text.startswith("RPRT"):
                code = int(text[4:].strip() or 0)
                if code < 0:
                    raise Refused(line[1:], code)
                return lines
            if first:
                first = False
                if text.endswith(":"):
                    continue  # the echoed command name, e.g. `get_pos:`
            lines.append(text)

    @staticmethod
    def _values(lines: list[str]) -> list[str]:
        return [ln.split(":", 1)[1].strip() if ":" in ln else ln.strip() for ln in lines]

    def position(self) -> tuple[float, float]:
        values = self._values(self.ask("p"))
        try:
            return float(values[0]), float(values[1])
        except (IndexError, ValueError):
            raise RotctldError(f"rotctld's `p` answered {values!r}") from None

    def move(self, az: float, el: float) -> None:
        self.ask("P", round(az % 360.0, 2), round(el, 2))
        self.sent_moves += 1

    def stop(self) -> None:
        self.ask("S")

    def park(self) -> None:
        self.ask("K")

    def info(self) -> str:
        return " ".join(self._values(self.ask("_")))

    def status(self) -> str:
        return " ".join(self._values(self.ask("s")))

    def level(self, name: str) -> float:
        values = [v for v in self._values(self.ask("v", name)) if v and v != name]
        try:
            return float(values[-1])
        except (IndexError, ValueError):
            raise RotctldError(f"rotctld's `v {name}` answered {values!r}") from None

    def set_level(self, name: str, value) -> None:
        self.ask("V", name, value)

    def dump_state(self) -> list[str]:
        self._send("\\dump_state")
        lines = []
        while True:
            text = self._readline()
            if text.strip() == "done":
                return lines
            if text.startswith("RPRT"):
                code = int(text[4:].strip() or 0)
                if code < 0:
                    raise Refused("\\dump_state", code)
                return lines
            lines.append(text)

    def limits(self) -> Limits:
        """The window targets must lie in: `\\dump_state`'s, with the elevation narrowed to the
        dish's own range where the birdcage backend's `_` names it (a backend advertises 0..90 to
        Hamlib so that it can hold a cap itself, docs/tracking.md section 2.2)."""
        limits = parse_dump_state(self.dump_state())
        if limits is None:
            raise RotctldError(f"rotctld at {self.address}: cannot read the limits from `\\dump_state`")
        try:
            el = el_limits_from_info(self.info())
        except Refused:
            el = None
        if el:
            limits.el_min, limits.el_max = el
            limits.source = "dump_state, elevation from the backend's info (_)"
        return limits
