#!/usr/bin/env python3
"""The bottom cell layer over time (paper Fig. 5): its Sauter diameter d32
and u_mf from it against the superficial velocity u_sup, from a run's
bottom.csv; the first time u_mf reaches u_sup (the de-fluidization warning)
is marked.

    python3 bottom_layer.py RUN/bottom.csv -o RUN/bottom.png [--correlation NAME] [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "bottom.csv of rcfd run -bottom_layer", ".png")
    parser.add_argument("--correlation", default="", help="name of the u_mf correlation, for the legend")
    args = rf.parse(parser)

    table = rf.read_csv(args.csv)
    t = table["time_s"]
    fig, (top, bottom) = rf.plt.subplots(2, 1, figsize=(7.5, 5.6), sharex=True)
    top.plot(t, 1e3 * table["d32_bottom_m"], color="tab:blue", lw=1.4, label="bottom layer")
    for name in table:
        if name.startswith("d32_") and name not in ("d32_bottom_m",):
            top.plot(t, 1e3 * table[name], lw=1.0, label="zone " + name[len("d32_"):-len("_m")])
    top.set_ylabel("Sauter diameter $d_{32}$ [mm]")
    top.legend(loc="best", frameon=False)
    umf_label = "$u_\\mathrm{mf}$" + (f" ({args.correlation})" if args.correlation else "")
    bottom.plot(t, table["umf_m_s"], color="tab:red", lw=1.4, label=umf_label)
    bottom.plot(t, table["usup_m_s"], color="black", lw=1.0, ls="--", label="$u_\\mathrm{sup}$")
    fired = rf.np.flatnonzero(table["defluidized"] > 0.5)
    if fired.size:
        when = t[fired[0]]
        for ax in (top, bottom):
            ax.axvline(when, color="tab:orange", lw=1.2, ls=":")
        bottom.annotate(f"de-fluidization warning\n$t$ = {when:.3g} s", (when, table["umf_m_s"][fired[0]]),
                        xytext=(8, -28), textcoords="offset points", color="tab:orange", fontsize=9)
    bottom.set_xlabel("time $t$ [s]")
    bottom.set_ylabel("velocity [m/s]")
    bottom.set_xlim(t[0], t[-1])
    bottom.legend(loc="best", frameon=False)
    fig.suptitle(args.title or "bottom cell layer")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
