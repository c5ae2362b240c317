#!/usr/bin/env python3
"""The form of the drift law from the measured drift: each size class's
velocity relative to the bulk of its cell (measured_drift.csv of rcfd
calibrate -calibrate_from measured, one file per bed) against the law's
size term relative to the bulk, x_i - sum_j s_j x_j, for model A (x = d^2 -
d32^2) and model B (x = (d - d32)|d - d32|).  A law of that form puts every
class of every bed on one line through the origin, u = -k_d (x - mean x);
the lines drawn are the fit to the first file's classes (error bars: 2
standard errors).

    python3 drift_law_form.py FIT/measured_drift.csv [OTHER/measured_drift.csv ...] \\
        --labels fit,other -o drift_law_form.png [--title TEXT]
"""
import rcfd_figure as rf


def size_terms(table, model):
    d, s, d32 = table["diameter_m"], table["mass_share"], table["d32_m"][0]
    x = d * d - d32 * d32 if model == "A" else (d - d32) * abs(d - d32)
    return x - (s * x).sum()


def main():
    args, files, labels = rf.several_files(__doc__, "measured_drift.csv")
    tables = [rf.read_csv(f) for f in files]
    fig, axes = rf.plt.subplots(1, 2, figsize=(9.0, 4.0))
    markers = ["o", "s", "^", "D", "v"]
    for ax, model, unit in ((axes[0], "A", "d^2 - d_{32}^2"), (axes[1], "B", "(d - d_{32})|d - d_{32}|")):
        fit = tables[0]
        x0 = size_terms(fit, model)
        w = 1.0 / fit["standard_error_m_s"] ** 2
        kd = -(w * x0 * fit["velocity_m_s"]).sum() / (w * x0 * x0).sum()
        span = max(abs(size_terms(t, model)).max() for t in tables) * 1.15
        xs = rf.np.linspace(-span, span, 2)
        ax.plot(1e6 * xs, -1e3 * kd * xs, color="black", lw=1.0,
                label=f"$u = -k_d\\,(x - \\bar x)$, $k_d$ = {kd:.3g} 1/(m s) ({labels[0]})")
        for k, (t, label) in enumerate(zip(tables, labels)):
            x = size_terms(t, model)
            ax.errorbar(1e6 * x, 1e3 * t["velocity_m_s"], yerr=2e3 * t["standard_error_m_s"], ls="none",
                        marker=markers[k % len(markers)], ms=6, capsize=3,
                        label=label + ": " + ", ".join(f"{1e3 * d:.3g}" for d in t["diameter_m"]) + " mm")
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.axvline(0.0, color="grey", lw=0.6)
        ax.set_xlabel(f"model {model}: $x - \\bar x$, $x = {unit}$ [mm$^2$]")
        ax.set_ylabel("drift relative to the bulk [mm/s], up positive")
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.17), frameon=False, fontsize=8)
    if args.title:
        fig.suptitle(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
