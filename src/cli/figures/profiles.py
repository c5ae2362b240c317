#!/usr/bin/env python3
"""Vertical profiles (paper Fig. 4): each fraction's volume fraction and the
total alpha_s per cell layer, averaged over the window and the cross-section,
from a run's profiles.csv; with --reference, the same from rcfd reference
(dashed).

    python3 profiles.py RUN/profiles.csv -o RUN/profiles.png [--reference REF/profiles.csv] [--title TEXT]
"""
import rcfd_figure as rf


def alpha_columns(table):
    return [name for name in table if name.startswith("alpha_") and name != "alpha_total"]


def label(column):
    core = column[len("alpha_"):]
    return f"$d$ = {core[1:-2]} mm" if core.startswith("d") and core.endswith("mm") else core


def main():
    parser = rf.arguments(__doc__, "profiles.csv of rcfd run -profiles", ".png")
    parser.add_argument("--reference-label", default="reference", help="legend name of the reference")
    parser.add_argument("--reference", help="profiles.csv of rcfd reference, drawn dashed")
    args = rf.parse(parser)

    run = rf.read_csv(args.csv)
    reference = rf.read_csv(args.reference) if args.reference else None
    fig, (ax, total) = rf.plt.subplots(1, 2, figsize=(8.5, 5.0), sharey=True,
                                       gridspec_kw={"width_ratios": [2, 1]})
    colours = rf.plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, column in enumerate(alpha_columns(run)):
        colour = colours[k % len(colours)]
        ax.plot(run[column], 1e3 * run["z"], color=colour, lw=1.5, label=label(column))
        if reference is not None and column in reference:
            ax.plot(reference[column], 1e3 * reference["z"], color=colour, lw=1.2, ls="--")
    total.plot(run["alpha_total"], 1e3 * run["z"], color="black", lw=1.5, label="this run")
    if reference is not None:
        # Fractions of the reference that this run does not have (another inventory): grey shades.
        others = [c for c in alpha_columns(reference) if c not in run]
        for k, column in enumerate(others):
            grey = str(0.25 + 0.45 * k / max(1, len(others) - 1))
            ax.plot(reference[column], 1e3 * reference["z"], color=grey, lw=1.2, ls="--",
                    label=f"{args.reference_label}: {label(column)}")
        if len(others) < len(alpha_columns(reference)):
            ax.plot([], [], color="gray", ls="--", label=f"{args.reference_label} (dashed)")
        total.plot(reference["alpha_total"], 1e3 * reference["z"], color="black", lw=1.2, ls="--",
                   label=args.reference_label)
    ax.set_xlabel("fraction's volume fraction $\\alpha_i$ [-]")
    ax.set_ylabel("height $z$ [mm]")
    total.set_xlabel("solid volume fraction $\\alpha_s$ [-]")
    ax.set_xlim(left=0)
    total.set_xlim(left=0)
    top = run["alpha_total"] > 1e-3 * max(run["alpha_total"].max(), 1e-30)
    if top.any():  # the freeboard above the bed says nothing: stop a little above the bed
        highest = 1e3 * run["z"][top].max()
        spacing = 1e3 * (run["z"][1] - run["z"][0]) if len(run["z"]) > 1 else highest
        ax.set_ylim(0, highest + 3 * spacing)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    if reference is not None:
        total.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), frameon=False)
    fig.suptitle(args.title or "vertical profiles, mean over the window and the cross-section")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
