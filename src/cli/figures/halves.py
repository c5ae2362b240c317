#!/usr/bin/env python3
"""Size distribution of the bottom and top halves of the bed (paper Fig. 6):
each class's mass fraction against d_i / d32 of the inventory, from a run's
halves.csv; with --reference, rcfd reference's halves.csv as open markers.

    python3 halves.py RUN/halves.csv -o RUN/halves.png [--reference REF/halves.csv] [--title TEXT]
"""
import rcfd_figure as rf


def read_halves(path):
    """(class labels, columns by name) of a halves.csv (its first column is text)."""
    with open(path) as f:
        lines = [line.strip() for line in f if line.strip() and not line.startswith("#")]
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    columns = {name: rf.np.array([float(r[i]) for r in rows]) for i, name in enumerate(header) if i > 0}
    return [r[0] for r in rows], columns


def main():
    parser = rf.arguments(__doc__, "halves.csv of rcfd run -halves", ".png")
    parser.add_argument("--reference-label", default="reference", help="legend name of the reference")
    parser.add_argument("--reference", help="halves.csv of rcfd reference")
    args = rf.parse(parser)

    labels, run = read_halves(args.csv)
    ratio = run["d_over_d32"]
    d32 = rf.np.median(run["diameter"] / ratio)
    fig, ax = rf.plt.subplots(figsize=(7.0, 5.0))
    ax.plot(ratio, run["bottom_mass_fraction"], "o-", color="tab:blue", label="bottom half")
    ax.plot(ratio, run["top_mass_fraction"], "s-", color="tab:red", label="top half")
    if args.reference:
        _, ref = read_halves(args.reference)
        ref_ratio = ref["d_over_d32"] if "d_over_d32" in ref else ref["diameter"] / d32
        ax.plot(ref_ratio, ref["bottom_mass_fraction"], "o--", color="tab:blue", mfc="none",
                label=f"bottom half, {args.reference_label}")
        ax.plot(ref_ratio, ref["top_mass_fraction"], "s--", color="tab:red", mfc="none",
                label=f"top half, {args.reference_label}")
    ax.axvline(1.0, color="gray", lw=0.8, ls=":")
    for x, text in zip(ratio, labels):
        ax.annotate(text[1:].replace("mm", " mm"), (x, 0), xytext=(0, 4), textcoords="offset points",
                    ha="center", fontsize=7, color="gray")
    ax.set_xlabel(f"$d_i / d_{{32}}$ [-]   ($d_{{32}}$ of the inventory = {1e3 * d32:.3f} mm)")
    ax.set_ylabel("mass fraction in the half [-]")
    ax.set_ylim(bottom=0)
    ax.margins(x=0.08)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
    ax.set_title(args.title or "size distribution of the bottom and top halves")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
