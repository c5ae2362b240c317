#!/usr/bin/env python3
"""Segregation over time: Delta z = z_CoG(smallest fraction) - z_CoG(largest),
from a run's cog.csv (or, with a mean +- 1 sd band, from an ensemble.csv).

    python3 delta_z.py RUN/cog.csv -o RUN/cog-delta.png [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "cog.csv of rcfd run, or ensemble.csv of rcfd run -ensemble N", "-delta.png")
    args = rf.parse(parser)

    table = rf.read_csv(args.csv)
    values, spread = rf.series(table, "delta_z_m")
    fig, ax = rf.plt.subplots(figsize=(7.5, 4.2))
    label = "mean $\\pm$ 1 sd" if spread is not None else None
    rf.plot_band(ax, table["time_s"], values, spread, label)
    ax.axhline(0.0, color="gray", lw=0.8)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("$\\Delta z = z_\\mathrm{CoG,small} - z_\\mathrm{CoG,large}$ [mm]")
    ax.set_xlim(table["time_s"][0], table["time_s"][-1])
    ax.set_title(args.title)
    if label:
        ax.legend(loc="best")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
