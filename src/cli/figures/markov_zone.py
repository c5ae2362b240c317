#!/usr/bin/env python3
"""A zone's visits from a database's frames (rcfd markov -zones NAME): the
distribution of the time a visit lasts (residence) and of the time outside
between leaving the zone and entering it again (away), computed exactly from
the chain, with their means.  With --particles, the same distributions from the
particle trajectories (rcfd reference -zones NAME) beside them; the means are
then both taken over the times the particles could show (up to their last
time), with the probability each puts there.

    python3 markov_zone.py DIR/zone_NAME.csv -o DIR/zone_NAME.png [--particles REF/zone_NAME.csv]
"""
import numpy as np

import rcfd_figure as rf


def summary(t, p, upto):
    keep = t <= upto * (1 + 1e-9)
    mass = p[keep].sum()
    mean = (t[keep] * p[keep]).sum() / max(mass, 1e-300)
    return mean, mass


def main():
    parser = rf.arguments(__doc__, "zone_NAME.csv written by rcfd markov", ".png")
    parser.add_argument("--particles", help="zone_NAME.csv written by rcfd reference -zones (drawn beside the chain's)")
    args = rf.parse(parser)
    c = rf.read_csv(args.csv)
    r = rf.read_csv(args.particles) if args.particles else None
    t = c["time"]
    dt = t[0] if len(t) else 1.0
    fig, axes = rf.plt.subplots(1, 2, figsize=(9.6, 3.8))
    for ax, name, label in zip(axes, ("residence", "away"), ("time in the zone per visit", "time away between visits")):
        p = c[name]
        upto = np.inf
        if r is not None:  # the particles' last time given for this distribution
            upto = r["time"][np.isfinite(r[name])][-1]
        mean, mass = summary(t, p, upto)
        within = "" if r is None else f" within {upto:.3g} s"
        ax.plot(t, p / dt, label=f"chain: mean {mean:.3g} s, P {mass:.3f}{within}")
        right = None
        reached = np.nonzero(np.cumsum(p) >= 0.999 * p.sum())[0]
        if p.sum() > 0 and len(reached):
            right = t[reached[0]]  # up to where 99.9 % of the absorbed have ended
        if r is not None:
            given = np.isfinite(r[name])
            tr, pr = r["time"][given], r[name][given]
            rdt = tr[0] if len(tr) else 1.0
            mean, mass = summary(tr, pr, upto)
            ax.plot(tr, pr / rdt, label=f"particles: mean {mean:.3g} s, P {mass:.3f}", alpha=0.8)
            right = min(right, upto) if right is not None else upto
        if right is not None:
            ax.set_xlim(0, right)
        ax.set_xlabel(label + " [s]")
        ax.set_ylabel("probability density [1/s]")
        bottom, top = ax.get_ylim()
        ax.set_ylim(bottom, top + 0.3 * (top - bottom))  # room for the legend above the curves
        ax.legend(loc="upper right", fontsize="small")
    fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
