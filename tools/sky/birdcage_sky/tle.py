# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Two-line element sets: CelesTrak-style files (name line + two lines, or bare pairs), Gpredict's
per-satellite satdata/*.sat and Debian gpredict's satellites.dat (the same keys, one section per
satellite), found by the default search or named with --tle; CelesTrak groups only with --fetch."""

from __future__ import annotations

import os
import re
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

from sgp4.api import WGS72, Satrec

from .clock import iso

CELESTRAK_GROUP_URL = "https://celestrak.org/NORAD/elements/gp.php?GROUP={group}&FORMAT=tle"
_GROUP = re.compile(r"^[A-Za-z0-9_-]+$")


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "birdcage" / "tle"


def default_sources() -> list[Path]:
    """Where a satellite is looked for when no --tle is given: Gpredict's own satellites, the
    cached --fetch groups, then Debian gpredict's bundled (old) satellites.dat."""
    home = Path(os.path.expanduser("~"))
    sources = sorted((home / ".config" / "Gpredict" / "satdata").glob("*.sat"))
    if cache_dir().is_dir():
        sources += sorted(cache_dir().glob("*.txt"))
    bundled = Path("/usr/share/gpredict/data/satdata/satellites.dat")
    if bundled.is_file():
        sources.append(bundled)
    return sources


@dataclass
class Tle:
    name: str
    line1: str
    line2: str
    source: str
    satrec: Satrec = field(repr=False, default=None)

    def __post_init__(self):
        if self.satrec is None:
            self.satrec = Satrec.twoline2rv(self.line1, self.line2, WGS72)

    @property
    def norad(self) -> int:
        return int(self.satrec.satnum)

    @property
    def epoch(self) -> float:
        """The elements' epoch (UTC seconds since 1970)."""
        return (self.satrec.jdsatepoch - 2440587.5) * 86400.0 + self.satrec.jdsatepochF * 86400.0

    def as_json(self) -> dict:
        return {"name": self.name, "norad": self.norad, "epoch": iso(self.epoch), "source": self.source}


def _checked(line: str) -> bool:
    return len(line) >= 69 and line[0] in "12" and line[1] == " "


def parse_text(text: str, source: str) -> list[Tle]:
    """A CelesTrak-style file, or Gpredict's key=value format (.sat, satellites.dat)."""
    if re.search(r"^\s*TLE1\s*=", text, re.M):
        return _parse_gpredict(text, source)
    lines = [ln.rstrip() for ln in text.splitlines()]
    out: list[Tle] = []
    i = 0
    while i < len(lines):
        if i + 1 < len(lines) and _checked(lines[i]) and lines[i].startswith("1 ") and lines[i + 1].startswith("2 "):
            name = lines[i - 1].strip() if i > 0 and lines[i - 1].strip() and not _checked(lines[i - 1]) else ""
            if name.startswith("0 "):
                name = name[2:]  # the 3LE "0 NAME" form
            out.append(_make(name, lines[i], lines[i + 1], source))
            i += 2
        else:
            i += 1
    return [t for t in out if t is not None]


def _parse_gpredict(text: str, source: str) -> list[Tle]:
    out: list[Tle] = []
    record: dict[str, str] = {}

    def flush():
        if "TLE1" in record and "TLE2" in record:
            tle = _make(record.get("NAME") or record.get("NICKNAME") or "", record["TLE1"], record["TLE2"], source)
            if tle is not None:
                out.append(tle)
        record.clear()

    for line in text.splitlines():
        line = line.strip()
        if line.startswith("["):
            flush()
        elif "=" in line:
            key, _, value = line.partition("=")
            record[key.strip().upper()] = value.strip()
    flush()
    return out


def _make(name: str, line1: str, line2: str, source: str) -> Tle | None:
    try:
        tle = Tle(name, line1, line2, source)
    except (ValueError, IndexError):
        return None
    if not tle.name:
        tle.name = str(tle.norad)
    return tle


def load(paths: list[Path]) -> list[Tle]:
    """Every element set in the files (a directory: its *.sat, *.tle, *.txt and *.dat files). A
    satellite found in several keeps its newest elements."""
    files: list[Path] = []
    for p in paths:
        p = Path(p)
        if p.is_dir():
            files += sorted(f for f in p.iterdir() if f.suffix.lower() in (".sat", ".tle", ".txt", ".dat"))
        elif p.is_file():
            files.append(p)
        else:
            raise FileNotFoundError(f"no such TLE file or directory: {p}")
    newest: dict[int, Tle] = {}
    order: list[int] = []
    for f in files:
        try:
            text = f.read_text(errors="replace")
        except OSError as error:
            raise FileNotFoundError(f"cannot read {f}: {error.strerror}") from None
        for tle in parse_text(text, str(f)):
            if tle.norad not in newest:
                order.append(tle.norad)
                newest[tle.norad] = tle
            elif tle.epoch > newest[tle.norad].epoch:
                newest[tle.norad] = tle
    return [newest[n] for n in order]


def fetch(group: str, timeout: float = 30.0) -> Path:
    """Downloads a CelesTrak group (e.g. `amateur`, `weather`, `stations`) into the cache. Only
    ever called for an explicit --fetch."""
    if not _GROUP.match(group):
        raise ValueError(f"--fetch {group!r}: a CelesTrak group name is letters, digits, '-' and '_'")
    url = CELESTRAK_GROUP_URL.format(group=group)
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            text = response.read().decode("utf-8", errors="replace")
    except (urllib.error.URLError, OSError) as error:
        raise ConnectionError(f"cannot fetch {url}: {getattr(error, 'reason', error)}") from None
    if not parse_text(text, url):
        raise ConnectionError(f"{url} returned no element sets (is {group!r} a CelesTrak group?): {text[:80]!r}")
    target = cache_dir() / f"{group}.txt"
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_suffix(".tmp")
    tmp.write_text(text)
    tmp.replace(target)
    return target


def find(tles: list[Tle], query: str) -> Tle:
    """By NORAD number, exact name (case-insensitive) or unique name prefix. Raises LookupError."""
    q = query.strip()
    if q.isdigit():
        for t in tles:
            if t.norad == int(q):
                return t
    lower = q.lower()
    exact = [t for t in tles if t.name.lower() == lower]
    if exact:
        return exact[0]
    prefix = [t for t in tles if t.name.lower().startswith(lower)]
    if len(prefix) == 1:
        return prefix[0]
    if len(prefix) > 1:
        names = ", ".join(t.name for t in prefix[:8]) + (", ..." if len(prefix) > 8 else "")
        raise LookupError(f"{query!r} matches {len(prefix)} satellites ({names}); give more of the name or the NORAD number")
    near = search(tles, q)
    hint = f" (names containing it: {', '.join(t.name for t in near[:5])})" if near else ""
    where = "" if tles else " (none loaded: --tle FILE, or --fetch a CelesTrak group)"
    raise LookupError(f"no satellite {query!r} in the TLEs{hint}{where}")


def search(tles: list[Tle], text: str) -> list[Tle]:
    """Satellites whose name contains the text (case-insensitive) or whose NORAD number it is."""
    lower = text.strip().lower()
    return [t for t in tles if lower in t.name.lower() or (lower.isdigit() and t.norad == int(lower))]
