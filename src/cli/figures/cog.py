#!/usr/bin/env python3
"""Centres of gravity of the bed and of every fraction over time, from a
run's cog.csv (or, with mean +- 1 sd bands, from an ensemble.csv).

    python3 cog.py RUN/cog.csv -o RUN/cog.png [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "cog.csv of rcfd run, or ensemble.csv of rcfd run -ensemble N", ".png")
    args = rf.parse(parser)

    table = rf.read_csv(args.csv)
    fig, ax = rf.plt.subplots(figsize=(7.5, 4.2))
    for column in rf.cog_columns(table):
        values, spread = rf.series(table, column)
        bed = {"color": "black", "lw": 1.0, "ls": "--", "band_alpha": 0.1}  # the bed in the background
        style = bed if column == "z_cog_bed_m" else {}
        rf.plot_band(ax, table["time_s"], values, spread, rf.fraction_label(column), **style)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("centre of gravity $z_\\mathrm{CoG}$ [mm]")
    ax.set_xlim(table["time_s"][0], table["time_s"][-1])
    title = args.title
    if rf.is_ensemble(table):
        note = "mean $\\pm$ 1 sd of the ensemble"
        title = f"{title} ({note})" if title else note
    ax.set_title(title)
    rf.legend_outside(ax)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
