#!/usr/bin/env python3
"""Size distributions of the bed's bottom and top halves of a reference and of
rcfd runs (paper Fig. 6): mass fraction of each class against d_i / d32, d32
the Sauter diameter of each file's whole bed, from the halves.csv files that
rcfd reference and rcfd run write (class, diameter [m], bottom_mass_fraction,
top_mass_fraction; time means over a window).

    python3 compare_halves.py REF.csv RUN.csv [RUN.csv ...] -o FIG.png [--label TEXT ...] [--title TEXT]
"""
import rcfd_figure as rf


def read_halves(path):
    """(diameter [m], bottom and top mass fractions) of a halves.csv; the class
    column holds text, so it is skipped."""
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    header = [name.strip() for name in lines[0].split(",")]
    rows = [line.split(",") for line in lines[1:]]
    column = {name: rf.np.array([float(row[i]) for row in rows]) for i, name in enumerate(header) if i > 0}
    return column["diameter"], column["bottom_mass_fraction"], column["top_mass_fraction"]


def main():
    parser = rf.arguments(__doc__, "reference halves.csv", "-compare.png")
    parser.add_argument("runs", nargs="+", help="halves.csv of each run")
    parser.add_argument("--label", action="append", default=[], help="legend text of the next run (repeat)")
    args = rf.parse(parser)

    fig, axes = rf.plt.subplots(1, 2, figsize=(8.5, 3.8), sharey=True)
    for k, path in enumerate([args.csv] + args.runs):
        d, bottom, top = read_halves(path)
        d32 = 1.0 / rf.np.sum(0.5 * (bottom + top) / d)  # the halves hold equal masses
        if k == 0:
            label, style = "reference", {"color": "black", "lw": 2.2, "marker": "s"}
        else:
            label = args.label[k - 1] if k - 1 < len(args.label) else path
            style = {"lw": 1.3, "marker": "o"}
        for ax, fraction in zip(axes, (bottom, top)):
            ax.plot(d / d32, fraction, label=label, **style)
    for ax, half in zip(axes, ("bottom half", "top half")):
        ax.set_title(half, fontsize=10)
        ax.set_xlabel("$d_i / d_{32}$")
        ax.set_ylim(bottom=0.0)
    axes[0].set_ylabel("mass fraction")
    fig.suptitle(args.title)
    rf.legend_outside(axes[-1])
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
