#!/usr/bin/env python3
"""Where the bed is wet and hot, and for which sizes (docs/scalars.md): from a
run's scalar_profiles.csv (rcfd run -scalar_profiles), each scalar's value per
size class against height (top row) and each class's bed mean against its
diameter (bottom row), mass-weighted over the window; with --product, the
product's values (steady_state.csv of the granulator) marked on the right.

    python3 scalar_profiles.py RUN/scalar_profiles.csv -o RUN/scalar_profiles.png \
        [--scalars moisture,temperature] [--product RUN/steady_state.csv] [--title TEXT]
"""
import numpy as np

import rcfd_figure as rf

UNITS = {"moisture": "moisture $X$ [kg/kg]", "temperature": "temperature $T$ [K]"}


def main():
    parser = rf.arguments(__doc__, "scalar_profiles.csv of rcfd run -scalar_profiles", ".png")
    parser.add_argument("--scalars", default="", help="comma-separated scalars to draw (default: all)")
    parser.add_argument("--product", help="steady_state.csv of the run: the product's values, marked")
    args = rf.parse(parser)
    table = rf.read_csv(args.csv)
    labels = [name[len("mass_"):] for name in table if name.startswith("mass_")]
    names = [n for n in args.scalars.split(",") if n] or sorted(
        {name[: -len("_all")] for name in table if name.endswith("_all")})
    product = rf.read_csv(args.product) if args.product else None
    z = 1e3 * table["z"]
    mass = np.array([table["mass_" + label] for label in labels])  # [class, layer]
    solid = mass.sum(axis=0)
    held = solid > 1e-3 * solid.max()  # the freeboard's traces say nothing
    diameters = [float(label[1:-2]) for label in labels]
    fig, axes = rf.plt.subplots(2, len(names), figsize=(4.6 * len(names), 8.0), squeeze=False)
    colours = rf.plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, name in enumerate(names):
        ax, size = axes[0][k], axes[1][k]
        means = []
        for j, label in enumerate(labels):
            value = table[f"{name}_{label}"]
            ax.plot(np.where(held, value, np.nan), z, color=colours[j % len(colours)], lw=1.4,
                    label=f"$d$ = {label[1:-2]} mm")
            amount = np.nansum(np.where(mass[j] > 0, value * mass[j], 0.0))
            means.append(amount / mass[j].sum())
        ax.plot(np.where(held, table[f"{name}_all"], np.nan), z, color="black", lw=2.0, label="all sizes")
        ax.set_xlabel(UNITS.get(name, name))
        ax.set_ylabel("height $z$ [mm]")
        ax.set_ylim(0, z[held].max() + 2 * (z[1] - z[0]))
        size.plot(diameters, means, "o-", color="black", label="bed, per class")
        if product is not None and f"product_{name}" in product:
            size.axhline(product[f"product_{name}"][-1], color="tab:red", ls="--", label="product (discharged)")
        size.set_xlabel("particle diameter $d$ [mm]")
        size.set_ylabel(UNITS.get(name, name))
        size.legend(frameon=False)
    axes[0][0].legend(frameon=False, loc="best")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
