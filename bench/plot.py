#!/usr/bin/python3
"""Turns tracking_bench's CSV output into the PNG plots and markdown tables of docs/benchmarks.md.

    /usr/bin/python3 bench/plot.py <bench-out-dir> <image-dir>

<bench-out-dir> holds matrix/ (the full run) and scale-<k>/ (the scale sweep), as
scripts/benchmark.sh lays them out. Writes PNGs into <image-dir> and tables.md into <bench-out-dir>.
Needs Debian's python3-matplotlib and python3-numpy.
"""
import csv
import glob
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# Traces worth a picture: the keyhole pass on both dishes and a north-crossing pass.
TRACE_PLOTS = [("iss-85", "hal205"), ("iss-85", "g2"), ("iss-45", "g2"), ("sso-70", "hal205")]
VARIANT_LABEL = {"g2": "Carryout G2", "hal205": "Trav'ler HAL 2.05"}
# Mechanical azimuth window and elevation limits (README, sim/README.md) for the unwind verdict.
AZ_WINDOW = {"g2": (-423.33, 23.33), "hal205": (0.0, 455.0)}
EL_MIN = {"g2": 18.0, "hal205": 15.0}
PASSES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "passes")


def unwind_avoidable(pass_name, variant):
    """True when one continuous azimuth branch inside the dish's window covers the whole measured
    stretch of the pass (from EL_MIN - 6 to EL_MIN, as tracking_bench runs it): then an unwind is
    the backend's choice, not the geometry's."""
    t, az, el = [], [], []
    with open(os.path.join(PASSES_DIR, pass_name + ".csv")) as f:
        for line in f:
            if line[0] in "#t":
                continue
            a, b, c = (float(x) for x in line.split(","))
            t.append(a), az.append(b), el.append(c)
    el = np.array(el)
    above = np.where(el >= EL_MIN[variant] - 6.0)[0]
    inside = np.where(el >= EL_MIN[variant])[0]
    if len(inside) == 0:
        return True
    track = unwrap_deg(np.array(az[above[0]:inside[-1] + 1]))
    lo, hi = track.min(), track.max()
    w_lo, w_hi = AZ_WINDOW[variant]
    return any(lo + n * 360.0 >= w_lo and hi + n * 360.0 <= w_hi for n in range(-3, 4))


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def column(rows, key):
    return np.array([float(r[key]) for r in rows])


def unwrap_deg(values):
    return np.degrees(np.unwrap(np.radians(values)))


def plot_trace(runs_dir, pass_name, variant, image_dir):
    fig, axes = plt.subplots(3, 1, figsize=(10, 9), sharex=True)
    drew = False
    for mode, thr, style in [("none", "0.5", "-"), ("leapfrog", "0.5", "--"), ("none", "5", ":")]:
        path = os.path.join(runs_dir, f"{pass_name}_{variant}_{mode}_thr{thr}.csv")
        if not os.path.exists(path):
            continue
        rows = read_csv(path)
        t = column(rows, "t")
        if not drew:
            axes[0].plot(t, column(rows, "sat_az"), color="black", lw=2.5, alpha=0.35, label="satellite")
            axes[1].plot(t, column(rows, "sat_el"), color="black", lw=2.5, alpha=0.35, label="satellite")
            drew = True
        label = f"dish, {mode}, threshold {thr}°"
        axes[0].plot(t, column(rows, "dish_az"), style, lw=1, label=label)
        axes[1].plot(t, column(rows, "dish_el"), style, lw=1, label=label)
        error = np.where(column(rows, "in_limits") > 0, column(rows, "error_deg"), np.nan)
        axes[2].plot(t, error, style, lw=1, label=label)
    if not drew:
        plt.close(fig)
        return None
    axes[0].set_ylabel("azimuth (°, displayed 0..360)")
    axes[1].set_ylabel("elevation (°)")
    axes[2].set_ylabel("pointing error (°)\n(inside the EL limits)")
    axes[2].set_xlabel("pass time (s)")
    axes[2].set_yscale("log")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(f"{pass_name} on the {VARIANT_LABEL.get(variant, variant)}: target vs true dish position")
    fig.tight_layout()
    name = f"track_{pass_name}_{variant}.png"
    fig.savefig(os.path.join(image_dir, name), dpi=90)
    plt.close(fig)
    return name


def plot_summary(summary, image_dir):
    passes = sorted({r["pass"] for r in summary})
    configs = sorted({(r["variant"], r["mode"], r["threshold"]) for r in summary},
                     key=lambda c: (c[0], float(c[2]), c[1]))
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), sharey=False)
    for ax, variant in zip(axes, ["g2", "hal205"]):
        mine = [c for c in configs if c[0] == variant]
        width = 0.8 / max(1, len(mine))
        for i, (v, mode, thr) in enumerate(mine):
            rms = []
            for p in passes:
                row = next((r for r in summary if r["pass"] == p and r["variant"] == v and r["mode"] == mode
                            and r["threshold"] == thr), None)
                rms.append(float(row["rms"]) if row and float(row["tracked_s"]) > 0 else np.nan)
            ax.bar(np.arange(len(passes)) + i * width, rms, width, label=f"{mode}, thr {thr}°")
        ax.set_xticks(np.arange(len(passes)) + 0.4 - width / 2)
        ax.set_xticklabels(passes, rotation=30)
        ax.set_title(VARIANT_LABEL[variant])
        ax.set_ylabel("RMS pointing error (°)")
        ax.axhline(0.25, color="green", lw=0.8, ls="--", label="goal 0.25° (thr 0.5)")
        ax.axhline(1.5, color="orange", lw=0.8, ls="--", label="goal 1.5° (thr 5)")
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "rms_by_pass.png"), dpi=90)
    plt.close(fig)


def plot_scale(sweeps, image_dir):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for variant in ["g2", "hal205"]:
        ks, rms, perr = [], [], []
        for k, rows in sorted(sweeps.items()):
            row = next((r for r in rows if r["variant"] == variant), None)
            if row:
                ks.append(k)
                rms.append(float(row["rms"]))
                perr.append(float(row["p_error_p95_deg"]))
        axes[0].plot(ks, rms, "o-", label=VARIANT_LABEL[variant])
        axes[1].plot(ks, perr, "o-", label=VARIANT_LABEL[variant])
    axes[0].set_ylabel("RMS pointing error (°)")
    axes[1].set_ylabel("p95 |reported − true| position (°)")
    for ax in axes:
        ax.set_xlabel("time scale k (simulated s per real s)")
        ax.set_xscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Scale sensitivity: iss-70, 120 s around TCA, no compensation, threshold 0.5°")
    fig.tight_layout()
    fig.savefig(os.path.join(image_dir, "scale_sensitivity.png"), dpi=90)
    plt.close(fig)


def tables(summary, sweeps):
    out = ["### Per pass (error in degrees while the satellite is inside the dish's EL limits)", "",
           "| pass | peak | N-cross | variant | mode | thr | tracked s | RMS | p95 | max | motor cmds | P sent | extra AZ travel | unwound | avoidable |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in sorted(summary, key=lambda r: (r["variant"], r["pass"], float(r["threshold"]), r["mode"])):
        tracked = float(r["tracked_s"]) > 0
        fmt = (lambda k: f"{float(r[k]):.2f}") if tracked else (lambda k: "–")
        out.append(f"| {r['pass']} | {float(r['peak_el']):.0f}° | {'yes' if r['crosses_north'] == '1' else 'no'} | "
                   f"{r['variant']} | {r['mode']} | {r['threshold']}° | {float(r['tracked_s']):.0f} | {fmt('rms')} | "
                   f"{fmt('p95')} | {fmt('max')} | {r['motor_commands']} | {r['set_commands']} | "
                   f"{float(r['extra_az_travel']):.0f}° | {'**yes**' if r['unwound'] == '1' else 'no'} | "
                   f"{'yes' if unwind_avoidable(r['pass'], r['variant']) else 'no'} |")
    out += ["", "### Aggregated over the passes (worst pass RMS / median of per-pass RMS / worst max)", "",
            "| variant | mode | thr | worst RMS | median RMS | worst p95 | worst max | motor cmds/pass (median) | unwinds (avoidable) |",
            "|---|---|---|---|---|---|---|---|---|"]
    groups = sorted({(r["variant"], r["mode"], r["threshold"]) for r in summary}, key=lambda g: (g[0], float(g[2]), g[1]))
    for g in groups:
        rows = [r for r in summary if (r["variant"], r["mode"], r["threshold"]) == g and float(r["tracked_s"]) > 0]
        if not rows:
            continue
        rms = [float(r["rms"]) for r in rows]
        out.append(f"| {g[0]} | {g[1]} | {g[2]}° | {max(rms):.2f} | {np.median(rms):.2f} | "
                   f"{max(float(r['p95']) for r in rows):.2f} | {max(float(r['max']) for r in rows):.2f} | "
                   f"{np.median([int(r['motor_commands']) for r in rows]):.0f} | "
                   f"{sum(int(r['unwound']) for r in rows)} of {len(rows)} "
                   f"({sum(int(r['unwound']) for r in rows if unwind_avoidable(r['pass'], r['variant']))}) |")
    out += ["", "### Latency through rotctld (ms, per run, pooled as max over runs of each percentile)", "",
            "| source | variant | p median | p p99 | p max | P median | P p99 | P max | wire floor `a` | reported-vs-true p95 |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    for label, rows_all in [("matrix", summary)] + [(f"scale {k}x", rows) for k, rows in sorted(sweeps.items())]:
        for v in ["g2", "hal205"]:
            rows = [r for r in rows_all if r["variant"] == v]
            if not rows:
                continue
            worst = lambda k: max(float(r[k]) for r in rows)  # noqa: E731
            med = lambda k: float(np.median([float(r[k]) for r in rows]))  # noqa: E731
            out.append(f"| {label} | {v} | {med('p_median_ms'):.3f} | {worst('p_p99_ms'):.3f} | {worst('p_max_ms'):.3f} | "
                       f"{med('P_median_ms'):.3f} | {worst('P_p99_ms'):.3f} | {worst('P_max_ms'):.3f} | "
                       f"{float(rows[0]['wire_floor_ms']):.2f} | {worst('p_error_p95_deg'):.3f}° |")
    out += ["", "### Scale sweep (iss-70, 120 s around TCA, none, threshold 0.5°)", "",
            "| k | variant | RMS | p95 | max | motor cmds | reported-vs-true p95 |", "|---|---|---|---|---|---|---|"]
    for k, rows in sorted(sweeps.items()):
        for r in sorted(rows, key=lambda r: r["variant"]):
            out.append(f"| {k:g} | {r['variant']} | {float(r['rms']):.2f} | {float(r['p95']):.2f} | {float(r['max']):.2f} | "
                       f"{r['motor_commands']} | {float(r['p_error_p95_deg']):.2f}° |")
    return "\n".join(out) + "\n"


def main():
    out_dir, image_dir = sys.argv[1], sys.argv[2]
    os.makedirs(image_dir, exist_ok=True)
    summary = read_csv(os.path.join(out_dir, "matrix", "summary.csv"))
    sweeps = {}
    for d in glob.glob(os.path.join(out_dir, "scale-*")):
        path = os.path.join(d, "summary.csv")
        if os.path.exists(path):
            sweeps[float(d.rsplit("-", 1)[1])] = read_csv(path)
    made = []
    for pass_name, variant in TRACE_PLOTS:
        name = plot_trace(os.path.join(out_dir, "matrix", "runs"), pass_name, variant, image_dir)
        if name:
            made.append(name)
    plot_summary(summary, image_dir)
    made.append("rms_by_pass.png")
    if sweeps:
        plot_scale(sweeps, image_dir)
        made.append("scale_sensitivity.png")
    with open(os.path.join(out_dir, "tables.md"), "w") as f:
        f.write(tables(summary, sweeps))
    print("plots:", ", ".join(os.path.join(image_dir, m) for m in made))
    print("tables:", os.path.join(out_dir, "tables.md"))


if __name__ == "__main__":
    main()
