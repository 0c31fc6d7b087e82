#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 the birdcage authors
"""Turns tracking_bench's CSV output into the PNG plots and markdown tables of docs/benchmarks.md.

    /usr/bin/python3 bench/plot.py <bench-out-dir> <image-dir>

<bench-out-dir> holds matrix/ (the pass matrix), mappings/ (north-crossing and forced-unwind passes
under the other azimuth mappings), realtime/ (the k = 1 subset) and scale-<k>/ (the time-scale
sweep), as scripts/benchmark.sh lays them out; each has summary.csv (one row per run), latency.csv
(every `p` and `P` of a variant x mode pooled) and runs/ (one trace per run). Any but matrix/ may
be missing. Writes PNGs into <image-dir> and tables.md into <bench-out-dir>. Needs Debian's
python3-matplotlib and python3-numpy.
"""
import csv
import glob
import math
import os
import sys

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Traces worth a picture: the keyhole pass on both dishes and the north-crossing passes.
TRACE_PLOTS = [("iss-85", "hal205"), ("iss-85", "g2"), ("iss-45", "g2"), ("sso-70", "hal205")]
# Lines in a trace plot: (mode, threshold, line style).
TRACE_LINES = [("none", "0.5", "-"), ("leapfrog", "0.5", "--"), ("predictive", "0.5", "-"), ("auto", "0.5", "-"),
               ("none", "5", ":"), ("predictive", "5", "-."), ("auto", "5", "-."), ("oracle", "0", "-")]
VARIANT_LABEL = {"g2": "Carryout G2", "hal205": "Trav'ler HAL 2.05"}
MODE_ORDER = ["none", "leapfrog", "predictive", "auto", "oracle"]
MODE_COLOUR = {"none": "tab:blue", "leapfrog": "tab:orange", "predictive": "tab:green", "auto": "tab:purple", "oracle": "black"}
# The oracle (the client posts the true position every cycle) runs at threshold 0: the floor of
# every threshold's panel.
ORACLE_THRESHOLD = "0"
# The tracking goals (docs/tracking.md §1.2, §2.2, §2.3): RMS per client threshold, and above the elevation cap.
RMS_GOAL = {"0.5": 0.25, "5": 1.0}   # on passes one branch holds (docs/benchmarks.md, the orbit model's goals)
MAX_GOAL_COARSE = 3.0          # max error at 5 deg on passes one branch holds
MOTOR_STARTS_GOAL_COARSE = 150  # motor commands per pass at 5 deg
VS_ORACLE_GOAL = 1.2           # a motor-limited dish: RMS as a multiple of the oracle's, every pass
MAX_GOAL_FINE = 1.0            # max error at 0.5 deg on passes one branch holds
FORCED_VS_ORACLE_GOAL = 1.5    # RMS on a forced-unwind pass, as a multiple of the oracle's
CAP_EXCESS_GOAL = 0.5
REACQUIRE_GOAL = 2.0
P_ERROR_P95_GOAL = 0.1         # `p` against the true position, degrees
P_P99_GOAL_MS = 1.0
# The pointing mode a user gets without `-C pointing=`: `auto`, the variant's first guess
# (FirmwareProfile::predictive_by_default) corrected by the dish's own step times and a trusted
# orbit (docs/usage.md). The goals are judged on it, the other modes shown beside it.
DEFAULT_MODE = {"g2": "auto", "hal205": "auto"}
DEFAULT_MAPPING = "nearest"    # the emulator's default; the matrix runs under it
# The client's rotator limits (tracking_bench --client-limits): "dish" = the dish's EL range, as
# README told Gpredict users before the orbit model, "wide" = EL 0-90 (its advice now). Goals, plots and the real-time comparison use the
# dish rows; the per-pass and summary tables show both, apart.
DEFAULT_LIMITS = "dish"

PER_PASS_NOTES = """\
Columns: *limits* = the rotator limits the Gpredict-like client clamps its targets to (*dish*: the
dish's EL range, README's advice before the orbit model; *wide*: EL 0–90°, the backend clamps instead, README's advice now).
*tracked s* = seconds the satellite is inside the dish's EL limits (the error figures
*RMS*, *p95*, *max* count only those: great-circle angle between the satellite and the dish's true
direction). *motor cmds* = `a <axis> <deg>` / `g` lines the emulator received during the run;
*P sent* = the client's `P` commands. The **tracked window** runs from the satellite rising to the
dish's lowest elevation until it sets below it again (time above the EL cap included: the dish still
follows azimuth there). *pre-pass AZ* = how far the dish's azimuth travelled before the window
(pre-positioning; a branch change there costs no tracking and is not an unwind). *mid-pass extra AZ* =
the dish's azimuth travel inside the window beyond the satellite's own travel and the offset at
rise. *unwound* = a **mid-pass unwind**: mid-pass extra AZ > 180°. *avoidable* = one continuous
branch of the dish's mechanical AZ window (G2 −423.33…+23.33°, Trav'ler 0…455°) holds the whole
tracked window, so an unwind there is the backend's choice, not the geometry's. *above cap s* =
seconds the satellite is above the dish's EL cap (G2 65°); *cap excess* = the worst of
(great-circle error) − (satellite el − cap) there, the error beyond the unavoidable deficit (goal
≤ {cap}°); *re-acquire* = seconds from the satellite dropping back below the cap until the error is first
≤ 1° again (goal ≤ {reacq} s; "never" = not within the run). "—" = the pass stays below the cap (or the
run's window does not include the drop).""".format(cap=CAP_EXCESS_GOAL, reacq=REACQUIRE_GOAL)

SUMMARY_NOTES = """\
Per variant × mode × client threshold × client limits, over the passes run: *RMS* = lowest–highest
per-pass RMS (median in brackets); *worst p95*, *worst max* = the highest per-pass p95 and max;
*motor cmds/pass* and *P sent/pass* = lowest–highest; *mid-pass unwinds* = runs that unwound
mid-pass, of all runs, with the avoidable ones in brackets; *worst cap excess* / *worst re-acquire*
over the passes that rise above the cap ("—" if none does)."""

LATENCY_NOTES = """\
Real-time round trips at the client through rotctld, every `p` and `P` of all runs of a variant ×
mode pooled (ms). *Wire floor* = one `a` position query as the variant's console answers it (2 bytes
out, echo + reply + prompt back, 10 bits/byte at its baud rate): what a synchronous `p` costs at best
on a real serial line; the pty has no baud rate, so it is computed, not measured. *Reported vs true*
= great-circle distance between `p`'s answer and the closest point of the dish's true path between
just before the question and just after the answer (degrees). The backend runs with
`-C time_scale=k`, so its polling follows the emulator's clock and this is meaningful at every k."""


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def number(row, key):
    """The field as a float, NaN when it is empty or absent."""
    text = row.get(key, "")
    return float(text) if text not in ("", None) else math.nan


def column(rows, key):
    return np.array([number(r, key) for r in rows])


def mode_key(mode):
    return MODE_ORDER.index(mode) if mode in MODE_ORDER else len(MODE_ORDER)


def config_key(config):
    variant, mode, thr, limits = config
    return (variant, float(thr), limits != DEFAULT_LIMITS, limits, mode_key(mode), mode)


def plot_trace(runs_dir, pass_name, variant, image_dir):
    fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    drew = False
    capped = False
    for mode, thr, style in TRACE_LINES:
        path = os.path.join(runs_dir, f"{pass_name}_{variant}_{mode}_thr{thr}.csv")
        if not os.path.exists(path):
            continue
        rows = read_csv(path)
        t = column(rows, "t")
        if not drew:
            axes[0].plot(t, column(rows, "sat_az"), color="black", lw=2.5, alpha=0.35, label="satellite")
            axes[1].plot(t, column(rows, "sat_el"), color="black", lw=2.5, alpha=0.35, label="satellite")
            drew = True
        label = "dish, oracle (true path)" if mode == "oracle" else f"dish, {mode}, threshold {thr}°"
        colour = MODE_COLOUR.get(mode)
        axes[0].plot(t, column(rows, "dish_az"), style, color=colour, lw=1, label=label)
        axes[1].plot(t, column(rows, "dish_el"), style, color=colour, lw=1, label=label)
        error = np.where(column(rows, "in_limits") > 0, column(rows, "error_deg"), np.nan)
        axes[2].plot(t, error, style, color=colour, lw=1, label=label)
        excess = column(rows, "cap_excess_deg") if "cap_excess_deg" in rows[0] else np.full(len(rows), np.nan)
        if np.isfinite(excess).any():
            capped = True
            # Log scale: an excess of exactly 0 (dish at the cap under the satellite) drawn at 0.001°.
            axes[2].plot(t, np.maximum(excess, 1e-3), style, color=colour, lw=1, alpha=0.45)
    if not drew:
        plt.close(fig)
        return None
    axes[0].set_ylabel("azimuth (°, displayed 0..360)")
    axes[1].set_ylabel("elevation (°)")
    axes[2].set_ylabel("pointing error (°)")
    if capped:
        axes[2].set_title("pale: above the EL cap, error − (satellite el − cap)", fontsize=8)
    axes[2].set_xlabel("pass time (s)")
    axes[2].set_yscale("log")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    fig.suptitle(f"{pass_name} on the {VARIANT_LABEL.get(variant, variant)}: target vs true dish position")
    fig.tight_layout()
    name = f"track_{pass_name}_{variant}.png"
    fig.savefig(os.path.join(image_dir, name), dpi=90)
    plt.close(fig)
    return name


def plot_summary(summary, image_dir):
    """RMS per pass: one panel per variant x client threshold, one bar per pointing mode."""
    passes = sorted({r["pass"] for r in summary})
    variants = [v for v in ["g2", "hal205"] if any(r["variant"] == v for r in summary)]
    thresholds = sorted({r["threshold"] for r in summary if r["threshold"] != ORACLE_THRESHOLD}, key=float)
    modes = sorted({r["mode"] for r in summary}, key=mode_key)
    if not variants or not thresholds:
        return None
    fig, axes = plt.subplots(len(thresholds), len(variants), figsize=(6.5 * len(variants), 4.2 * len(thresholds)),
                             squeeze=False)
    width = 0.8 / max(1, len(modes))
    for row, thr in enumerate(thresholds):
        for col, variant in enumerate(variants):
            ax = axes[row][col]
            for i, mode in enumerate(modes):
                rms = []
                for p in passes:
                    wanted = ORACLE_THRESHOLD if mode == "oracle" else thr
                    r = next((r for r in summary if r["pass"] == p and r["variant"] == variant and r["mode"] == mode
                              and r["threshold"] == wanted), None)
                    rms.append(number(r, "rms") if r and number(r, "tracked_s") > 0 else np.nan)
                ax.bar(np.arange(len(passes)) + i * width, rms, width, label=mode, color=MODE_COLOUR.get(mode))
            ax.set_xticks(np.arange(len(passes)) + 0.4 - width / 2)
            ax.set_xticklabels(passes, rotation=30)
            ax.set_title(f"{VARIANT_LABEL.get(variant, variant)}, client threshold {thr}°")
            ax.set_ylabel("RMS pointing error (°)")
            ax.set_yscale("log")
            ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            ax.yaxis.set_minor_locator(matplotlib.ticker.LogLocator(subs=(2.0, 5.0)))
            ax.yaxis.set_minor_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
            if thr in RMS_GOAL:
                ax.axhline(RMS_GOAL[thr], color="red", lw=0.8, ls="--", label=f"goal {RMS_GOAL[thr]}°")
            ax.grid(alpha=0.3, axis="y", which="both")
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "rms_by_pass.png"), dpi=90)
    plt.close(fig)
    return "rms_by_pass.png"


def plot_scale(sweeps, image_dir):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    lines = sorted({(r["variant"], r["mode"]) for rows in sweeps.values() for r in rows},
                   key=lambda c: (c[0], mode_key(c[1])))
    for variant, mode in lines:
        ks, rms, perr = [], [], []
        for k, rows in sorted(sweeps.items()):
            row = next((r for r in rows if r["variant"] == variant and r["mode"] == mode), None)
            if row:
                ks.append(k)
                rms.append(number(row, "rms"))
                perr.append(number(row, "p_error_p95_deg"))
        style = "o-" if variant == "g2" else "s--"
        label = f"{VARIANT_LABEL.get(variant, variant)}, {mode}"
        axes[0].plot(ks, rms, style, color=MODE_COLOUR.get(mode), label=label)
        axes[1].plot(ks, perr, style, color=MODE_COLOUR.get(mode), label=label)
    axes[0].set_ylabel("RMS pointing error (°)")
    axes[1].set_ylabel("p95 |reported − true| position (°)")
    for ax in axes:
        ax.set_xlabel("time scale k (emulator and backend, simulated s per real s)")
        ax.set_xscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    thresholds = sorted({r["threshold"] for rows in sweeps.values() for r in rows}, key=float)
    fig.suptitle(f"Scale sensitivity: iss-70, 120 s around TCA, threshold {', '.join(thresholds)}°")
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "scale_sensitivity.png"), dpi=90)
    plt.close(fig)
    return "scale_sensitivity.png"


def fmt(value, digits=2, unit=""):
    return "—" if value is None or math.isnan(value) else f"{value:.{digits}f}{unit}"


def span(values, digits=0):
    values = [v for v in values if not math.isnan(v)]
    if not values:
        return "—"
    lo, hi = min(values), max(values)
    return f"{lo:.{digits}f}" if lo == hi else f"{lo:.{digits}f}–{hi:.{digits}f}"


def reacquire_text(value):
    if math.isnan(value):
        return "—"
    return "never" if value < 0 else f"{value:.1f}"


def mapping_of(row):
    return row.get("az_mapping") or DEFAULT_MAPPING


def limits_of(row):
    """The client's rotator limits; summaries written before the column existed are "dish"."""
    return row.get("client_limits") or DEFAULT_LIMITS


def per_pass_table(summary, title="### Per pass", notes=PER_PASS_NOTES):
    out = [title, "", notes, "",
           "| pass | peak | N-cross | variant | mode | AZ mapping | thr | limits | tracked s | RMS | p95 | max | motor cmds | P sent | "
           "pre-pass AZ | mid-pass extra AZ | unwound | avoidable | above cap s | cap excess | re-acquire s |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(summary, key=lambda r: (r["variant"], r["pass"], mapping_of(r), float(r["threshold"]),
                                            limits_of(r) != DEFAULT_LIMITS, limits_of(r), mode_key(r["mode"]))):
        tracked = number(r, "tracked_s") > 0
        err = (lambda k: fmt(number(r, k))) if tracked else (lambda k: "—")
        above = number(r, "above_cap_s")
        out.append(f"| {r['pass']} | {number(r, 'peak_el'):.0f}° | {'yes' if r['crosses_north'] == '1' else 'no'} | "
                   f"{r['variant']} | {r['mode']} | {mapping_of(r)} | {r['threshold']}° | {limits_of(r)} | {number(r, 'tracked_s'):.0f} | {err('rms')} | "
                   f"{err('p95')} | {err('max')} | {r['motor_commands']} | {r['set_commands']} | "
                   f"{number(r, 'prepass_az_travel'):.0f}° | {number(r, 'extra_az_travel'):.0f}° | "
                   f"{'**yes**' if r['unwound'] == '1' else 'no'} | {'yes' if r['one_branch'] == '1' else 'no'} | "
                   f"{fmt(above, 0) if above > 0 else '—'} | {fmt(number(r, 'cap_excess_max'), 2, '°')} | "
                   f"{reacquire_text(number(r, 'reacquire_s'))} |")
    return out


def summary_table(summary):
    out = ["### Summary per variant × mode × threshold × client limits", "", SUMMARY_NOTES, "",
           "| variant | mode | thr | limits | passes | RMS | worst p95 | worst max | motor cmds/pass | P sent/pass | "
           "mid-pass unwinds (avoidable) | worst cap excess | worst re-acquire s |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    groups = sorted({(r["variant"], r["mode"], r["threshold"], limits_of(r)) for r in summary}, key=config_key)
    for g in groups:
        rows = [r for r in summary if (r["variant"], r["mode"], r["threshold"], limits_of(r)) == g
                and number(r, "tracked_s") > 0]
        if not rows:
            continue
        rms = [number(r, "rms") for r in rows]
        unwound = [r for r in rows if r["unwound"] == "1"]
        capped = [r for r in rows if number(r, "above_cap_s") > 0]
        excess = max((number(r, "cap_excess_max") for r in capped), default=math.nan)
        reacquire = [number(r, "reacquire_s") for r in capped if not math.isnan(number(r, "reacquire_s"))]
        worst_reacquire = ("never" if any(v < 0 for v in reacquire) else f"{max(reacquire):.1f}") if reacquire else "—"
        out.append(f"| {g[0]} | {g[1]} | {g[2]}° | {g[3]} | {len(rows)} | {span(rms, 2)} ({np.median(rms):.2f}) | "
                   f"{max(number(r, 'p95') for r in rows):.2f} | {max(number(r, 'max') for r in rows):.2f} | "
                   f"{span([number(r, 'motor_commands') for r in rows])} | "
                   f"{span([number(r, 'set_commands') for r in rows])} | "
                   f"{len(unwound)} of {len(rows)} ({sum(1 for r in unwound if r['one_branch'] == '1')}) | "
                   f"{fmt(excess, 2, '°')} | {worst_reacquire} |")
    return out


def latency_table(latency_sets):
    out = ["### Latency through rotctld", "", LATENCY_NOTES, "",
           "| source | variant | mode | p median | p p95 | p p99 | p max | P median | P p95 | P p99 | P max | "
           "wire floor `a` | reported vs true p95 | p99 |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for label, rows in latency_sets:
        for r in sorted(rows, key=lambda r: (r["variant"], mode_key(r["mode"]))):
            ms = lambda k: f"{number(r, k):.3f}"  # noqa: E731
            out.append(f"| {label} | {r['variant']} | {r['mode']} | {ms('p_median_ms')} | {ms('p_p95_ms')} | "
                       f"{ms('p_p99_ms')} | {ms('p_max_ms')} | {ms('P_median_ms')} | {ms('P_p95_ms')} | "
                       f"{ms('P_p99_ms')} | {ms('P_max_ms')} | {number(r, 'wire_floor_ms'):.2f} | "
                       f"{number(r, 'p_error_p95_deg'):.3f}° | {number(r, 'p_error_p99_deg'):.3f}° |")
    return out


def sweep_table(sweeps):
    out = ["### Scale sweep (iss-70, 120 s around TCA)", "",
           "| k | variant | mode | thr | RMS | p95 | max | motor cmds | reported vs true p95 | p99 |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for k, rows in sorted(sweeps.items()):
        for r in sorted(rows, key=lambda r: (r["variant"], mode_key(r["mode"]), float(r["threshold"]))):
            out.append(f"| {k:g} | {r['variant']} | {r['mode']} | {r['threshold']}° | {number(r, 'rms'):.2f} | "
                       f"{number(r, 'p95'):.2f} | {number(r, 'max'):.2f} | {r['motor_commands']} | "
                       f"{number(r, 'p_error_p95_deg'):.2f}° | {number(r, 'p_error_p99_deg'):.2f}° |")
    return out


MAPPING_NOTES = """\
The same columns as the matrix, for the north-crossing and forced-unwind passes under the two
other ways the emulated firmware may map an azimuth target onto its travel (`--az-mapping`):
*literal* (a number is a mechanical angle) and *wrap_manager* (the firmware keeps the axis inside
one 360° sector, wrap point at north). The backend is not told which it meets. *avoidable* is
judged against what the mapping lets the dish reach: under a wrap manager at north, no north
crossing is held by any branch."""

REALTIME_NOTES = """\
The same runs at k = 1 (real time: emulator, backend and client) beside their k = 5 matrix row.
If the time scale distorted the backend or the client, the error and the motor commands would
differ systematically between the two columns; single runs differ by their own noise (compare
bimodal rows, e.g. an unwind in one run and not in the other)."""


def key_of(row):
    return (row["pass"], row["variant"], row["mode"], row["threshold"], mapping_of(row), limits_of(row))


def realtime_table(matrix, realtime):
    by_key = {key_of(r): r for r in matrix}
    out = ["### Real time (k = 1) against the matrix (k = 5)", "", REALTIME_NOTES, "",
           "| pass | variant | mode | thr | RMS k=1 | RMS k=5 | max k=1 | max k=5 | motor cmds k=1 | k=5 | "
           "P sent k=1 | k=5 | unwound k=1 | k=5 | `p` p99 k=1 | reported vs true p95 k=1 |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(realtime, key=lambda r: (r["variant"], r["pass"], float(r["threshold"]), mode_key(r["mode"]))):
        m = by_key.get(key_of(r))
        other = (lambda k, d=2: fmt(number(m, k), d)) if m else (lambda k, d=2: "—")
        unwound = lambda row: "**yes**" if row["unwound"] == "1" else "no"  # noqa: E731
        out.append(f"| {r['pass']} | {r['variant']} | {r['mode']} | {r['threshold']}° | {fmt(number(r, 'rms'))} | "
                   f"{other('rms')} | {fmt(number(r, 'max'))} | {other('max')} | {r['motor_commands']} | "
                   f"{other('motor_commands', 0)} | {r['set_commands']} | {other('set_commands', 0)} | "
                   f"{unwound(r)} | {unwound(m) if m else '—'} | {fmt(number(r, 'p_p99_ms'), 3)} ms | "
                   f"{fmt(number(r, 'p_error_p95_deg'), 3)}° |")
    return out


def runs_of(summary, variant, mode, threshold):
    return [r for r in summary if r["variant"] == variant and r["mode"] == mode and r["threshold"] == threshold
            and number(r, "tracked_s") > 0]


def worst(rows, key):
    """(value, pass) of the row with the highest `key`, or (nan, '')."""
    if not rows:
        return math.nan, ""
    row = max(rows, key=lambda r: number(r, key))
    return number(row, key), row["pass"]


def verdict(ok):
    return "**met**" if ok else "not met"


def goal_rows(matrix, mappings, latency, variant, mode):
    """One (goal, figure, met) per tracking goal, for this variant run in this mode."""
    rows = []
    fine = runs_of(matrix, variant, mode, "0.5")
    held = [r for r in fine if r["one_branch"] == "1"]
    forced = [r for r in fine if r["one_branch"] != "1"]
    rms, at = worst(held, "rms")
    met = sum(1 for r in held if number(r, "rms") <= RMS_GOAL["0.5"])
    rows.append((f"0.5°: RMS ≤ {RMS_GOAL['0.5']}° where a branch holds the pass",
                 f"worst {fmt(rms)}° ({at}); {met} of {len(held)} passes within", bool(held) and met == len(held)))
    worst_max, at = worst(held, "max")
    met = sum(1 for r in held if number(r, "max") <= MAX_GOAL_FINE)
    rows.append((f"0.5°: max ≤ {MAX_GOAL_FINE}° where a branch holds the pass",
                 f"worst {fmt(worst_max)}° ({at}); {met} of {len(held)} passes within",
                 bool(held) and met == len(held)))
    oracle = {r["pass"]: r for r in runs_of(matrix, variant, "oracle", ORACLE_THRESHOLD)}
    ratios = [(number(r, "rms") / number(oracle[r["pass"]], "rms"), r["pass"]) for r in forced
              if r["pass"] in oracle and number(oracle[r["pass"]], "rms") > 0]
    if ratios:
        ratio, at = max(ratios)
        rows.append((f"0.5°, forced-unwind passes: RMS ≤ {FORCED_VS_ORACLE_GOAL}× the oracle's",
                     "worst " + f"{ratio:.1f}× ({at}); " + ", ".join(f"{p} {x:.1f}×" for x, p in sorted(ratios, key=lambda x: x[1])),
                     ratio <= FORCED_VS_ORACLE_GOAL))
    coarse = [r for r in runs_of(matrix, variant, mode, "5") if r["one_branch"] == "1"]
    rms, at = worst(coarse, "rms")
    met = sum(1 for r in coarse if number(r, "rms") <= RMS_GOAL["5"])
    rows.append((f"5°: RMS ≤ {RMS_GOAL['5']}° where a branch holds the pass",
                 f"worst {fmt(rms)}° ({at}); {met} of {len(coarse)} passes within", bool(coarse) and met == len(coarse)))
    worst_max, at = worst(coarse, "max")
    met = sum(1 for r in coarse if number(r, "max") <= MAX_GOAL_COARSE)
    rows.append((f"5°: max ≤ {MAX_GOAL_COARSE:g}° where a branch holds the pass",
                 f"worst {fmt(worst_max)}° ({at}); {met} of {len(coarse)} passes within", bool(coarse) and met == len(coarse)))
    starts, at = worst(coarse, "motor_commands")
    met = sum(1 for r in coarse if number(r, "motor_commands") <= MOTOR_STARTS_GOAL_COARSE)
    rows.append((f"5°: ≤ {MOTOR_STARTS_GOAL_COARSE} motor commands per pass",
                 f"worst {fmt(starts, 0)} ({at}); {met} of {len(coarse)} passes within", bool(coarse) and met == len(coarse)))
    for thr in ("0.5", "5"):
        pairs = [(number(r, "rms") / number(oracle[r["pass"]], "rms"), r["pass"]) for r in runs_of(matrix, variant, mode, thr)
                 if r["pass"] in oracle and number(oracle[r["pass"]], "rms") > 0]
        if pairs:
            ratio, at = max(pairs)
            within = sum(1 for x, _ in pairs if x <= VS_ORACLE_GOAL)
            rows.append((f"{thr}°: RMS ≤ {VS_ORACLE_GOAL:g}× the oracle's (every pass)",
                         f"worst {ratio:.1f}× ({at}); {within} of {len(pairs)} passes within", within == len(pairs)))
    if mode != "none":
        over = []
        for thr in ("0.5", "5"):
            base = {r["pass"]: r for r in runs_of(matrix, variant, "none", thr)}
            for r in runs_of(matrix, variant, mode, thr):
                if r["pass"] in base and number(base[r["pass"]], "motor_commands") > 0:
                    over.append((number(r, "motor_commands") / number(base[r["pass"]], "motor_commands"),
                                 f"{r['pass']} {thr}°"))
        if over:
            ratio, at = max(over)
            within = sum(1 for x, _ in over if x <= 1.0)
            rows.append(("motor commands per pass ≤ `none`'s at the same threshold",
                         f"worst {ratio:.1f}× ({at}); {within} of {len(over)} runs within", within == len(over)))
    every = [r for r in matrix + mappings if r["variant"] == variant and r["mode"] == mode]
    avoidable = [r for r in every if r["unwound"] == "1" and r["one_branch"] == "1"]
    rows.append(("no avoidable unwind (matrix and mapping runs)",
                 f"{len(avoidable)} of {len(every)} runs" +
                 (" (" + ", ".join(f"{r['pass']} {r['threshold']}° {mapping_of(r)}" for r in avoidable) + ")"
                  if avoidable else ""), not avoidable))
    swing, at = worst(every, "prepass_az_travel")
    rows.append(("no pre-pass swing beyond the chosen branch (pre-pass AZ ≤ 400°: one branch change and the "
                 "approach)", f"worst {fmt(swing, 0)}° ({at})", not math.isnan(swing) and swing <= 400.0))
    capped = [r for r in matrix if r["variant"] == variant and r["mode"] == mode and number(r, "above_cap_s") > 0
              and number(r, "tracked_s") > 0]
    if capped:
        excess, at = worst(capped, "cap_excess_max")
        rows.append((f"above the cap: excess ≤ {CAP_EXCESS_GOAL}°", f"worst {fmt(excess)}° ({at})",
                     excess <= CAP_EXCESS_GOAL))
        reacquire = [(number(r, "reacquire_s"), r["pass"] + " " + r["threshold"] + "°") for r in capped
                     if not math.isnan(number(r, "reacquire_s"))]
        if reacquire:
            never = [p for v, p in reacquire if v < 0]
            value, at = max(reacquire)
            text = f"never ({', '.join(never)})" if never else f"worst {value:.1f} s ({at})"
            rows.append((f"above the cap: re-acquire ≤ {REACQUIRE_GOAL:g} s", text,
                         not never and value <= REACQUIRE_GOAL))
    pooled = next((r for r in latency if r["variant"] == variant and r["mode"] == mode), None)
    if pooled:
        rows.append((f"`p` vs truth p95 ≤ {P_ERROR_P95_GOAL}°", f"{number(pooled, 'p_error_p95_deg'):.3f}°",
                     number(pooled, "p_error_p95_deg") <= P_ERROR_P95_GOAL))
        rows.append((f"`p` p99 ≤ {P_P99_GOAL_MS:g} ms through rotctld", f"{number(pooled, 'p_p99_ms'):.3f} ms",
                     number(pooled, "p_p99_ms") <= P_P99_GOAL_MS))
    return rows


def goals_table(matrix, mappings, latency):
    out = ["### Against the tracking goals", "",
           f"Judged on each dish's default pointing mode ({', '.join(f'{v}: `{m}`' for v, m in DEFAULT_MODE.items())}), "
           "with the other modes beside it; from the matrix (k = 5, AZ mapping nearest, client limits dish) and, for unwinds and "
           "pre-pass travel, the mapping runs too.", "",
           "| variant | goal | mode | figure | verdict |", "|---|---|---|---|---|"]
    variants = [v for v in ["g2", "hal205"] if any(r["variant"] == v for r in matrix)]
    passes = sorted({r["pass"] for r in matrix})
    north = sorted({r["pass"] for r in matrix if r["crosses_north"] == "1"})
    pass_set = [f"The pass set: {len(passes)} passes, {len(north)} of them crossing north ({', '.join(north)}).", "",
                "| variant | AZ mapping | passes run | no branch holds (a forced unwind) |", "|---|---|---|---|"]
    for variant in variants:
        for mapping in [DEFAULT_MAPPING] + sorted({mapping_of(r) for r in mappings} - {DEFAULT_MAPPING}):
            rows = [r for r in matrix + list(mappings) if r["variant"] == variant and mapping_of(r) == mapping]
            if rows:
                forced = sorted({r["pass"] for r in rows if r["one_branch"] != "1" and number(r, "tracked_s") > 0})
                pass_set.append(f"| {variant} | {mapping} | {len({r['pass'] for r in rows})} | "
                                f"{', '.join(forced) if forced else '—'} |")
    out[2:2] = pass_set + [""]
    for variant in variants:
        modes = [DEFAULT_MODE.get(variant, "none")] + [m for m in ("predictive", "none", "leapfrog")
                                                      if m != DEFAULT_MODE.get(variant, "none")]
        per_mode = {m: goal_rows(matrix, mappings, latency, variant, m) for m in modes if runs_of(matrix, variant, m, "0.5")}
        default = modes[0]
        for i, (goal, figure, ok) in enumerate(per_mode.get(default, [])):
            out.append(f"| {variant} | {goal} | **{default}** (default) | {figure} | {verdict(ok)} |")
            for m in modes[1:]:
                match = next((row for row in per_mode.get(m, []) if row[0] == goal), None)
                if match:
                    out.append(f"| | | {m} | {match[1]} | {verdict(match[2])} |")
    return out


def worst_passes(matrix):
    """(pass, variant) of the highest-RMS pass per dish in its default mode, at each threshold."""
    picked = []
    for variant, mode in DEFAULT_MODE.items():
        for thr in ("0.5", "5"):
            _, at = worst(runs_of(matrix, variant, mode, thr), "rms")
            if at and (at, variant) not in picked:
                picked.append((at, variant))
    return picked


def tables(summary, latency_sets, sweeps, mappings=(), realtime=(), latency=(), other_limits=()):
    """summary: the matrix's dish-limits rows; other_limits: its other rows (per-pass and summary tables only)."""
    everything = list(summary) + list(other_limits)
    out = goals_table(summary, list(mappings), list(latency)) + [""]
    out += per_pass_table(everything) + [""] + summary_table(everything) + [""]
    if mappings:
        out += per_pass_table(list(mappings), "### North crossings and forced unwinds under the other AZ mappings",
                              MAPPING_NOTES) + [""]
    if realtime:
        out += realtime_table(summary, list(realtime)) + [""]
    out += latency_table(latency_sets)
    if sweeps:
        out += [""] + sweep_table(sweeps)
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out_dir, image_dir = sys.argv[1], sys.argv[2]
    os.makedirs(image_dir, exist_ok=True)
    matrix = read_csv(os.path.join(out_dir, "matrix", "summary.csv"))
    summary = [r for r in matrix if limits_of(r) == DEFAULT_LIMITS]
    other_limits = [r for r in matrix if limits_of(r) != DEFAULT_LIMITS]

    def optional(*parts):
        path = os.path.join(out_dir, *parts)
        return read_csv(path) if os.path.exists(path) else []

    mappings, realtime = optional("mappings", "summary.csv"), optional("realtime", "summary.csv")
    matrix_latency = optional("matrix", "latency.csv")
    sweeps, latency_sets = {}, []
    if matrix_latency:
        scale = {r["scale"] for r in summary}
        latency_sets.append((f"matrix {'/'.join(sorted(scale))}x", matrix_latency))
    for label, name in (("mapping runs", "mappings"), ("real time 1x", "realtime")):
        rows = optional(name, "latency.csv")
        if rows:
            latency_sets.append((label, rows))
    for d in sorted(glob.glob(os.path.join(out_dir, "scale-*")), key=lambda d: float(d.rsplit("-", 1)[1])):
        path = os.path.join(d, "summary.csv")
        if os.path.exists(path):
            k = float(d.rsplit("-", 1)[1])
            sweeps[k] = read_csv(path)
            if os.path.exists(os.path.join(d, "latency.csv")):
                latency_sets.append((f"sweep {k:g}x", read_csv(os.path.join(d, "latency.csv"))))
    made = []
    for pass_name, variant in TRACE_PLOTS + [w for w in worst_passes(summary) if w not in TRACE_PLOTS]:
        name = plot_trace(os.path.join(out_dir, "matrix", "runs"), pass_name, variant, image_dir)
        if name:
            made.append(name)
    name = plot_summary(summary, image_dir)
    if name:
        made.append(name)
    if sweeps:
        made.append(plot_scale(sweeps, image_dir))
    with open(os.path.join(out_dir, "tables.md"), "w") as f:
        f.write(tables(summary, latency_sets, sweeps, mappings, realtime, matrix_latency, other_limits))
    print("plots:", ", ".join(os.path.join(image_dir, m) for m in made))
    print("tables:", os.path.join(out_dir, "tables.md"))


if __name__ == "__main__":
    main()
