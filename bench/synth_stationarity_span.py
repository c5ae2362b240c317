#!/usr/bin/env python3
"""Halves of a span against the span's length, from long per-frame series of a
synthetic bed (`rcfd synth -synth_series FILE -synth_series_only`; the CSV has
columns frame, t_s, bed_height_m, z_cog_m).  Part of bench/synth_stationarity_span.sh.

  synth_stationarity_span.py [--batches B] [--spans 300,600,...] [--markdown OUT] SERIES.csv ...

1. Integrated autocorrelation time tau = 1 + 2 sum rho_k (frames) of the bed height,
   z_CoG and |z_CoG - mean| (what Delta z_CoG averages), from the autocorrelation
   function summed up to the first lag W >= 5 tau(W) (Sokal's window), and, as a check,
   from batch means of 1/16 of a series.
2. Every series is cut into spans of S frames; in each span the halves' relative
   difference of the mean bed height and of Delta z_CoG (mean |z - mean| of each half,
   as `rcfd synth` prints), and the standard error rcfd synth prints with it (batch
   means of the span, B batches).  Per S: the rms of the differences over the spans
   (what a user sees), the standard error expected from tau (2 sqrt(tau var / S) / mean),
   the median of the printed standard errors, and the share of spans whose difference
   is within 2 printed standard errors.  A stationary bed has an rms that falls like
   1 / sqrt(S) and matches the expected standard error.
3. The span at which 2 % is the typical (rms) difference, and at which 2 % is 2 standard
   errors (95 % of spans within 2 %).
Pure Python (no numpy).
"""
import argparse
import csv
import math
import statistics


def read_series(path):
    heights, centres = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            heights.append(float(row["bed_height_m"]))
            centres.append(float(row["z_cog_m"]))
    return heights, centres


def mean(x):
    return math.fsum(x) / len(x)


def mean_deviation(z):
    m = mean(z)
    return mean([abs(v - m) for v in z])


def autocorrelation_time(x, c=5.0, most=4000):
    """tau = 1 + 2 sum_{k=1}^{W} rho_k with the smallest W >= c tau(W) (Sokal 1997)."""
    n = len(x)
    m = mean(x)
    d = [v - m for v in x]
    var = math.fsum(v * v for v in d) / n
    tau = 1.0
    limit = min(most, n // 4)
    for k in range(1, limit):
        rho = math.fsum(d[i] * d[i + k] for i in range(n - k)) / (n * var)
        tau += 2.0 * rho
        if k >= c * tau:
            return tau, str(k)
    return tau, f"> {limit}"  # the window never closed: tau is uncertain


def variance_of_mean_by_batches(x, batches):
    """As rcfd's varianceOfMeanByBatches (src/builders/synthetic/span_statistics.cpp)."""
    m = len(x) // batches
    if batches < 2 or m < 2:
        return float("nan")
    means = [mean(x[b * m:(b + 1) * m]) for b in range(batches)]
    return statistics.variance(means) / batches


def halves(x, statistic, per_frame, batches):
    """Relative difference of `statistic` over the two halves, and the printed standard error."""
    half = len(x) // 2
    first, second = statistic(x[:half]), statistic(x[half:])
    y = per_frame(x)
    error = 2.0 * math.sqrt(variance_of_mean_by_batches(y, batches)) / mean(y)
    return second / first - 1.0, error


def deviations(z):
    m = mean(z)
    return [abs(v - m) for v in z]


def rms(values):
    return math.sqrt(math.fsum(v * v for v in values) / len(values))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("series", nargs="+")
    parser.add_argument("--batches", type=int, default=6, help="batches of a span (rcfd's kHalvesBatches)")
    parser.add_argument("--spans", default="150,300,600,1200,2400,4800,9600,19200")
    parser.add_argument("--dt", type=float, default=5e-3, help="time between frames [s]")
    parser.add_argument("--markdown", help="also write the tables here")
    args = parser.parse_args()
    out = []

    def say(line=""):
        print(line)
        out.append(line)

    data = [read_series(p) for p in args.series]
    frames = sum(len(h) for h, _ in data)
    say(f"Series: {', '.join(p.split('/')[-1] for p in args.series)} ({frames} frames, {frames * args.dt:.0f} s)")
    say()
    say("Integrated autocorrelation time tau [frames] (Sokal window W; batch means of 1/16 of a series):")
    say()
    say("| series | quantity | mean | std | tau (ACF) | W | tau (batch means) |")
    say("|---|---|---|---|---|---|---|")
    taus = {"bed height": [], "z_CoG": [], "abs(z_CoG - mean)": []}
    for path, (h, z) in zip(args.series, data):
        for name, x in (("bed height", h), ("z_CoG", z), ("abs(z_CoG - mean)", deviations(z))):
            tau, window = autocorrelation_time(x)
            batch = len(x) * variance_of_mean_by_batches(x, 16) / statistics.variance(x)
            taus[name].append((tau, len(x), mean(x), statistics.pvariance(x)))
            say(f"| {path.split('/')[-1]} | {name} | {mean(x) * 1e3:.3f} mm | {statistics.pstdev(x) * 1e3:.3f} mm |"
                f" {tau:.1f} | {window} | {batch:.1f} |")
    # Pooled tau, mean and variance (weights: frames), for the expected standard errors.
    pooled = {}
    for name, rows in taus.items():
        n = sum(r[1] for r in rows)
        pooled[name] = tuple(math.fsum(r[i] * r[1] for r in rows) / n for i in (0, 2, 3))
    say()
    say("Halves of spans of S frames (every series cut into spans; rms over the spans of the halves' relative")
    say(f"difference; expected = 2 sqrt(tau var / S) / mean from the pooled tau; printed = median of rcfd synth's")
    say(f"standard error (batch means, {args.batches} batches); within 2 SE = share of spans with |difference| <= 2 printed SE):")
    say()
    say("| S frames | S [s] | spans | bed height rms | expected | printed | within 2 SE |"
        " Delta z_CoG rms | expected | printed | within 2 SE |")
    say("|---|---|---|---|---|---|---|---|---|---|---|")
    spans = [int(s) for s in args.spans.split(",")]
    fit = []
    for S in spans:
        rows = {"h": [], "d": []}
        for h, z in data:
            for start in range(0, len(h) - S + 1, S):
                rows["h"].append(halves(h[start:start + S], mean, lambda x: x, args.batches))
                rows["d"].append(halves(z[start:start + S], mean_deviation, deviations, args.batches))
        if len(rows["h"]) < 2:
            continue
        cells = []
        for key, name in (("h", "bed height"), ("d", "abs(z_CoG - mean)")):
            diffs = [r[0] for r in rows[key]]
            printed = [r[1] for r in rows[key]]
            tau, level, var = pooled[name]
            expected = 2.0 * math.sqrt(tau * var / S) / level
            inside = sum(abs(d) <= 2.0 * e for d, e in rows[key]) / len(diffs)
            cells += [f"{100 * rms(diffs):.1f} %", f"{100 * expected:.1f} %", f"{100 * statistics.median(printed):.1f} %",
                      f"{100 * inside:.0f} %"]
            if key == "d":
                fit.append((S, rms(diffs), len(diffs)))
        say(f"| {S} | {S * args.dt:g} | {len(rows['h'])} | " + " | ".join(cells) + " |")
    say()
    # rms ~ a S^p by least squares in logs over the spans with at least 4 segments.
    points = [(math.log(S), math.log(r)) for S, r, count in fit if count >= 4]
    if len(points) >= 2:
        mx, my = mean([p[0] for p in points]), mean([p[1] for p in points])
        slope = math.fsum((p[0] - mx) * (p[1] - my) for p in points) / math.fsum((p[0] - mx) ** 2 for p in points)
        say(f"Delta z_CoG halves: rms ~ S^{slope:.2f} over spans with >= 4 segments (stationary: S^-0.50)")
    tau, level, var = pooled["abs(z_CoG - mean)"]
    for target, label in ((0.02, "the rms difference is 2 %"), (0.01, "2 % is 2 standard errors (95 % of spans within 2 %)")):
        S = 4.0 * tau * var / (level * target) ** 2
        say(f"Span at which {label}: {S:.0f} frames = {S * args.dt:.0f} s")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
