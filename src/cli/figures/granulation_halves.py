#!/usr/bin/env python3
"""Paper Fig. 7: the size distribution of the bottom and top halves of the bed
in several granulator situations (e.g. no growth and no through-flow, growth
only, growth with through-flow), one panel per run, from each run's halves.csv.

    python3 granulation_halves.py A/halves.csv B/halves.csv ... --labels "a;b;..." -o fig.png
"""
import argparse

import rcfd_figure as rf
from halves import read_halves


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="+", help="halves.csv of each run")
    parser.add_argument("--labels", default="", help="panel titles separated by ; (default: the directories)")
    parser.add_argument("-o", "--output", required=True, help="PNG file")
    parser.add_argument("--title", default="", help="figure title")
    args = parser.parse_args()
    titles = args.labels.split(";") if args.labels else [p.rsplit("/", 2)[-2] for p in args.csv]
    fig, axes = rf.plt.subplots(1, len(args.csv), figsize=(3.6 * len(args.csv), 4.2), sharey=True, squeeze=False)
    for ax, path, title in zip(axes[0], args.csv, titles):
        labels, run = read_halves(path)
        x = rf.np.arange(len(labels))
        ax.bar(x - 0.2, run["bottom_mass_fraction"], 0.4, color="tab:blue", label="bottom half")
        ax.bar(x + 0.2, run["top_mass_fraction"], 0.4, color="tab:red", label="top half")
        ax.set_xticks(x, [text[1:].replace("mm", "") for text in labels], fontsize=8)
        ax.set_xlabel("class: diameter [mm]")
        ax.set_title(title, fontsize=10)
    axes[0][0].set_ylabel("mass fraction in the half [-]")
    axes[0][0].legend(loc="upper right", frameon=False)
    if args.title:
        fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
