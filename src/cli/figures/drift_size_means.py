#!/usr/bin/env python3
"""Which mean diameter collapses the measured drift of several beds (issue 21):
each class's velocity relative to the bulk of its cell against d_i / d_mean
for four means, with one curve per size law and ONE constant for all beds.

Means: the inventory's d32 (sum s / sum s/d) and d43 (sum s d, the mass-
weighted mean), s the bed's mass shares; and the local mixture's d32 and d43,
from the measured drift field (rcfd info -extra_csv measured_drift_field,...):
per frame and region (2 x 2 x 2 cells) every class's velocity and mass, so
each class's d_i is divided by the mean of its region's own mixture in that
frame.  Those (frame, region, class) entries are pooled per bed in bins of
ln(d_i / d_mean) 0.05 wide; a bin's velocity is the mass-weighted mean, its
error bar 2 standard errors of its per-frame means, bins with less than
0.2 % of the bed's mass are left out.

Curves: u = k G(x), x = d / d_mean, G(1) = 0 (no drift at the mean size):
A -(x^2 - 1), B -(x - 1)|x - 1|, drag 1/x - 1, log -ln x, power x^-m - 1.
k (and power's m, a scan of [0.05, 5] in steps of 0.01) by least squares of
all beds' points, each weighted by its share of its bed's mass so that each
bed counts once; the score is the RMS residual with the same weights.  The
local bins are also scored like for like against the inventory's d32: each
bin predicted by the mass-weighted mean over its classes of k G(d_i / d32)
(the bars hatched; a class's drift then does not depend on its region).

Each bed is a directory holding measured_law_fits.csv and measured_drift.csv
(rcfd calibrate -calibrate_from measured), measured_drift_field.csv and
measured_drift_field_layout.csv (rcfd info -extra_csv):

    python3 drift_size_means.py DIR1 [DIR2 ...] --labels a,b -o means.png \\
        [--table means.csv] [--title TEXT]
"""
import csv
import os

import rcfd_figure as rf
from drift_size_laws import read_fits

np = rf.np

SHAPES = {
    "A": lambda x, m: -(x * x - 1.0),
    "B": lambda x, m: -(x - 1.0) * np.abs(x - 1.0),
    "drag": lambda x, m: 1.0 / x - 1.0,
    "log": lambda x, m: -np.log(x),
    "power": lambda x, m: x ** (-m) - 1.0,
}
LAW_STYLE = {"A": ("0.45", "--"), "B": ("tab:brown", ":"), "drag": ("tab:red", "-"),
             "log": ("tab:purple", "-."), "power": ("black", "-")}
MEANS = [("inventory d32", "$d_i / d_{32}$ (inventory)"), ("inventory d43", "$d_i / d_{43}$ (inventory)"),
         ("local d32", "$d_i / d_{32}$ of the region's mixture"),
         ("local d43", "$d_i / d_{43}$ of the region's mixture")]
LIKE_FOR_LIKE = "inventory d32 on local bins"
BIN_WIDTH = 0.05  # of ln x
MIN_BIN_SHARE = 0.002


def matrix(path):
    """A CSV of rcfd info -extra_csv as a 2-D array."""
    table = rf.read_csv(path)
    return np.column_stack([table[name] for name in table])


def classes(directory):
    """(d, u, se, s) of a bed's classes: measured_law_fits.csv of any law."""
    fits = read_fits(os.path.join(directory, "measured_law_fits.csv"))
    t = next(iter(fits.values()))
    return t["diameter_m"], t["velocity_m_s"], t["standard_error_m_s"], t["mass_share"]


def local_points(directory, frames, kind):
    """Binned (x, u, se, share, then the bin's mass fraction of each class) of one bed against the
    local mixture's mean `kind` (d32 or d43)."""
    layout = matrix(os.path.join(directory, "measured_drift_field_layout.csv"))[0]
    field = matrix(os.path.join(directory, "measured_drift_field.csv"))
    d = layout[3:]
    if field.shape[0] % frames:
        raise SystemExit(f"{directory}: {field.shape[0]} field rows are not a multiple of {frames} frames")
    frame = np.arange(field.shape[0]) // (field.shape[0] // frames)
    u, mass = field[:, 0::3], field[:, 2::3]
    total = mass.sum(axis=1)
    keep = total > 0
    if kind == "d32":
        mean = total[keep] / (mass[keep] / d).sum(axis=1)
    else:
        mean = (mass[keep] * d).sum(axis=1) / total[keep]
    x = d[None, :] / mean[:, None]
    u, mass, frame = u[keep], mass[keep], np.repeat(frame[keep][:, None], len(d), axis=1)
    cls = np.broadcast_to(np.arange(len(d)), mass.shape)
    used = mass > 0
    x, u, mass, frame, cls = x[used], u[used], mass[used], frame[used], cls[used]
    bins = np.round(np.log(x) / BIN_WIDTH).astype(int)
    out = []
    for b in np.unique(bins):
        inside = bins == b
        share = mass[inside].sum() / mass.sum()
        if share < MIN_BIN_SHARE:
            continue
        m, v, f = mass[inside], u[inside], frame[inside]
        per_frame_mass = np.bincount(f, weights=m, minlength=frames)
        per_frame = np.bincount(f, weights=m * v, minlength=frames)
        seen = per_frame_mass > 0
        means = per_frame[seen] / per_frame_mass[seen]
        se = means.std(ddof=1) / np.sqrt(seen.sum()) if seen.sum() > 1 else np.nan
        composition = np.bincount(cls[inside], weights=m, minlength=len(d)) / m.sum()
        out.append(np.concatenate([[(m * x[inside]).sum() / m.sum(), (m * v).sum() / m.sum(), se, share],
                                   composition]))
    return np.array(out)


def fit_common(points, law, shape=None):
    """k, m, RMS of all beds and per bed of u = k G(x) through every bed's points (x, u, se, share);
    shape(m) instead gives G of all points (all beds in turn) for another predictor."""
    x = np.concatenate([p[:, 0] for p in points])
    u = np.concatenate([p[:, 1] for p in points])
    w = np.concatenate([p[:, 3] / p[:, 3].sum() for p in points])
    bed = np.concatenate([np.full(len(p), i) for i, p in enumerate(points)])
    best = None
    for m in (np.arange(5, 501) / 100.0 if law == "power" else [np.nan]):
        g = SHAPES[law](x, m) if shape is None else shape(m)
        k = (w * g * u).sum() / (w * g * g).sum()
        r = u - k * g
        chi = (w * r * r).sum()
        if best is None or chi < best[0]:
            best = (chi, k, m, r)
    _, k, m, r = best
    rms = np.sqrt((w * r * r).sum() / w.sum())
    per_bed = [np.sqrt((w[bed == i] * r[bed == i] ** 2).sum() / w[bed == i].sum()) for i in range(len(points))]
    return k, m, rms, per_bed


def main():
    parser = rf.arguments(__doc__, "directory of the first bed", ".png")
    parser.add_argument("others", nargs="*", help="directories of further beds")
    parser.add_argument("--labels", default="", help="comma-separated labels, one per bed")
    parser.add_argument("--table", default="", help="CSV of the common fits (mean, law, k, m, RMS per bed)")
    args = parser.parse_args()
    directories = [args.csv] + args.others
    labels = args.labels.split(",") if args.labels else directories
    if not args.output:
        raise SystemExit("-o PNG is required")
    beds = [classes(directory) for directory in directories]
    points = {}
    for name, _ in MEANS:
        points[name] = []
        for directory, (d, u, se, s) in zip(directories, beds):
            if name.startswith("inventory"):
                mean = s.sum() / (s / d).sum() if name.endswith("d32") else (s * d).sum() / s.sum()
                points[name].append(np.column_stack([d / mean, u, se, s]))
            else:
                # the pairs of snapshots: measured_drift.csv counts the frames each class was seen in
                frames = int(rf.read_csv(os.path.join(directory, "measured_drift.csv"))["frames"].max())
                points[name].append(local_points(directory, frames, name.split()[1]))
    laws = list(SHAPES)
    fits = {(name, law): fit_common(points[name], law) for name, _ in MEANS for law in laws}
    # Like for like: the bins of the local d32 predicted from each class's d_i / inventory d32 (the
    # bin's mass-weighted mean of the law over its classes) instead of from the bin's local x.
    inventory = [np.column_stack([d / (s.sum() / (s / d).sum())]) for d, _, _, s in beds]
    for law in laws:
        def on_local(m, law=law):
            return np.concatenate([p[:, 4:] @ SHAPES[law](x[:, 0], m) for p, x in zip(points["local d32"], inventory)])
        fits[(LIKE_FOR_LIKE, law)] = fit_common(points["local d32"], law, on_local)

    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
    markers = ["o", "s", "^", "D", "v"]
    fig, axes = rf.plt.subplots(2, 3, figsize=(15.0, 9.0))
    axes = axes.ravel()
    xmin = min(p[:, 0].min() for name, _ in MEANS for p in points[name]) * 0.95
    xmax = max(p[:, 0].max() for name, _ in MEANS for p in points[name]) * 1.05
    grid = np.linspace(xmin, xmax, 300)
    for ax, (name, xlabel) in zip(axes, MEANS):
        local = name.startswith("local")
        for i, (p, label) in enumerate(zip(points[name], labels)):
            ax.errorbar(p[:, 0], 1e3 * p[:, 1], yerr=2e3 * p[:, 2], ls="-" if local else "none", lw=0.5,
                        marker=markers[i % 5], ms=3.5 if local else 6, capsize=1.5, color=colours[i % 5],
                        label=label if name == MEANS[0][0] else None)
        for law in laws:
            k, m, rms, _ = fits[(name, law)]
            colour, style = LAW_STYLE[law]
            edge = " (scan's edge)" if law == "power" and m <= 0.05 else ""
            shape = f", m {m:.2f}{edge}" if law == "power" else ""
            ax.plot(grid, 1e3 * k * SHAPES[law](grid, m), color=colour, ls=style, lw=1.2,
                    label=f"{law}: k {1e3 * k:.1f} mm/s{shape}, RMS {1e3 * rms:.2f} mm/s")
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.axvline(1.0, color="grey", lw=0.6)
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(-19, 22)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("drift relative to the bulk [mm/s]")
        ax.set_title(f"against {name}" + (" (bins, mass-weighted)" if local else " (classes)"), fontsize=10)
        ax.legend(loc="upper right", fontsize=7, frameon=False)
    # Scores: RMS of the common curve per mean and law, and per bed for the best law.
    scored = [name for name, _ in MEANS] + [LIKE_FOR_LIKE]
    names = {LIKE_FOR_LIKE: "inventory d32, scored on the local d32's bins"}
    bar_colours = ["tab:cyan", "tab:blue", "gold", "tab:olive", "tab:pink"]
    width = 0.8 / len(scored)
    ax = axes[4]
    for j, name in enumerate(scored):
        rms = [1e3 * fits[(name, law)][2] for law in laws]
        ax.bar(np.arange(len(laws)) + (j - (len(scored) - 1) / 2) * width, rms, width,
               label=names.get(name, name), color=bar_colours[j], hatch="//" if name == LIKE_FOR_LIKE else None)
    ax.set_xticks(np.arange(len(laws)))
    ax.set_xticklabels(laws)
    ax.set_ylabel("RMS residual of one common curve [mm/s]")
    ax.set_title("collapse: all beds, each weighted once", fontsize=10)
    ax.set_ylim(0, 1.75 * max(fits[key][2] for key in fits) * 1e3)
    ax.legend(fontsize=8, frameon=False, loc="upper right")
    ax = axes[5]
    for j, name in enumerate(scored):
        best_law = min(laws, key=lambda law: fits[(name, law)][2])
        per_bed = [1e3 * v for v in fits[(name, best_law)][3]]
        ax.bar(np.arange(len(labels)) + (j - (len(scored) - 1) / 2) * width, per_bed, width,
               label=f"{names.get(name, name)} ({best_law})", color=bar_colours[j],
               hatch="//" if name == LIKE_FOR_LIKE else None)
    ax.set_xticks(np.arange(len(labels)))
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_ylabel("RMS residual per bed [mm/s]")
    ax.set_title("per bed, the best law of each mean", fontsize=10)
    ax.legend(fontsize=8, frameon=False, loc="upper left")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    rf.save(fig, args.output)
    if args.table:
        with open(args.table, "w", newline="") as f:
            out = csv.writer(f)
            out.writerow(["mean", "law", "k_m_s", "m", "rms_m_s"] + [f"rms_{label}_m_s" for label in labels])
            for name in [name for name, _ in MEANS] + [LIKE_FOR_LIKE]:
                for law in laws:
                    k, m, rms, per_bed = fits[(name, law)]
                    out.writerow([name, law, f"{k:.6g}", "" if np.isnan(m) else f"{m:.2f}", f"{rms:.4g}"]
                                 + [f"{v:.4g}" for v in per_bed])
    for name in [name for name, _ in MEANS] + [LIKE_FOR_LIKE]:
        print(f"{name}: " + ", ".join(f"{law} {1e3 * fits[(name, law)][2]:.2f}" for law in laws) + " mm/s RMS")


if __name__ == "__main__":
    main()
