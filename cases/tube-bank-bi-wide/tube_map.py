#!/usr/bin/env python3
"""Where the large particles collect around the tubes (cases/tube-bank-bi-wide).

Reads the mid-plane snapshots (snapshot_<t>s.csv) of a run, averages each cell's
volume fraction of each class over them, and writes to the run's directory:
  tube_map.csv      x_m, z_m, alpha_small, alpha_large, large_share (alpha_large / alpha_total)
  tube_regions.csv  region, cells, alpha_total, large_share: on top of the tubes, under
                    them, at their flanks (within 1 cm of a tube), the rest of the bank's
                    height, below the bank and above it (the bed only: alpha_total > 0.2;
                    without tubes, the places of the tubes are left out)
  tube_map.png      the large class's share over the mid-plane, tubes drawn
A region's share is sum(alpha_large) / sum(alpha_total) over its cells (each mid-plane
cell counts once; the cut cells next to a tube count like whole ones).

usage: tube_map.py RUN_DIR [COMPARE_DIR]   (COMPARE_DIR: the same bed without tubes,
drawn beside it and its regions written to its own tube_regions.csv)
"""
import csv
import glob
import os
import sys

# The case's tubes: centre x, centre z, radius [m] (case.yaml's database command).
TUBES = [(0.04, 0.08, 0.01), (0.10, 0.08, 0.01), (0.16, 0.08, 0.01), (0.07, 0.14, 0.01), (0.13, 0.14, 0.01)]
BANK = (0.06, 0.16)  # heights the bank spans, with 1 cm around its tubes [m]
NEAR = 0.01           # a cell within this distance of a tube's wall is the tube's [m]
CELL = 0.005          # the mesh's cells [m]


def read_snapshots(run):
    files = sorted(glob.glob(os.path.join(run, "snapshot_*s.csv")))
    if not files:
        sys.exit(f"tube_map.py: no snapshot_*s.csv in '{run}' (run the case with its -snapshots_times)")
    cells = {}
    for name in files:
        with open(name) as f:
            rows = csv.reader(f)
            header = next(rows)
            if len(header) != 5:
                sys.exit(f"tube_map.py: '{name}' has {len(header)} columns; two size classes expected")
            for r in rows:
                key = (float(r[0]), float(r[1]))
                small, large, _ = cells.get(key, (0.0, 0.0, 0))
                cells[key] = (small + float(r[2]), large + float(r[3]), 0)
    n = len(files)
    return [(x, z, s / n, l / n) for (x, z), (s, l, _) in sorted(cells.items(), key=lambda c: (c[0][1], c[0][0]))], n


def region(x, z):
    for tx, tz, r in TUBES:
        dx, dz = x - tx, z - tz
        d = (dx * dx + dz * dz) ** 0.5
        if d < r:  # without tubes: where one would be (left out)
            return None
        if d <= r + NEAR:
            if abs(dx) <= 0.7 * r:
                return "on top of a tube" if dz > 0 else "under a tube"
            return "flank of a tube"
    if z < BANK[0]:
        return "below the bank"
    if z > BANK[1]:
        return "above the bank"
    return "in the bank, away from tubes"


ORDER = ["on top of a tube", "flank of a tube", "under a tube", "in the bank, away from tubes",
         "below the bank", "above the bank"]


def write(run, cells):
    with open(os.path.join(run, "tube_map.csv"), "w") as f:
        f.write("x_m,z_m,alpha_small,alpha_large,large_share\n")
        for x, z, s, l in cells:
            share = l / (s + l) if s + l > 0 else float("nan")
            f.write(f"{x:.6g},{z:.6g},{s:.5g},{l:.5g},{share:.5g}\n")
    sums = {}
    for x, z, s, l in cells:
        if s + l <= 0.2:
            continue
        k = region(x, z)
        if k is None:
            continue
        n, a, large = sums.get(k, (0, 0.0, 0.0))
        sums[k] = (n + 1, a + s + l, large + l)
    with open(os.path.join(run, "tube_regions.csv"), "w") as f:
        f.write("region,cells,alpha_total,large_share\n")
        for k in ORDER:
            if k in sums:
                n, a, large = sums[k]
                f.write(f"{k},{n},{a / n:.4f},{large / a:.4f}\n")
    return sums


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    runs = sys.argv[1:]
    maps = []
    for run in runs:
        cells, n = read_snapshots(run)
        sums = write(run, cells)
        print(f"{run}: {n} snapshots, {len(cells)} mid-plane cells")
        for k in ORDER:
            if k in sums:
                c, a, large = sums[k]
                print(f"  {k:30s} {c:5d} cells  alpha {a / c:.3f}  large share {large / a:.3f}")
        maps.append(cells)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle
    fig, axes = plt.subplots(1, len(maps), figsize=(4.2 * len(maps) + 1.5, 6), squeeze=False)
    fig.subplots_adjust(wspace=0.35)
    for ax, cells, run in zip(axes[0], maps, runs):
        # One pixel per cell of the mid-plane (a cut cell's centroid is off the lattice: its cell).
        h = CELL
        grid = [[float("nan")] * round(0.2 / h) for _ in range(round(0.3 / h))]
        for x, z, s, l in cells:
            i, k = int(x / h), int(z / h)
            if s + l > 0.2 and k < len(grid):
                grid[k][i] = l / (s + l)
        im = ax.imshow(grid, origin="lower", extent=(0, 0.2, 0, 0.3), cmap="viridis", vmin=0.2, vmax=0.7,
                       interpolation="nearest")
        for tx, tz, r in TUBES:  # the tubes, or where they would be (dashed)
            ax.add_patch(Circle((tx, tz), r, facecolor="white", edgecolor="k") if run == runs[0] else
                         Circle((tx, tz), r, fill=False, edgecolor="w", linestyle="--"))
        ax.set_aspect("equal")
        ax.set_xlim(0, 0.2)
        ax.set_ylim(0, 0.3)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]")
        ax.set_title(("tube bank" if run == runs[0] else "no tubes") + ": large class's share")
    fig.colorbar(im, ax=axes[0].tolist(), label="alpha_large / alpha_total (mid-plane, mean of the snapshots)")
    out = os.path.join(runs[0], "tube_map.png")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
