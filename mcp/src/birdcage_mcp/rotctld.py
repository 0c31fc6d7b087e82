# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors

"""A client of rotctld's text protocol (Hamlib 4.5's NET rotator protocol) over TCP.

Every command is sent in the extended form (`+` prefix): rotctld then echoes the command's name,
prints one `Key: value` line per value, and always ends with `RPRT <code>`. That last line makes a
reply's end unambiguous whatever the command, which the plain form (values only, no end marker
on success) does not.

Only the commands listed in ALLOWED are ever sent. rotctld 4.5.4 parses an unknown long command
such as `\\get_conf` one character at a time, so an unlisted word could run single-letter
commands (`R` reset, `K` park) by accident.
"""

from __future__ import annotations

import asyncio
import os
import re
from dataclasses import dataclass

# Hamlib's error codes (rig.h `enum rig_errcode_e`), as rotctld prints them negated in RPRT.
HAMLIB_ERRORS = {
    1: "invalid parameter",
    2: "invalid configuration",
    3: "memory shortage",
    4: "function not implemented",
    5: "communication timed out",
    6: "I/O error",
    7: "internal Hamlib error",
    8: "protocol error",
    9: "command rejected by the rotator",
    10: "command performed, but argument truncated",
    11: "function not available",
    12: "target not available",
    13: "bus error",
    14: "bus collision",
    15: "NULL argument",
    16: "invalid VFO",
    17: "argument out of domain",
    18: "function deprecated",
    19: "security error",
    20: "rotator is not powered on",
}

# The commands this client sends, by their first word. Nothing here reaches the firmware except
# through the backend, whose session layer refuses the firmware's hazard commands.
ALLOWED = {"p", "P", "S", "K", "R", "s", "_", "v", "V", "1"}

SAFE_ARGUMENT = re.compile(r"^[A-Za-z0-9_.?+-]+$")


class RotctldError(Exception):
    """A failure a user can act on; str() is the text shown to them."""


class RotctldUnreachable(RotctldError):
    pass


class RotctldRefused(RotctldError):
    """rotctld answered `RPRT <negative>`."""

    def __init__(self, command: str, code: int):
        self.command = command
        self.code = code
        meaning = HAMLIB_ERRORS.get(-code, "unknown error")
        super().__init__(f"rotctld refused `{command}`: RPRT {code} ({meaning})")


@dataclass
class Reply:
    """One extended-form reply: the `Key: value` pairs in order, and lines without a key."""

    pairs: list[tuple[str, str]]
    lines: list[str]

    def value(self, key: str) -> str:
        for k, v in self.pairs:
            if k == key:
                return v
        raise RotctldError(f"rotctld's reply has no `{key}` (got: {'; '.join(self.lines) or 'nothing'})")


class Rotctld:
    """One TCP connection to rotctld, opened on first use and re-opened after a failure (rotctld
    may have been restarted). Commands are serialised: rotctld answers one at a time anyway."""

    def __init__(self, host: str = "localhost", port: int = 4533, timeout: float = 15.0):
        self.host = host
        self.port = port
        self.timeout = timeout
        self._reader: asyncio.StreamReader | None = None
        self._writer: asyncio.StreamWriter | None = None
        self._lock = asyncio.Lock()
        # Counts the connections made: a new one may find another rotator behind the same port.
        self.connections = 0

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    async def _connect(self) -> None:
        try:
            self._reader, self._writer = await asyncio.wait_for(
                asyncio.open_connection(self.host, self.port), self.timeout
            )
            self.connections += 1
        except (OSError, asyncio.TimeoutError) as error:
            code = getattr(error, "errno", None)
            reason = os.strerror(code).lower() if code else (str(error) or "no answer")
            raise RotctldUnreachable(
                f"cannot reach rotctld at {self.address} ({reason}); is rotctld running and listening there? "
                f"(e.g. `rotctld -m <model> -r <device> -t {self.port}`, with the birdcage backend preloaded "
                f"for a Winegard dish)"
            ) from None

    async def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
            try:
                await self._writer.wait_closed()
            except OSError:
                pass
        self._reader = self._writer = None

    async def ask(self, command: str, *args: object, timeout: float | None = None) -> Reply:
        """Sends `+command args` and returns the reply; raises RotctldRefused on `RPRT <0`."""
        if command not in ALLOWED:
            raise ValueError(f"command {command!r} is not one this client sends")
        words = [str(a) for a in args]
        for word in words:
            if not SAFE_ARGUMENT.match(word):
                raise RotctldError(f"argument {word!r} is not a plain word or number")
        line = " ".join(["+" + command, *words])
        async with self._lock:
            for attempt in (1, 2):
                if self._writer is None:
                    await self._connect()
                try:
                    return await asyncio.wait_for(self._exchange(line), timeout or self.timeout)
                except asyncio.TimeoutError:  # before OSError: TimeoutError is one
                    # The reply may still arrive later and would be taken for the next one's.
                    await self.close()
                    raise RotctldError(
                        f"rotctld at {self.address} did not answer `{line[1:]}` within "
                        f"{timeout or self.timeout:g} s"
                    ) from None
                except (OSError, asyncio.IncompleteReadError, ConnectionError):
                    # A connection rotctld closed (restarted) fails on first use: reconnect once.
                    await self.close()
                    if attempt == 2:
                        raise RotctldUnreachable(
                            f"rotctld at {self.address} closed the connection during `{line[1:]}`"
                        ) from None
        raise AssertionError("unreachable")

    async def _exchange(self, line: str) -> Reply:
        assert self._reader is not None and self._writer is not None
        self._writer.write((line + "\n").encode())
        await self._writer.drain()
        pairs: list[tuple[str, str]] = []
        lines: list[str] = []
        first = True
        while True:
            raw = await self._reader.readuntil(b"\n")
            text = raw.decode(errors="replace").rstrip("\r\n")
            if text.startswith("RPRT "):
                code = int(text[5:].strip() or 0)
                if code < 0:
                    raise RotctldRefused(line[1:], code)
                return Reply(pairs, lines)
            if first:
                first = False  # the echoed command name, e.g. `get_pos:`
                continue
            lines.append(text)
            key, sep, value = text.partition(":")
            if sep:
                pairs.append((key.strip(), value.strip()))

    # ---- typed helpers ----

    async def position(self) -> tuple[float, float]:
        reply = await self.ask("p")
        return float(reply.value("Azimuth")), float(reply.value("Elevation"))

    async def levels(self) -> list[str]:
        """The level names `v ?` lists (the backend's extension levels among them)."""
        reply = await self.ask("v", "?")
        return " ".join(reply.lines).split()
