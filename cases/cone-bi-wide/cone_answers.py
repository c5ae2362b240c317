#!/usr/bin/env python3
"""The answers of cases/cone-bi-wide: the bottom layer's d32 and the segregation over time.

Reads cog.csv and bottom.csv of one or more runs (the conical bottom first, then, say, the flat
cylinder of cases/cylinder-bi-wide) and writes to the first run's directory:
  cone_answers.csv  run, time_s, delta_z_mm (centre of gravity, small minus large),
                    d32_bottom_mm (the bottom cell layer: under the cone, the cone's tip)
                    at 0.5, 1, 2, 3, 5, 7.5 and 10 s
  cone_answers.png  both against time, every run
usage: cone_answers.py RUN_DIR [RUN_DIR ...]
"""
import csv
import os
import sys

TIMES = [0.5, 1, 2, 3, 5, 7.5, 10]


def series(path, column):
    with open(path) as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    header, body = rows[0], rows[1:]
    if column not in header:
        sys.exit(f"cone_answers.py: '{path}' has no column {column}")
    i = header.index(column)
    return [float(r[0]) for r in body], [float(r[i]) for r in body]


def at(times, values, t):
    return values[min(range(len(times)), key=lambda k: abs(times[k] - t))]


def main():
    runs = sys.argv[1:]
    if not runs:
        sys.exit(__doc__)
    data = []
    lines = ["run,time_s,delta_z_mm,d32_bottom_mm"]
    for run in runs:
        tz, dz = series(os.path.join(run, "cog.csv"), "delta_z_m")
        tb, d32 = series(os.path.join(run, "bottom.csv"), "d32_bottom_m")
        data.append((run, tz, dz, tb, d32))
        for t in TIMES:
            lines.append(f"{os.path.basename(os.path.normpath(run))},{t:g},{1e3 * at(tz, dz, t):.1f},{1e3 * at(tb, d32, t):.3f}")
    with open(os.path.join(runs[0], "cone_answers.csv"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
    for run, tz, dz, tb, d32 in data:
        name = os.path.basename(os.path.normpath(run))
        a.plot(tz, [1e3 * v for v in dz], label=name)
        b.plot(tb, [1e3 * v for v in d32], label=name)
    a.set_xlabel("t [s]")
    a.set_ylabel("Δz = z_small − z_large [mm]")
    a.set_title("segregation")
    b.set_xlabel("t [s]")
    b.set_ylabel("d32 of the bottom cell layer [mm]")
    b.set_title("bottom layer (under a cone: its tip)")
    for ax in (a, b):
        ax.legend()
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = os.path.join(runs[0], "cone_answers.png")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
