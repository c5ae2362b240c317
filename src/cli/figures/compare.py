#!/usr/bin/env python3
"""Validation curves: Delta z(t) = z_CoG(small) - z_CoG(large) of a reference
(e.g. CFD-DEM) and of rcfd runs, from the CSV rcfd compare -o writes (the
reference's times, then one column per run; empty where a run has no data);
with --classes, beside it each class's z_CoG,i - z_CoG,bed from the classes
CSV rcfd compare writes next to it (reference solid, runs dashed, one colour
per class).

    python3 compare.py CURVES.csv -o CURVES.png [--window T0,T1] [--title TEXT] [--legend TEXT ...]
                       [--classes CURVES-classes.csv [--class-legend TEXT ...]]
"""
import rcfd_figure as rf
from matplotlib.lines import Line2D

RUN_STYLES = ["--", ":", "-.", (0, (5, 1, 1, 1, 1, 1))]


def draw_delta_z(ax, args, table):
    time = table["time_s"]
    runs = [name for name in table if name.startswith("delta_z_") and name != "delta_z_reference_m"]
    if args.window:
        t0, t1 = (float(t) for t in args.window.split(","))
        ax.axvspan(t0, t1, color="gray", alpha=0.12, lw=0, label="window of the Eq. 7 means")
    ax.plot(time, 1e3 * table["delta_z_reference_m"], color="black", lw=2.2, label="reference")
    for k, name in enumerate(runs):
        label = args.legend[k] if k < len(args.legend) else name[len("delta_z_"):-len("_m")]
        ax.plot(time, 1e3 * table[name], lw=1.3, label=label)
    ax.axhline(0.0, color="gray", lw=0.8)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("$\\Delta z = z_\\mathrm{CoG,small} - z_\\mathrm{CoG,large}$ [mm]")
    ax.set_xlim(time[0], time[-1])


def draw_classes(ax, table, legends):
    """Each class's height above the bed's centre of gravity: the reference
    solid, run k in RUN_STYLES[k], a colour per class."""
    time = table["time_s"]
    classes = [name[: -len("_reference_m")] for name in table
               if name.startswith("class_") and name.endswith("_reference_m")]
    labels = []
    for c, name in enumerate(classes):
        colour = f"C{c % 10}"
        ax.plot(time, 1e3 * table[name + "_reference_m"], color=colour, lw=1.8)
        runs = [col for col in table if col.startswith(name + "_") and col != name + "_reference_m"]
        for k, col in enumerate(runs):
            ax.plot(time, 1e3 * table[col], color=colour, lw=1.2, ls=RUN_STYLES[k % len(RUN_STYLES)])
            if c == 0:
                labels.append(col[len(name) + 1:-len("_m")])
    ax.axhline(0.0, color="gray", lw=0.8)
    ax.set_xlabel("time $t$ [s]")
    ax.set_ylabel("$z_{\\mathrm{CoG},i} - z_\\mathrm{CoG,bed}$ [mm]")
    ax.set_xlim(time[0], time[-1])
    handles = [Line2D([], [], color=f"C{c % 10}", lw=1.8, label=rf.fraction_label("z_cog_" + name[len("class_"):]))
               for c, name in enumerate(classes)]
    handles.append(Line2D([], [], color="black", lw=1.8, label="reference"))
    handles += [Line2D([], [], color="black", lw=1.2, ls=RUN_STYLES[k % len(RUN_STYLES)],
                       label=legends[k] if k < len(legends) else label) for k, label in enumerate(labels)]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0, frameon=False)


def main():
    parser = rf.arguments(__doc__, "curves CSV written by rcfd compare -o", ".png")
    parser.add_argument("--window", help="t0,t1 [s]: shade the window of the Eq. 7 means")
    parser.add_argument("--legend", action="append", default=[],
                        help="legend text of the next run (repeat; default: its column's name)")
    parser.add_argument("--classes", help="classes CSV written by rcfd compare (CURVES-classes.csv): "
                        "draw each class's z_CoG,i - z_CoG,bed beside Delta z")
    parser.add_argument("--class-legend", action="append", default=[],
                        help="legend text of the next run's class curves (repeat; default: its name)")
    args = rf.parse(parser)

    table = rf.read_csv(args.csv)
    if not args.classes:
        fig, ax = rf.plt.subplots(figsize=(7.5, 4.2))
        draw_delta_z(ax, args, table)
        ax.set_title(args.title)
        rf.legend_outside(ax)
        rf.save(fig, args.output)
        return
    fig, (ax, right) = rf.plt.subplots(1, 2, figsize=(14.5, 4.8))
    draw_delta_z(ax, args, table)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False, ncol=2)
    draw_classes(right, rf.read_csv(args.classes), args.class_legend)
    right.set_title("each class against the bed")
    fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
