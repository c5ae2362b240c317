#!/usr/bin/env python3
"""Mid-plane snapshots (paper Fig. 1): one fraction's volume fraction in the
vertical mid-plane at each snapshot time, from a run's snapshot_<t>s.csv files.

    python3 snapshots.py RUN/snapshot_1.0000s.csv [RUN/snapshot_2.0000s.csv ...] -o RUN/snapshots.png
        [--fraction d1.459mm | total] [--title TEXT]
"""
import argparse
import os
import re

import rcfd_figure as rf


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", nargs="+", help="snapshot_<t>s.csv files of rcfd run -snapshots_times")
    parser.add_argument("-o", "--output", required=True, help="PNG file")
    parser.add_argument("--fraction", default="", help="column after alpha_ (default: the smallest fraction)")
    parser.add_argument("--title", default="")
    args = parser.parse_args()

    args.csv.sort(key=snapshot_time)  # in time order, whatever order the shell listed them in
    tables = [rf.read_csv(path) for path in args.csv]
    names = list(tables[0])
    across, up = names[0], names[1]
    fractions = [n for n in names[2:] if n != "alpha_total"]
    column = "alpha_" + args.fraction if args.fraction else fractions[0]
    if column not in tables[0]:
        raise SystemExit(f"{args.csv[0]}: no column {column}; have {', '.join(names[2:])}")
    vmax = max(t[column].max() for t in tables) or 1.0
    # The freeboard above the bed is empty: show the bed and a margin above it.
    filled = [t[up][t["alpha_total"] > 1e-2] for t in tables]
    top = max((f.max() for f in filled if f.size), default=tables[0][up].max())
    top = min(1.25 * top, 1.01 * tables[0][up].max())
    width = tables[0][across].max() - tables[0][across].min()
    panel = 2.2  # inches per snapshot
    height = min(8.0, panel * top / max(width, 1e-12))
    fig, axes = rf.plt.subplots(1, len(tables), figsize=(1.6 + panel * len(tables), 1.3 + height), sharey=True,
                                squeeze=False, layout="constrained")
    for ax, table, path in zip(axes[0], tables, args.csv):
        xs, zs = rf.np.unique(table[across]), rf.np.unique(table[up])
        grid = rf.np.full((zs.size, xs.size), rf.np.nan)
        grid[rf.np.searchsorted(zs, table[up]), rf.np.searchsorted(xs, table[across])] = table[column]
        ax.grid(False)
        image = ax.pcolormesh(1e3 * edges(xs), 1e3 * edges(zs), grid, cmap="viridis", vmin=0, vmax=vmax,
                              shading="flat")
        ax.set_aspect("equal")
        t = snapshot_time(path)
        ax.set_title(f"$t$ = {t:g} s" if t != float("inf") else os.path.basename(path))
        ax.set_xlabel(f"{across[:-2]} [mm]")
    axes[0][0].set_ylabel(f"{up[:-2]} [mm]")
    axes[0][0].set_ylim(0, 1e3 * top)
    name = column[len("alpha_"):]
    pretty = f"$d$ = {name[1:-2]} mm" if name.startswith("d") and name.endswith("mm") else name
    fig.colorbar(image, ax=axes[0].tolist(), shrink=0.9, label=f"volume fraction $\\alpha$ of {pretty} [-]")
    fig.suptitle(args.title or "vertical mid-plane of the bed")
    rf.save(fig, args.output)


def snapshot_time(path):
    """The time in a snapshot_<t>s.csv name (infinity for another name)."""
    match = re.search(r"snapshot_([0-9.]+)s", os.path.basename(path))
    return float(match.group(1)) if match else float("inf")


def edges(centres):
    """Cell edges from equally spaced centres."""
    h = centres[1] - centres[0] if centres.size > 1 else 1.0
    return rf.np.append(centres - h / 2, centres[-1] + h / 2)


if __name__ == "__main__":
    main()
