#!/usr/bin/env python3
"""Where the solid lives at frame 0 by the period chain (rcfd markov
-markov_spectrum period): the share of each distribution per cell layer against
height, frame 0's mass share, the bulk's periodic stationary distribution and
each size class's. With --profiles, a run's profiles.csv (rcfd run -profiles
-profiles_window T,T at T a multiple of the period) is drawn dashed beside the
classes, each class's alpha per layer over its sum, and the two are compared:
the L1 distance over the layers and the centres' heights (printed).

    python3 markov_stationary.py DIR/stationary.csv -o DIR/stationary.png [--profiles RUN/profiles.csv]

Layers are the cells' z (a box with gravity along -z, as the database's beds).
"""
import numpy as np

import rcfd_figure as rf


def layers(table, column):
    """Per distinct z (rounded to 1e-9 m), the sum of `column` over the layer's cells."""
    z = np.round(np.asarray(table["z"], dtype=float), 9)
    values = np.asarray(table[column], dtype=float)
    heights = np.unique(z)
    return heights, np.array([values[z == h].sum() for h in heights])


def centre(z, share):
    return float((z * share).sum() / share.sum())


def main():
    parser = rf.arguments(__doc__, "stationary.csv written by rcfd markov -markov_spectrum period", ".png")
    parser.add_argument("--profiles", default="", help="a run's profiles.csv at a multiple of the period, to compare")
    args = rf.parse(parser)
    c = rf.read_csv(args.csv)
    classes = [name[len("period_stationary_"):] for name in c if name.startswith("period_stationary_")
               and name != "period_stationary_share"]
    run = rf.read_csv(args.profiles) if args.profiles else None
    fig, ax = rf.plt.subplots(figsize=(5.2, 5.6))
    z, frame0 = layers(c, "frame0_share")
    _, bulk = layers(c, "period_stationary_share")
    keep = (frame0 > 0) | (bulk > 0)
    last = np.nonzero(keep)[0].max() + 1 if keep.any() else len(z)
    z, frame0, bulk = z[:last], frame0[:last], bulk[:last]
    ax.plot(frame0, z, color="grey", lw=3, alpha=0.5, label="frame 0's mass share")
    ax.plot(bulk, z, color="black", label=f"bulk, period chain (centre {centre(z, bulk):.4f} m)")
    if run is not None:
        print(f"bulk: centre {centre(z, bulk):.4f} m, frame 0's {centre(z, frame0):.4f} m, "
              f"L1 over layers {np.abs(bulk - frame0).sum():.3g}")
    for i, name in enumerate(classes):
        colour = f"C{i}"
        _, share = layers(c, "period_stationary_" + name)
        share = share[:last]
        ax.plot(share, z, color=colour, label=f"{name}, period chain ({centre(z, share):.4f} m)")
        column = "alpha_" + name
        if run is None or column not in run:
            continue
        rz = np.asarray(run["z"], dtype=float)
        ra = np.asarray(run[column], dtype=float)
        # The run's layer of each of the chain's layers (the same mesh: the same centres).
        theirs = np.array([ra[np.argmin(np.abs(rz - h))] for h in z])
        theirs = theirs / ra.sum()
        ax.plot(theirs, z, "--", color=colour, label=f"{name}, run ({centre(z, theirs):.4f} m)")
        print(f"{name}: centre {centre(z, share):.4f} m (chain) against {centre(z, theirs):.4f} m (run); "
              f"L1 over layers {np.abs(share - theirs).sum():.3g}")
    ax.set_xlabel("share of the distribution per cell layer [-]")
    ax.set_ylabel("height of the layer's centre [m]")
    ax.set_xlim(left=0)
    ax.legend(fontsize=8)
    ax.set_title(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
