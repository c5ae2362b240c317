#!/usr/bin/env python3
"""The size laws against the measured drift of several beds: each size
class's velocity relative to the bulk of its cell (measured_law_fits.csv of
rcfd calibrate -calibrate_from measured -calibrate_models A,B,drag,log,power,
one file per bed) against d_i/d32, one panel per law, with the law fitted to
each bed relative to the bulk, u(d) = k (g(d, d32) - sum_j s_j g(d_j, d32))
(curves in the bed's colour; error bars: 2 standard errors).  The last panel
shows every law's residual (measured - law) per class of the beds with more
than two classes (two classes fit any one-parameter law exactly).

    python3 drift_size_laws.py BED1/measured_law_fits.csv [BED2/... ...] \\
        --labels bed1,bed2 -o drift_size_laws.png [--title TEXT]
"""
import csv

import rcfd_figure as rf

np = rf.np

# g(d, d32) of the built-in laws (rcfd/size_law.hpp), m the power's exponent.
LAWS = {
    "A": lambda d, D, m: -(d * d - D * D),
    "B": lambda d, D, m: -(d - D) * np.abs(d - D),
    "drag": lambda d, D, m: D / d - 1.0,
    "log": lambda d, D, m: np.log(D / d),
    "power": lambda d, D, m: (D / d) ** m - 1.0,
}
FORMULA = {
    "A": "$-(d^2 - d_{32}^2)$",
    "B": "$-(d - d_{32})|d - d_{32}|$",
    "drag": "$d_{32}/d - 1$",
    "log": "$\\ln(d_{32}/d)$",
    "power": "$(d_{32}/d)^m - 1$",
}


def read_fits(path):
    """{law: {column: array}} of one measured_law_fits.csv."""
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if line.strip() and not line.startswith("#")))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    laws = {}
    for row in rows:
        laws.setdefault(row["model"], []).append(row)
    out = {}
    for law, lines in laws.items():
        table = {key: np.array([float(r[key]) if r[key] not in ("", "nan") else np.nan for r in lines])
                 for key in lines[0] if key not in ("model", "kd_unit")}
        table["kd_unit"] = lines[0]["kd_unit"]
        out[law] = table
    return out


def main():
    args, files, labels = rf.several_files(__doc__, "measured_law_fits.csv")
    beds = [read_fits(f) for f in files]
    laws = [law for law in LAWS if law in beds[0]]
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
    markers = ["o", "s", "^", "D", "v"]
    fig, axes = rf.plt.subplots(2, 3, figsize=(13.0, 8.0), sharex=True)
    axes = axes.ravel()
    xmin = min(min(bed[laws[0]]["diameter_m"] / bed[laws[0]]["d32_m"]) for bed in beds) * 0.9
    xmax = max(max(bed[laws[0]]["diameter_m"] / bed[laws[0]]["d32_m"]) for bed in beds) * 1.08
    for ax, law in zip(axes, laws):
        for k, (bed, label) in enumerate(zip(beds, labels)):
            t = bed[law]
            D, d, s = t["d32_m"][0], t["diameter_m"], t["mass_share"]
            m = t["shape_parameter"][0] if np.isfinite(t["shape_parameter"][0]) else 1.0
            mean = (s * LAWS[law](d, D, m)).sum()
            x = np.linspace(xmin, xmax, 200)
            kd = t["kd"][0]
            ax.plot(x, 1e3 * kd * (LAWS[law](x * D, D, m) - mean), color=colours[k % 5], lw=1.0)
            shape = f", m = {m:.2f}" if law == "power" and np.isfinite(t["shape_parameter"][0]) else ""
            fit = f"$\\chi^2$/dof {t['chi2_per_dof'][0]:.3g}" if len(d) > 2 else "exact (2 classes)"
            ax.errorbar(d / D, 1e3 * t["velocity_m_s"], yerr=2e3 * t["standard_error_m_s"], ls="none",
                        marker=markers[k % 5], color=colours[k % 5], ms=5, capsize=2,
                        label=f"{label}: k = {kd:.3g} {t['kd_unit']}{shape}, {fit}")
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.axvline(1.0, color="grey", lw=0.6)
        ax.set_title(f"{law}: u = k ({FORMULA[law]} $-$ bulk mean)", fontsize=10)
        ax.set_ylabel("drift relative to the bulk [mm/s]")
        ax.legend(loc="upper right", fontsize=7, frameon=False)
    # Residuals of every law on the beds with more than two classes.
    ax = axes[len(laws)] if len(laws) < len(axes) else None
    if ax is not None:
        for k, (bed, label) in enumerate(zip(beds, labels)):
            if len(bed[laws[0]]["diameter_m"]) < 3:
                continue
            for j, law in enumerate(laws):
                t = bed[law]
                offset = (j - (len(laws) - 1) / 2) * 0.012
                ax.errorbar(t["diameter_m"] / t["d32_m"][0] + offset, 1e3 * t["residual_m_s"],
                            yerr=2e3 * t["standard_error_m_s"], ls="-", lw=0.6, marker=markers[j % 5], ms=5,
                            capsize=2, color=colours[j % 5], label=f"{law} ({label})")
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.set_title("residual: measured $-$ law (beds of more than two classes)", fontsize=10)
        ax.set_ylabel("residual [mm/s]")
        ax.legend(loc="upper right", fontsize=7, frameon=False)
        for extra in axes[len(laws) + 1:]:
            extra.axis("off")
    for ax in axes[3:]:
        ax.set_xlabel("$d_i / d_{32}$")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
