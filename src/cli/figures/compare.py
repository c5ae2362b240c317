#!/usr/bin/env python3
"""Validation curves: Delta z(t) = z_CoG(small) - z_CoG(large) of a reference
(e.g. CFD-DEM) and of rcfd runs, from the CSV rcfd compare -o writes (the
reference's times, then one column per run; empty where a run has no data).

    python3 compare.py CURVES.csv -o CURVES.png [--window T0,T1] [--title TEXT] [--legend TEXT ...]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "curves CSV written by rcfd compare -o", ".png")
    parser.add_argument("--window", help="t0,t1 [s]: shade the window of the Eq. 7 means")
    parser.add_argument("--legend", action="append", default=[],
                        help="legend text of the next run (repeat; default: its column's name)")
    args = rf.parse(parser)

    table = rf.read_csv(args.csv)
    time = table["time_s"]
    runs = [name for name in table if name.startswith("delta_z_") and name != "delta_z_reference_m"]
    fig, ax = rf.plt.subplots(figsize=(7.5, 4.2))
    if args.window:
        t0, t1 = (float(t) for t in args.window.split(","))
        ax.axvspan(t0, t1, color="gray", alpha=0.12, lw=0, label="window of the Eq. 7 means")
    ax.plot(time, 1e3 * table["delta_z_reference_m"], color="black", lw=2.2, label="reference")
    for k, name in enumerate(runs):
        label = args.legend[k] if k < len(args.legend) else name[len("delta_z_"):-len("_m")]
        ax.plot(time, 1e3 * table[name], lw=1.3, label=label)
    ax.axhline(0.0, color="gray", lw=0.8)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("$\\Delta z = z_\\mathrm{CoG,small} - z_\\mathrm{CoG,large}$ [mm]")
    ax.set_xlim(time[0], time[-1])
    ax.set_title(args.title)
    rf.legend_outside(ax)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
