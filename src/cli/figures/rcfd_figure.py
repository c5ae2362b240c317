"""What the rcfd figure scripts share: reading rcfd's CSV files, naming their
columns in legends, and writing a PNG so that a reader never sees half a file.

The scripts next to this module import it; copy it along when you copy one.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # no display needed: rcfd draws on clusters too
import matplotlib.pyplot as plt  # noqa: E402 (after choosing the backend)
import numpy as np  # noqa: E402

plt.rcParams.update({"figure.dpi": 150, "font.size": 10, "axes.grid": True, "grid.alpha": 0.3})


def arguments(doc, csv_help, default_suffix):
    """An argument parser with what every script takes: the CSV, -o PNG (by
    default the CSV's name with default_suffix) and --title; add your own
    with parser.add_argument, then call parse(parser)."""
    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("csv", help=csv_help)
    parser.add_argument("-o", "--output", help=f"PNG file (default: the CSV's name with {default_suffix})")
    parser.add_argument("--title", default="", help="figure title (default: none)")
    parser.set_defaults(default_suffix=default_suffix)
    return parser


def parse(parser):
    """The parsed arguments, args.output filled in."""
    args = parser.parse_args()
    args.output = args.output or os.path.splitext(args.csv)[0] + args.default_suffix
    return args


def several_files(doc, csv_name, default_suffix=".png"):
    """(args, files, labels) of a script that draws one CSV per bed: the
    files given, and --labels (comma-separated, one per file; default the
    file names)."""
    parser = arguments(doc, f"{csv_name} of the first bed", default_suffix)
    parser.add_argument("others", nargs="*", help=f"{csv_name} of further beds")
    parser.add_argument("--labels", default="", help="comma-separated labels, one per file")
    args = parse(parser)
    files = [args.csv] + args.others
    return args, files, args.labels.split(",") if args.labels else files


def read_csv(path):
    """The columns of a CSV file rcfd wrote, by name and in file order.

    Lines starting with '#' are comments; an empty field reads as NaN (a gap
    in a curve)."""
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    if len(lines) < 2:
        raise SystemExit(f"{path}: no header and data rows")
    header = [name.strip() for name in lines[0].split(",")]
    data = np.genfromtxt(lines[1:], delimiter=",", dtype=float)
    data = data.reshape(len(lines) - 1, len(header))
    return {name: data[:, i] for i, name in enumerate(header)}


def is_ensemble(table):
    """An ensemble summary (rcfd run -ensemble N) has <column>_mean and _std."""
    return any(name.endswith("_mean") for name in table)


def series(table, column):
    """(values, standard deviation or None) of a column of a run's cog.csv or
    of an ensemble.csv (its mean and spread over the members)."""
    if column + "_mean" in table:
        return table[column + "_mean"], table[column + "_std"]
    return table[column], None


def cog_columns(table):
    """Names of the centre-of-gravity columns (z_cog_bed_m, z_cog_d1.950mm_m, ...)."""
    names = [name[: -len("_mean")] if name.endswith("_mean") else name for name in table]
    return [name for name in names if name.startswith("z_cog_") and not name.endswith("_std")]


def fraction_label(column):
    """Legend text of a column: z_cog_d1.950mm_m -> '$d$ = 1.950 mm', z_cog_bed_m -> 'bed'."""
    core = column[len("z_cog_"):]
    if core.endswith("_m"):
        core = core[: -len("_m")]
    if core.startswith("d") and core.endswith("mm"):
        return f"$d$ = {core[1:-2]} mm"
    return core


def plot_band(ax, time, values, spread, label, scale=1e3, band_alpha=0.2, **style):
    """A curve (in mm by default) and, for an ensemble, its mean +- 1 sd band."""
    (line,) = ax.plot(time, scale * values, label=label, **{"lw": 1.4, **style})
    if spread is not None:
        ax.fill_between(time, scale * (values - spread), scale * (values + spread),
                        color=line.get_color(), alpha=band_alpha, lw=0)
    return line


def legend_outside(ax):
    """The legend right of the axes, where it cannot cover a curve."""
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False)


def save(fig, path):
    """Writes fig as PNG to path atomically: a temporary file, then os.replace."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    temporary = os.path.join(folder, f".{os.path.basename(path)}.{os.getpid()}.tmp")
    try:
        fig.savefig(temporary, format="png", bbox_inches="tight")
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)
    plt.close(fig)
