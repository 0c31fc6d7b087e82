# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Sky scans as samples in the dish's axes: the upstream `az el rssi` lines
(sim/data/g2-ku-skyscan/scan_data.txt) and birdcage-skyscan's CSV `az,el,value,time`
(docs/receiver.md), in the order they were taken."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class Scan:
    az: np.ndarray
    el: np.ndarray
    value: np.ndarray
    time: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.az)

    def columns_alternate(self) -> bool:
        """Whether the scan runs serpentine (consecutive columns in opposite directions), where a
        reading taken before the move it is labelled with shifts alternate columns apart."""
        directions = []
        start = 0
        for i in range(1, len(self.az) + 1):
            if i == len(self.az) or abs(self.az[i] - self.az[start]) > 1e-6:
                if i - start > 1:
                    directions.append(np.sign(self.el[i - 1] - self.el[start]))
                start = i
        return len(directions) > 2 and np.mean(np.array(directions[1:]) != np.array(directions[:-1])) > 0.8

    def previous_in_column(self) -> np.ndarray:
        """Index of the sample taken before each one in the same column (itself at a column's start)."""
        prev = np.arange(len(self.az))
        same = np.abs(np.diff(self.az)) < 1e-6
        prev[1:][same] = np.arange(len(self.az) - 1)[same]
        return prev

    def save(self, path: Path) -> None:
        with open(path, "w") as f:
            f.write("az,el,value,time\n")
            for i in range(len(self)):
                t = "" if self.time is None else f"{self.time[i]:.3f}"
                f.write(f"{self.az[i]:.3f},{self.el[i]:.3f},{self.value[i]:.3f},{t}\n")


def read(path: Path) -> Scan:
    az, el, value, when = [], [], [], []
    with open(path, newline="") as f:
        for line in f:
            line = line.strip()
            fields = line.split(",") if "," in line else line.split()
            try:
                a, e, v = float(fields[0]), float(fields[1]), float(fields[2])
            except (ValueError, IndexError):
                continue  # a header or a row cut off by an interruption
            az.append(a)
            el.append(e)
            value.append(v)
            try:
                when.append(float(fields[3]))
            except (ValueError, IndexError):
                when.append(np.nan)
    if len(az) < 10:
        raise ValueError(f"{path}: fewer than 10 scan rows (`az el rssi` or `az,el,value,time`)")
    t = np.array(when)
    return Scan(np.array(az), np.array(el), np.array(value), None if np.isnan(t).all() else t)
