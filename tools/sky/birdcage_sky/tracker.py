# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Following a target through the dish's window (docs/sky.md section 4).

Before AOS the dish is sent once to where the pass will enter the window (the target's azimuth
PREROLL_S before AOS, at el_min) and waits there. From then on the tracker sends targets that
lead the target by the dish's response, and only when the led target has moved by the threshold
on the sky since the last one sent:

  lead = response + threshold / (2 x the target's rate on the sky)

so the dish arrives, then sits centred on the target's path until the next step. `response` is
learnt from the dish's own feedback: every `p` is placed along the target's path (how many
seconds the dish trails or leads the unled target), and the response is corrected by that
offset's running mean, so the dish ends up neither trailing nor leading on average. It starts
from INITIAL_RESPONSE_S. Behind the birdcage backend's predictive pointing (which leads by itself,
docs/tracking.md section 6) the targets are sent unled instead. Elevations are held inside the
dish's window (at el_max while the target is above it, the azimuth still followed). The pointing
error is `p` against the unled target, clamped to the window as the dish can reach it, sampled at
every poll from acquisition to LOS.
"""

from __future__ import annotations

import math
import re
import time
from dataclasses import dataclass, field

import numpy as np

from .clock import Clock, iso
from .geodesy import Station, angular_distance
from .passes import Pass, current_or_next
from .rotctld import Limits, Rotctld, RotctldError
from .targets import FixedAzEl, Target

INITIAL_RESPONSE_S = 0.5  # a guess until the dish has answered a few moves
# Seconds before AOS from which targets are sent (held at el_min, the azimuth following the
# target): the backend learns the pass's direction and picks its cable-wrap branch before the
# target is in reach (docs/tracking.md section 2.3), as it does behind Gpredict.
PREROLL_S = 10.0
MAX_RESPONSE_S = 10.0
LEARN_TIME_S = 15.0  # the running mean's time constant (at least three steps)
ACQUIRED_DEG = 1.0  # the error counts once the dish is this close to the target (after any slew)
POINTING_CHECK_REAL_S = 3.0  # how often the backend's pointing mode is read again (it may change)


@dataclass
class Options:
    threshold: float = 0.2  # degrees on the sky between two targets sent
    park_at_los: bool = False
    duration: float | None = None  # seconds of the clock
    horizon_s: float = 86400.0  # how far ahead a pass is looked for
    progress_real_s: float = 1.0  # real seconds between progress events
    fixed_response: float | None = None  # seconds: no learning (0: targets as they are, no lead)
    log = None  # a text file: one CSV line per poll


@dataclass
class Stats:
    errors: list = field(default_factory=list)
    clamped_samples: int = 0

    def summary(self) -> tuple[float | None, float | None]:
        if not self.errors:
            return None, None
        e = np.asarray(self.errors)
        return float(np.sqrt(np.mean(e * e))), float(e.max())


def backend_steers_ahead(info: str) -> bool:
    """Whether the birdcage backend's `_` says it leads the targets itself: `pointing
    predictive`, or `pointing none, predictive while the orbit holds` (a slow dish switches to
    the orbit it fitted to the targets once it trusts it)."""
    return bool(re.search(r"\bpointing predictive\b|\bpredictive while the orbit holds\b", info))


class Tracker:
    def __init__(self, rot: Rotctld, clock: Clock, station: Station, target: Target, limits: Limits,
                 emit, options: Options):
        self.rot, self.clock, self.station, self.target = rot, clock, station, target
        self.limits, self.emit, self.options = limits, emit, options
        self.stop_requested = False
        self.stats = Stats()
        self.response = INITIAL_RESPONSE_S if options.fixed_response is None else options.fixed_response
        self.last_learn: float | None = None
        self.backend_leads = False
        self.acquired = False
        self.pointing_checked = -math.inf
        self.parked = False

    # ---- geometry ----

    def look(self, t: float) -> tuple[float, float]:
        return self.target.look_one(self.station, t)

    def reachable(self, az: float, el: float) -> tuple[float, float]:
        return az % 360.0, self.limits.clamp_el(el)

    def rate(self, t: float) -> float:
        """The target's speed on the sky, degrees per second."""
        a0, e0 = self.look(t)
        a1, e1 = self.look(t + 1.0)
        return float(angular_distance(a0, e0, a1, e1))

    # ---- the run ----

    def end(self, outcome: str, reason: str) -> dict:
        rms, worst = self.stats.summary()
        event = {"event": "end", "outcome": outcome, "reason": reason,
                 "rms_error_deg": None if rms is None else round(rms, 4),
                 "max_error_deg": None if worst is None else round(worst, 4),
                 "samples": len(self.stats.errors), "commands_sent": self.rot.sent_moves, "parked": self.parked,
                 # Extensions: the response the lead was built on, and the samples taken with the
                 # target above the dish's cap (their error is against the cap).
                 "response_s": round(self.response, 3), "clamped_samples": self.stats.clamped_samples,
                 "backend_leads": self.backend_leads}
        self.emit(event)
        return event

    def interrupted(self) -> dict:
        try:
            self.rot.stop()
        except RotctldError:
            pass
        return self.end("interrupted", "stopped by a signal; the dish was sent S (stop)")

    def run(self) -> dict:
        start = self.clock.now()
        if isinstance(self.target, FixedAzEl):
            return self.run_fixed(start)
        found = current_or_next(self.target, self.station, start, self.options.horizon_s, self.limits.el_min,
                                self.limits.el_max)
        if found is None:
            hours = self.options.horizon_s / 3600
            self.emit({"event": "plan", "target": self.target.name, "aos": None, "los": None, "max_el": None,
                       "now": iso(start, 3)})
            return self.end("unreachable", f"{self.target.name} does not enter the dish's window "
                                           f"(el {self.limits.el_min:g}..{self.limits.el_max:g}) within {hours:g} h")
        self.emit({"event": "plan", "target": self.target.name, "aos": iso(found.aos), "los": iso(found.los),
                   "max_el": round(found.max_el, 2), "now": iso(start, 3),
                   "tca": iso(found.tca), "above_max_s": round(sum(b - a for a, b in found.above_max), 1)})
        deadline = start + self.options.duration if self.options.duration else None
        if found.aos is not None and found.aos > start:
            outcome = self.wait_for(found, deadline)
            if outcome:
                return outcome
        return self.follow(found, deadline)

    def wait_for(self, found: Pass, deadline: float | None) -> dict | None:
        # Where the first target sent will be: every later one lies ahead of it along the pass.
        begin = self.start_following(found)
        aim = self.reachable(*self.look(begin + self.lead(begin)))
        self.rot.move(*aim)
        last_emit = -math.inf
        while True:
            if self.stop_requested:
                return self.interrupted()
            now = self.clock.now()
            if deadline is not None and now >= deadline:
                return self.end("duration", "the duration ended before the pass began")
            if now >= self.start_following(found):
                return None
            if time.monotonic() - last_emit >= self.options.progress_real_s:
                last_emit = time.monotonic()
                self.emit({"event": "wait", "now": iso(now, 3), "seconds_to_aos": round(found.aos - now, 1),
                           "aim": {"az": round(aim[0], 2), "el": round(aim[1], 2)}})
            self.clock.sleep_until(self.start_following(found), real_cap=0.1)

    def start_following(self, found: Pass) -> float:
        return found.aos - max(self.lead(found.aos), PREROLL_S)

    def step(self, t: float) -> float:
        return self.options.threshold

    def lead(self, t: float) -> float:
        self.check_pointing()
        if self.response <= 0 or self.backend_leads:
            return 0.0
        rate = max(self.rate(t), 1e-6)
        return min(self.response + self.step(t) / (2 * rate), 600.0)

    def follow(self, found: Pass, deadline: float | None) -> dict:
        sent: tuple[float, float] | None = None
        last_emit = -math.inf
        rate_t, rate = -math.inf, 0.0
        while True:
            if self.stop_requested:
                return self.interrupted()
            t = self.clock.now()
            if found.los is not None and t >= found.los:
                return self.finish("los", f"{self.target.name} left the dish's window at LOS")
            if deadline is not None and t >= deadline:
                return self.finish("duration", "the duration ended")
            if t - rate_t > 5.0:
                rate_t, rate = t, max(self.rate(t), 1e-6)
            self.check_pointing()
            response = 0.0 if self.backend_leads else self.response
            step = self.options.threshold
            lead = min(response + step / (2 * rate), 600.0) if response > 0 else 0.0
            led = self.reachable(*self.look(t + lead))
            if sent is None or self.apart(led, sent) >= step:
                self.rot.move(*led)
                sent = led
            before = self.clock.now()
            dish = self.rot.position()
            tp = (before + self.clock.now()) / 2
            truth_az, truth_el = self.look(tp)
            reach = self.reachable(truth_az, truth_el)
            error = float(angular_distance(dish[0], dish[1], reach[0], reach[1]))
            in_window = found.aos is None or tp >= found.aos
            # A pass joined under way starts with a slew: the error counts from acquisition.
            self.acquired = self.acquired or (in_window and error <= ACQUIRED_DEG)
            in_window = in_window and self.acquired
            if in_window:
                self.stats.errors.append(error)
                if truth_el > self.limits.el_max:
                    self.stats.clamped_samples += 1
            if self.options.log:
                self.options.log.write(f"{tp:.3f},{reach[0]:.3f},{reach[1]:.3f},{dish[0]:.3f},{dish[1]:.3f},"
                                       f"{sent[0]:.3f},{sent[1]:.3f},{self.response:.3f},{error:.4f}\n")
            if in_window and not self.backend_leads and truth_el <= self.limits.el_max and error < 3 * step + 1.0:
                self.learn_response(tp, dish, (truth_az, truth_el), step / rate)
            if time.monotonic() - last_emit >= self.options.progress_real_s:
                last_emit = time.monotonic()
                self.emit({"event": "progress", "now": iso(tp, 3),
                           "target": {"az": round(reach[0], 2), "el": round(reach[1], 2)},
                           "dish": {"az": round(dish[0], 2), "el": round(dish[1], 2)},
                           "error_deg": round(error, 3),
                           "seconds_to_los": None if found.los is None else round(found.los - tp, 1)})
            # Poll often enough that the led target never runs a quarter step past the threshold.
            tick = min(max(0.25 * step / rate, 0.05), 1.0)
            self.clock.sleep(min(tick, 0.25 * self.clock.time_scale))

    def check_pointing(self) -> None:
        """Whether the birdcage backend leads the targets itself (`pointing predictive` in its
        info, which it may choose or drop during a pass from what its motors show). Then the
        targets go unled; a second lead on top of the backend's would double it."""
        if time.monotonic() - self.pointing_checked < POINTING_CHECK_REAL_S:
            return
        self.pointing_checked = time.monotonic()
        try:
            info = self.rot.info()
        except RotctldError:
            return
        self.backend_leads = backend_steers_ahead(info)

    def learn_response(self, t: float, dish: tuple[float, float], truth: tuple[float, float],
                       step_interval: float) -> None:
        """Corrects the response by how far along the target's path the dish is: trailing by a
        second on average makes the response a second longer."""
        if self.options.fixed_response is not None:
            return
        later = self.look(t + 1.0)
        cos_el = math.cos(math.radians(truth[1]))
        vx = (((later[0] - truth[0] + 180.0) % 360.0) - 180.0) * cos_el
        vy = later[1] - truth[1]
        speed2 = vx * vx + vy * vy
        if speed2 < 1e-6:  # a target that hardly moves says nothing about the dish's delay
            return
        ex = (((dish[0] - truth[0] + 180.0) % 360.0) - 180.0) * cos_el
        ey = dish[1] - truth[1]
        trailing_s = -(ex * vx + ey * vy) / speed2
        dt = 0.0 if self.last_learn is None else min(t - self.last_learn, 5.0)
        self.last_learn = t
        time_constant = max(LEARN_TIME_S, 3 * step_interval)
        self.response = min(max(self.response + trailing_s * dt / time_constant, 0.0), MAX_RESPONSE_S)

    @staticmethod
    def apart(a: tuple[float, float], b: tuple[float, float]) -> float:
        """On the sky: the pointing error the step would leave, whichever axes it takes."""
        return float(angular_distance(a[0], a[1], b[0], b[1]))

    def finish(self, outcome: str, reason: str) -> dict:
        if self.options.park_at_los and outcome == "los":
            self.rot.park()
            self.parked = True
            reason += "; parked (K)"
        return self.end(outcome, reason)

    def run_fixed(self, start: float) -> dict:
        az, el = self.target.az, self.target.el
        self.emit({"event": "plan", "target": self.target.name, "aos": None, "los": None, "max_el": el,
                   "now": iso(start, 3)})
        if not self.limits.el_min <= el <= self.limits.el_max:
            return self.end("unreachable", f"elevation {el:g} is outside the dish's window "
                                           f"{self.limits.el_min:g}..{self.limits.el_max:g}")
        self.rot.move(az, el)
        deadline = start + self.options.duration if self.options.duration else None
        last_emit, still = -math.inf, 0
        previous = None
        while True:
            if self.stop_requested:
                return self.interrupted()
            t = self.clock.now()
            dish = self.rot.position()
            error = float(angular_distance(dish[0], dish[1], az, el))
            if time.monotonic() - last_emit >= self.options.progress_real_s:
                last_emit = time.monotonic()
                self.emit({"event": "progress", "now": iso(t, 3), "target": {"az": round(az, 2), "el": round(el, 2)},
                           "dish": {"az": round(dish[0], 2), "el": round(dish[1], 2)}, "error_deg": round(error, 3),
                           "seconds_to_los": None})
            still = still + 1 if previous == dish else 0
            previous = dish
            if deadline is None and still >= 3:
                self.stats.errors.append(error)
                return self.end("duration", "the dish reached the fixed position")
            if deadline is not None:
                if still >= 3 or self.stats.errors:
                    self.stats.errors.append(error)
                if t >= deadline:
                    return self.end("duration", "the duration ended")
            self.clock.sleep(min(0.5, 0.2 * self.clock.time_scale))
