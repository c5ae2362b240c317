#!/usr/bin/env python3
"""Heat map of a database's recurrence matrix: the distance between the solid
volume fraction fields alpha_s of every pair of frames, divided by the
largest (0: the same field), from the CSV rcfd recurrence writes (K rows of
K numbers; row i, column j compares frames i and j).

    python3 recurrence.py DB-recurrence.csv -o DB-recurrence.png [--frame_dt S] [--norm N] [--title TEXT]
"""
import numpy as np

import rcfd_figure as rf

# How each of rcfd's -recurrence_norm choices compares two fields (sums over cells c).
DISTANCES = {
    "sqrDiff": "$\\sum_c (\\alpha_{s,c}^i - \\alpha_{s,c}^j)^2$",
    "euclidean": "$\\| \\alpha_s^i - \\alpha_s^j \\|_2$",
    "absDiff": "$\\sum_c |\\alpha_{s,c}^i - \\alpha_{s,c}^j|$",
    "max": "$\\max_c |\\alpha_{s,c}^i - \\alpha_{s,c}^j|$",
}


def main():
    parser = rf.arguments(__doc__, "DB-recurrence.csv written by rcfd recurrence DB.h5", ".png")
    parser.add_argument("--frame_dt", type=float, default=0.0,
                        help="time between frames [s]: axes in seconds (default: frame numbers)")
    parser.add_argument("--norm", default="sqrDiff", choices=sorted(DISTANCES), help="the matrix's norm")
    args = rf.parse(parser)

    matrix = np.loadtxt(args.csv, delimiter=",", comments="#", ndmin=2)
    frames = matrix.shape[0]
    if args.frame_dt > 0:
        extent = (0.0, frames * args.frame_dt)
        xlabel, ylabel = "time $t_j$ of frame $j$ [s]", "time $t_i$ of frame $i$ [s]"
    else:
        extent = (0, frames)
        xlabel, ylabel = "frame $j$ [-]", "frame $i$ [-]"
    fig, ax = rf.plt.subplots(figsize=(6.4, 5.4))
    image = ax.imshow(matrix, origin="lower", cmap="viridis", interpolation="nearest",
                      extent=(*extent, *extent), vmin=0.0, vmax=max(matrix.max(), 1e-300))
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(False)
    ax.set_title(args.title)
    bar = fig.colorbar(image, ax=ax, shrink=0.9)
    bar.set_label(DISTANCES[args.norm] + " / largest [-]")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
