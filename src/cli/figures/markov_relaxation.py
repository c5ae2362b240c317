#!/usr/bin/env python3
"""Tracer mixing from a database's frames (rcfd markov): the deviation of the
tracer concentration from the bed mean, max over the counted cells of
|c_i - 1|, against time, the mean and the worst over the start cells, with the
averaged chain's decay |lambda2|^n and the mixing tolerance.

    python3 markov_relaxation.py DIR/relaxation.csv -o DIR/relaxation.png [--tolerance 0.05] [--relaxation_time S]
"""
import numpy as np

import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "relaxation.csv written by rcfd markov", ".png")
    parser.add_argument("--tolerance", type=float, default=0.05, help="the mixing tolerance (a line)")
    parser.add_argument("--relaxation_time", type=float, default=0.0, help="-dt/ln|lambda2| [s], for the legend")
    args = rf.parse(parser)
    c = rf.read_csv(args.csv)
    fig, ax = rf.plt.subplots(figsize=(6.4, 4.2))
    ax.semilogy(c["time"], c["worst_deviation"], label="worst start cell")
    ax.semilogy(c["time"], c["mean_deviation"], label="mean over start cells")
    label = "$|\\lambda_2|^n$" + (f" ($\\tau$ = {args.relaxation_time:.3g} s)" if args.relaxation_time > 0 else "")
    ax.semilogy(c["time"], np.maximum(c["lambda2_decay"], 1e-300), "--", label=label)
    ax.axhline(args.tolerance, color="grey", lw=0.8, label=f"tolerance {args.tolerance:g}")
    ax.set_xlabel("time since the tracer was placed [s]")
    ax.set_ylabel("max$_i$ |tracer share / solid share - 1| [-]")
    ax.set_ylim(bottom=max(1e-4, np.nanmin(c["mean_deviation"]) / 2))
    ax.legend()
    ax.set_title(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
