#!/usr/bin/env python3
"""Vertical profiles of a reference and of rcfd runs (paper Fig. 4): each size
class's solid volume fraction and alpha_total against height, from the
profiles.csv files that rcfd reference and rcfd run write (z, alpha_d<D>mm...,
alpha_total; time means over a window).  A class a run lacks is left out of
its panel.

    python3 compare_profiles.py REF.csv RUN.csv [RUN.csv ...] -o FIG.png [--label TEXT ...] [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "reference profiles.csv", "-compare.png")
    parser.add_argument("runs", nargs="+", help="profiles.csv of each run")
    parser.add_argument("--label", action="append", default=[], help="legend text of the next run (repeat)")
    args = rf.parse(parser)

    ref = rf.read_csv(args.csv)
    runs = [rf.read_csv(path) for path in args.runs]
    curves = [name for name in ref if name.startswith("alpha_")]
    top = max(max(table["z"][table["alpha_total"] > 0], default=0.0) for table in [ref] + runs)
    fig, axes = rf.plt.subplots(1, len(curves), figsize=(2.6 * len(curves) + 1.5, 4.6), sharey=True)
    for ax, curve in zip(axes, curves):
        ax.plot(ref[curve], 1e3 * ref["z"], color="black", lw=2.2, label="reference")
        for k, table in enumerate(runs):
            if curve in table:
                label = args.label[k] if k < len(args.label) else args.runs[k]
                ax.plot(table[curve], 1e3 * table["z"], lw=1.3, label=label)
        name = curve[len("alpha_"):]
        ax.set_title("all sizes" if name == "total" else rf.fraction_label("z_cog_" + name), fontsize=10)
        ax.set_xlabel("solid volume fraction $\\alpha$")
        ax.set_xlim(left=0.0)
    axes[0].set_ylabel("height $z$ [mm]")
    axes[0].set_ylim(0.0, 1e3 * top * 1.1 if top > 0 else None)
    fig.suptitle(args.title)
    rf.legend_outside(axes[-1])
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
