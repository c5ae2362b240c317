#!/usr/bin/env python3
"""The Pareto front of bench/pareto.sh: error against run time, one point per setting.

usage: pareto.py pareto.csv -o pareto.png [--markdown pareto.md]

A setting is on the front when no other is at least as fast and at least as accurate (RMS of
Delta z over the reference peak), and better in one of the two.  Fast is measured two ways: the
whole process (load, set-up and time loop) per simulated second, which the figure uses, and the
time loop alone per simulated second (the table marks both fronts).  The figure: RMS/peak (left)
and |Delta_seg| over 0.5-1.5 s (right) against the process's wall seconds per simulated second;
marker = space coarsening, colour = time stride, filled = drift every step, open = drift every 4
steps; the front (on RMS/peak) joined by a line.
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    for r in rows:
        for k in ("step_wall_per_sim_s", "process_wall_s", "peak_mb", "delta_seg_percent", "rms_over_peak", "kd",
                  "fit_rms_over_peak", "dt_rec_s"):
            r[k] = float(r[k])
        # The replay is one pass over the database: frames - 1 steps of dt_rec.
        r["process_per_sim_s"] = r["process_wall_s"] / ((int(r["frames"]) - 1) * r["dt_rec_s"])
    return rows


def front(rows, cost="process_per_sim_s", error="rms_over_peak"):
    """Indices of the settings no other one dominates."""
    on = []
    for i, a in enumerate(rows):
        dominated = any(b[cost] <= a[cost] and b[error] <= a[error] and (b[cost] < a[cost] or b[error] < a[error])
                        for j, b in enumerate(rows) if j != i)
        if not dominated:
            on.append(i)
    return sorted(on, key=lambda i: rows[i][cost])


def label(r):
    return f"{r['space']} / {r['stride']} / {r['drift_every']}" + ("" if r["precision"] == "full" else f" / {r['precision']}")


def markdown(rows, on, onLoop, path):
    lines = [
        "| space x×y×z | stride | drift every | precision | cells | frames | dt_rec [ms] | k_d [1/(m s)] | "
        "fit RMS/peak | loop wall s / sim. s | process wall [s] | process wall s / sim. s | peak [MB] | "
        "Δ_seg 0.5–1.5 s [%] | RMS/peak | front (process) | front (loop) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for i, r in enumerate(rows):
        lines.append(
            f"| {r['space']} | {r['stride']} | {r['drift_every']} | {r['precision']} | {r['cells']} | {r['frames']} | "
            f"{1e3 * r['dt_rec_s']:.0f} | {r['kd']:.3g} | {r['fit_rms_over_peak']:.3f} | "
            f"{r['step_wall_per_sim_s']:.4f} | {r['process_wall_s']:.2f} | {r['process_per_sim_s']:.3f} | "
            f"{r['peak_mb']:.0f} | {r['delta_seg_percent']:+.1f} | {r['rms_over_peak']:.3f} | "
            f"{'**yes**' if i in on else ''} | {'yes' if i in onLoop else ''} |")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("csv")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--markdown")
    a = p.parse_args()
    rows = read(a.csv)
    on = front(rows)
    if a.markdown:
        markdown(rows, on, front(rows, cost="step_wall_per_sim_s"), a.markdown)
    markers = {"1x1x1": "o", "2x1x1": "s", "1x1x2": "^", "2x1x2": "D"}
    colours = {"1": "tab:blue", "2": "tab:orange", "4": "tab:green"}
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    fig.subplots_adjust(left=0.07, right=0.98, top=0.92, bottom=0.22, wspace=0.2)
    for ax, key, name in ((axes[0], "rms_over_peak", "RMS of $\\Delta z$ / reference peak (0.2–3.49 s)"),
                          (axes[1], "delta_seg_percent", "$|\\Delta_{seg}|$ over 0.5–1.5 s [%]")):
        for r in rows:
            y = abs(r[key])
            filled = r["drift_every"] == "1"
            ax.scatter(r["process_per_sim_s"], y, marker=markers.get(r["space"], "x"), s=55,
                       facecolors=colours.get(r["stride"], "grey") if filled else "none",
                       edgecolors=colours.get(r["stride"], "grey"), linewidths=1.4, zorder=3)
        if key == "rms_over_peak":
            ax.plot([rows[i]["process_per_sim_s"] for i in on], [rows[i][key] for i in on], "k--", lw=1,
                    zorder=2, label="Pareto front (RMS/peak)")
            for k, i in enumerate(on): # labels alternately above and below the front
                ax.annotate(label(rows[i]), (rows[i]["process_per_sim_s"], rows[i][key]), fontsize=7,
                            xytext=(4, 6 if k % 2 == 0 else -12), textcoords="offset points")
        else:
            for i in on:
                ax.scatter(rows[i]["process_per_sim_s"], abs(rows[i][key]), s=160, facecolors="none",
                           edgecolors="k", lw=0.8, zorder=2)
        ax.set_xscale("log")
        ax.set_xlabel("wall seconds per simulated second, whole process (load included; one core)")
        ax.set_ylabel(name)
        ax.grid(True, which="both", alpha=0.3)
    # Legend: what markers, colours and fills mean.
    from matplotlib.lines import Line2D
    handles = [Line2D([], [], marker=m, ls="", color="k", mfc="none", label=f"space {s}") for s, m in markers.items()]
    handles += [Line2D([], [], marker="o", ls="", color=c, label=f"stride {s}") for s, c in colours.items()]
    handles += [Line2D([], [], marker="o", ls="", color="k", label="drift every step"),
                Line2D([], [], marker="o", ls="", color="k", mfc="none", label="drift every 4 steps"),
                Line2D([], [], ls="--", color="k", label="Pareto front (RMS/peak; circled right)")]
    fig.legend(handles=handles, fontsize=8, loc="lower center", ncol=6)
    fig.suptitle("dpm-bi-narrow: error against run time; drift B scaled by $(a/\\bar a)^2$, $k_d$ calibrated per "
                 "resolution on 0.2–1.7 s, scored on 0.2–3.49 s; labels: space / stride / drift every", fontsize=10)
    fig.savefig(a.output, dpi=120)


if __name__ == "__main__":
    main()
