#!/usr/bin/env python3
"""A zone's visits from a database's frames (rcfd markov -zones NAME): the
distribution of the time a visit lasts (residence) and of the time outside
between leaving the zone and entering it again (away), computed exactly from
the chain, with their means.

    python3 markov_zone.py DIR/zone_NAME.csv -o DIR/zone_NAME.png
"""
import numpy as np

import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "zone_NAME.csv written by rcfd markov", ".png")
    args = rf.parse(parser)
    c = rf.read_csv(args.csv)
    t = c["time"]
    dt = t[0] if len(t) else 1.0
    fig, axes = rf.plt.subplots(1, 2, figsize=(9.6, 3.8))
    for ax, name, label in zip(axes, ("residence", "away"), ("time in the zone per visit", "time away between visits")):
        p = c[name]
        mean = (t * p).sum() / max(p.sum(), 1e-300)
        ax.plot(t, p / dt, label=f"mean {mean:.3g} s, absorbed {p.sum():.4f}")
        ax.set_xlabel(label + " [s]")
        ax.set_ylabel("probability density [1/s]")
        reached = np.nonzero(np.cumsum(p) >= 0.999 * p.sum())[0]
        if p.sum() > 0 and len(reached):
            ax.set_xlim(0, t[reached[0]])  # up to where 99.9 % of the absorbed have ended
        ax.legend()
    fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
