#!/usr/bin/env python3
"""The number of entries into a zone within a time (rcfd markov
-markov_passes_time T): the probability of j entries for the bulk's chain and,
with --classes, each size class's beside it, with each chain's mean.  How
evenly particles pass a spray zone sets how evenly a coating or a granule
grows.

    python3 markov_passes.py DIR/passes_NAME.csv -o DIR/passes_NAME.png \\
        [--classes DIR/passes_NAME_CLASS.csv ...]
"""
import os

import numpy as np

import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "passes_NAME.csv written by rcfd markov", ".png")
    parser.add_argument("--classes", nargs="*", default=[],
                        help="passes_NAME_CLASS.csv of the size classes (drawn beside the bulk's)")
    args = rf.parse(parser)
    stem = os.path.splitext(os.path.basename(args.csv))[0]
    files = [args.csv] + args.classes
    # A class's label is what its file name adds to the bulk's (passes_spray_d1.459mm: d1.459mm).
    labels = ["bulk"] + [os.path.splitext(os.path.basename(f))[0][len(stem) + 1:] or f for f in args.classes]
    fig, ax = rf.plt.subplots(figsize=(7.2, 3.8))
    width = 0.8 / len(files)
    last = 0
    for n, (path, label) in enumerate(zip(files, labels)):
        c = rf.read_csv(path)
        j, p = c["passes"], c["probability"]
        mean = (j * p).sum()  # the last count holds "that many or more": a lower bound there
        ax.bar(j + (n - (len(files) - 1) / 2) * width, p, width, label=f"{label}: mean {mean:.3g}")
        reached = np.nonzero(np.cumsum(p) >= 0.999)[0]
        last = max(last, int(j[reached[0]]) if len(reached) else int(j[-1]))
    ax.set_xlim(-0.6, last + 0.6)
    ax.set_xlabel("entries into the zone (the last count: that many or more)")
    ax.set_ylabel("probability [-]")
    ax.legend(loc="upper right", fontsize="small")
    fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
