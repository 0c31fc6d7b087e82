#!/usr/bin/python3
"""Turns tracking_bench's CSV output into the PNG plots and markdown tables of docs/benchmarks.md.

    /usr/bin/python3 bench/plot.py <bench-out-dir> <image-dir>

<bench-out-dir> holds matrix/ (the pass matrix) and scale-<k>/ (the time-scale sweep), as
scripts/benchmark.sh lays them out; each has summary.csv (one row per run), latency.csv (every `p`
and `P` of a variant x mode pooled) and runs/ (one trace per run). Writes PNGs into <image-dir> and
tables.md into <bench-out-dir>. Needs Debian's python3-matplotlib and python3-numpy.
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
TRACE_LINES = [("none", "0.5", "-"), ("leapfrog", "0.5", "--"), ("predictive", "0.5", "-"),
               ("none", "5", ":"), ("predictive", "5", "-."), ("oracle", "0", "-")]
VARIANT_LABEL = {"g2": "Carryout G2", "hal205": "Trav'ler HAL 2.05"}
MODE_ORDER = ["none", "leapfrog", "predictive", "oracle"]
MODE_COLOUR = {"none": "tab:blue", "leapfrog": "tab:orange", "predictive": "tab:green", "oracle": "black"}
# The oracle (the client posts the true position every cycle) runs at threshold 0: the floor of
# every threshold's panel.
ORACLE_THRESHOLD = "0"
# Goals of issue 5 (docs/tracking.md): RMS per client threshold, and above the elevation cap.
RMS_GOAL = {"0.5": 0.25, "5": 1.5}
CAP_EXCESS_GOAL = 0.5
REACQUIRE_GOAL = 2.0

PER_PASS_NOTES = """\
Columns: *tracked s* = seconds the satellite is inside the dish's EL limits (the error figures
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
Per variant × mode × client threshold, over the passes run: *RMS* = lowest–highest per-pass RMS
(median in brackets); *worst p95*, *worst max* = the highest per-pass p95 and max; *motor cmds/pass*
and *P sent/pass* = lowest–highest; *mid-pass unwinds* = runs that unwound mid-pass, of all runs, with
the avoidable ones in brackets; *worst cap excess* / *worst re-acquire* over the passes that rise
above the cap ("—" if none does)."""

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
    variant, mode, thr = config
    return (variant, float(thr), mode_key(mode), mode)


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


def per_pass_table(summary):
    out = ["### Per pass", "", PER_PASS_NOTES, "",
           "| pass | peak | N-cross | variant | mode | thr | tracked s | RMS | p95 | max | motor cmds | P sent | "
           "pre-pass AZ | mid-pass extra AZ | unwound | avoidable | above cap s | cap excess | re-acquire s |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(summary, key=lambda r: (r["variant"], r["pass"], float(r["threshold"]), mode_key(r["mode"]))):
        tracked = number(r, "tracked_s") > 0
        err = (lambda k: fmt(number(r, k))) if tracked else (lambda k: "—")
        above = number(r, "above_cap_s")
        out.append(f"| {r['pass']} | {number(r, 'peak_el'):.0f}° | {'yes' if r['crosses_north'] == '1' else 'no'} | "
                   f"{r['variant']} | {r['mode']} | {r['threshold']}° | {number(r, 'tracked_s'):.0f} | {err('rms')} | "
                   f"{err('p95')} | {err('max')} | {r['motor_commands']} | {r['set_commands']} | "
                   f"{number(r, 'prepass_az_travel'):.0f}° | {number(r, 'extra_az_travel'):.0f}° | "
                   f"{'**yes**' if r['unwound'] == '1' else 'no'} | {'yes' if r['one_branch'] == '1' else 'no'} | "
                   f"{fmt(above, 0) if above > 0 else '—'} | {fmt(number(r, 'cap_excess_max'), 2, '°')} | "
                   f"{reacquire_text(number(r, 'reacquire_s'))} |")
    return out


def summary_table(summary):
    out = ["### Summary per variant × mode × threshold", "", SUMMARY_NOTES, "",
           "| variant | mode | thr | passes | RMS | worst p95 | worst max | motor cmds/pass | P sent/pass | "
           "mid-pass unwinds (avoidable) | worst cap excess | worst re-acquire s |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    groups = sorted({(r["variant"], r["mode"], r["threshold"]) for r in summary}, key=config_key)
    for g in groups:
        rows = [r for r in summary if (r["variant"], r["mode"], r["threshold"]) == g and number(r, "tracked_s") > 0]
        if not rows:
            continue
        rms = [number(r, "rms") for r in rows]
        unwound = [r for r in rows if r["unwound"] == "1"]
        capped = [r for r in rows if number(r, "above_cap_s") > 0]
        excess = max((number(r, "cap_excess_max") for r in capped), default=math.nan)
        reacquire = [number(r, "reacquire_s") for r in capped if not math.isnan(number(r, "reacquire_s"))]
        worst_reacquire = ("never" if any(v < 0 for v in reacquire) else f"{max(reacquire):.1f}") if reacquire else "—"
        out.append(f"| {g[0]} | {g[1]} | {g[2]}° | {len(rows)} | {span(rms, 2)} ({np.median(rms):.2f}) | "
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


def tables(summary, latency_sets, sweeps):
    out = per_pass_table(summary) + [""] + summary_table(summary) + [""] + latency_table(latency_sets)
    if sweeps:
        out += [""] + sweep_table(sweeps)
    return "\n".join(out) + "\n"


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    out_dir, image_dir = sys.argv[1], sys.argv[2]
    os.makedirs(image_dir, exist_ok=True)
    summary = read_csv(os.path.join(out_dir, "matrix", "summary.csv"))
    sweeps, latency_sets = {}, []
    matrix_latency = os.path.join(out_dir, "matrix", "latency.csv")
    if os.path.exists(matrix_latency):
        scale = {r["scale"] for r in summary}
        latency_sets.append((f"matrix {'/'.join(sorted(scale))}x", read_csv(matrix_latency)))
    for d in sorted(glob.glob(os.path.join(out_dir, "scale-*")), key=lambda d: float(d.rsplit("-", 1)[1])):
        path = os.path.join(d, "summary.csv")
        if os.path.exists(path):
            k = float(d.rsplit("-", 1)[1])
            sweeps[k] = read_csv(path)
            if os.path.exists(os.path.join(d, "latency.csv")):
                latency_sets.append((f"sweep {k:g}x", read_csv(os.path.join(d, "latency.csv"))))
    made = []
    for pass_name, variant in TRACE_PLOTS:
        name = plot_trace(os.path.join(out_dir, "matrix", "runs"), pass_name, variant, image_dir)
        if name:
            made.append(name)
    name = plot_summary(summary, image_dir)
    if name:
        made.append(name)
    if sweeps:
        made.append(plot_scale(sweeps, image_dir))
    with open(os.path.join(out_dir, "tables.md"), "w") as f:
        f.write(tables(summary, latency_sets, sweeps))
    print("plots:", ", ".join(os.path.join(image_dir, m) for m in made))
    print("tables:", os.path.join(out_dir, "tables.md"))


if __name__ == "__main__":
    main()
