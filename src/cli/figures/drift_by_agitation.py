#!/usr/bin/env python3
"""Does the drift scale with the bed's agitation?  Each size class's measured
velocity relative to the bulk against the leaving share a of the particle's
cell (measured_drift_by_agitation.csv of rcfd calibrate -calibrate_from
measured -calibrate_exponent), with laws u = u_mean (a / a_bar)^n scaled to
the class's mean for the exponents given (e.g. the measured fit and the one
the centre-of-gravity calibration needs).  Error bars: 2 standard errors;
marker area grows with the particles counted.

    python3 drift_by_agitation.py CAL/measured_drift_by_agitation.csv --exponents 0.16,2 \\
        -o drift_by_agitation.png [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "measured_drift_by_agitation.csv of rcfd calibrate", ".png")
    parser.add_argument("--exponents", default="1", help="comma-separated n of the laws drawn")
    parser.add_argument("--labels", default="", help="comma-separated labels of the exponents")
    args = rf.parse(parser)
    t = rf.read_csv(args.csv)
    abar = t["agitation_mean"][0]
    exponents = [float(n) for n in args.exponents.split(",")]
    labels = args.labels.split(",") if args.labels else [f"n = {n:g}" for n in exponents]
    fig, ax = rf.plt.subplots(figsize=(7.5, 4.6))
    colours = ["tab:blue", "tab:red", "tab:green", "tab:purple"]
    a_line = rf.np.linspace(0.0, 1.0, 101)
    for k, d in enumerate(sorted(set(t["diameter_m"]))):
        rows = (t["diameter_m"] == d) & (t["frames"] >= 2)
        a, u, se, count = t["agitation"][rows], t["velocity_m_s"][rows], t["standard_error_m_s"][rows], t["particles"][rows]
        colour = colours[k % len(colours)]
        ax.errorbar(a, 1e3 * u, yerr=2e3 * se, ls="none", color=colour, capsize=2)
        ax.scatter(a, 1e3 * u, s=8 + 60 * count / count.max(), color=colour, label=f"{1e3 * d:.3g} mm, measured")
        w = count / count.sum()
        for n, style, label in zip(exponents, ["-", "--", ":", "-."], labels):
            # u_mean (a/a_bar)^n with u_mean chosen so the particle-weighted mean matches
            scale = (w * u).sum() / (w * (a / abar) ** n).sum()
            ax.plot(a_line, 1e3 * scale * (a_line / abar) ** n, color=colour, ls=style, lw=1.0,
                    label=f"{1e3 * d:.3g} mm, $(a/\\bar a)^n$, {label}")
    # The data set the scale (a steep law runs off it at large a).
    ok = t["frames"] >= 2
    top = 1.6e3 * rf.np.nanmax(abs(t["velocity_m_s"][ok]) + 2 * t["standard_error_m_s"][ok])
    ax.set_ylim(-top, top)
    ax.axvline(abar, color="grey", lw=0.8, ls=":")
    ax.text(abar, 0.95 * top, " mean $\\bar{a}$", va="top", color="grey")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("leaving share $a = 1 - T_{ii}$ of the particle's cell [-]")
    ax.set_ylabel("drift relative to the bulk [mm/s], up positive")
    rf.legend_outside(ax)
    if args.title:
        ax.set_title(args.title)
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
