"""Delta z against time for the four sequence-length settings, one panel per carry kind.

usage: python3 bench/stitch_lengths.py SERIES_CSV OUT_PNG
SERIES_CSV: bench/results/stitch_lengths_series.csv (bench/stitch_lengths.sh writes it).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = list(csv.DictReader(open(sys.argv[1])))
carries = list(dict.fromkeys(r["carry"] for r in rows))
names = {"remap": "remap (before)", "column": "column (default now)", "column-bed": "column, whole bed one column"}
fig, axes = plt.subplots(1, len(carries), figsize=(4.6 * len(carries), 3.6), sharey=True, squeeze=False)
for ax, carry in zip(axes[0], carries):
    mine = [r for r in rows if r["carry"] == carry]
    for lengths in dict.fromkeys((r["min_length"], r["max_length"]) for r in mine):
        curve = [r for r in mine if (r["min_length"], r["max_length"]) == lengths]
        ax.plot([float(r["time_s"]) for r in curve], [float(r["delta_z_mm"]) for r in curve],
                label=f"{lengths[0]}-{lengths[1]} frames")
    ax.axvspan(75, 150, color="0.92", zorder=0)
    ax.set_title(f"{names.get(carry, carry)}, mean of {mine[0]['seeds']} seed(s)", fontsize=10)
    ax.set_xlabel("t [s]")
    ax.grid(alpha=0.3)
axes[0][0].set_ylabel(r"$\Delta z$ [mm] (1 s means)")
axes[0][0].legend(fontsize=8, title="sequence lengths", title_fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
