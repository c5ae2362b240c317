#!/usr/bin/env python3
"""A granulator run over time (paper Sec. 3.4, Fig. 7): the product's size
distribution (mass shares of what left the discharge zone during the last
residence time) and the holdup's, per class, from a run's product.csv; the
steady state (steady_state.csv's criterion) marked when it was reached.

    python3 granulation.py RUN/product.csv -o RUN/granulation.png [--title TEXT]
"""
import rcfd_figure as rf


def main():
    parser = rf.arguments(__doc__, "product.csv of rcfd run -pipeline ...,discharge", ".png")
    args = rf.parse(parser)
    table = rf.read_csv(args.csv)
    time = table["time_s"]
    # The classes: product_<class> with its holdup_<class> (a run with scalars adds product_<scalar>).
    labels = [name[len("product_"):] for name in table
              if name.startswith("product_") and "holdup_" + name[len("product_"):] in table]
    fig, (top, bottom) = rf.plt.subplots(2, 1, figsize=(7.0, 7.0), sharex=True)
    colors = rf.plt.cm.viridis(rf.np.linspace(0.0, 0.9, len(labels)))
    for label, color in zip(labels, colors):
        name = label[1:].replace("mm", " mm")
        top.plot(time, table["product_" + label], color=color, label=name)
        bottom.plot(time, table["holdup_" + label], color=color, label=name)
    steady = table["steady"]
    if steady.size and steady[-1] > 0:
        first = time[rf.np.argmax(steady > 0)]
        for ax in (top, bottom):
            ax.axvline(first, color="gray", ls="--", lw=1.0)
        top.annotate(f"steady from {first:.3g} s", (first, 1.0), xycoords=("data", "axes fraction"),
                     xytext=(4, -12), textcoords="offset points", fontsize=8, color="gray")
    top.set_ylabel("product: mass share [-]\n(last residence time)")
    bottom.set_ylabel("holdup: mass share [-]")
    bottom.set_xlabel("time [s]")
    for ax in (top, bottom):
        ax.set_ylim(bottom=0)
    bottom.legend(loc="upper center", bbox_to_anchor=(0.5, -0.18), ncol=min(len(labels), 5), frameon=False)
    top.set_title(args.title or "size distribution of the product and the holdup")
    rf.save(fig, args.output)


if __name__ == "__main__":
    main()
