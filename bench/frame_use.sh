#!/usr/bin/env bash
# How evenly stitched paths use the frames of a database (issue 15): 60 s random
# paths (12,000 steps) of the default bed, seeds 1-3, with the uniform draw among
# the 4 best matches (the default) and with -path_least_used among 4, 16 and 64.
# Per rule: the worst factor from uniform over frames 1..K-1 (max(largest/mean,
# mean/smallest); frame 0 is entered only at the start), the largest and
# smallest use over the mean, how many frames are within a factor 2 of the mean,
# and the share of steps in each quarter of the frames.  The path does not
# depend on the physics, so the runs drift nothing.  Writes bench/results/frame_use.md.
# usage: bench/frame_use.sh [BUILD_DIR] [DATABASE] [T_END]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
tend=${3:-60}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
"$build/rcfd" recurrence "$db" -quiet >/dev/null # stored once, used by every run
K=$("$build/rcfd" info "$db" | awk '$1 == "frames:" { print $2 }')
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
rules=("uniform draw, 4 candidates|-path_candidates 4"
  "least used, 4 candidates|-path_least_used -path_candidates 4"
  "least used, 16 candidates|-path_least_used -path_candidates 16"
  "least used, 64 candidates|-path_least_used -path_candidates 64")
out=bench/results/frame_use.md
mkdir -p bench/results
{
  echo "# frame use of $tend s random paths, $db ($K frames), $(date -u +%Y-%m-%dT%H:%MZ)"
  echo
  echo "| rule | seed | factor from uniform | largest / mean | smallest / mean | frames within x2 | quarters of the frames: share of steps |"
  echo "|---|---|---|---|---|---|---|"
  for entry in "${rules[@]}"; do
    read -r -a opt <<<"${entry#*|}"
    for seed in 1 2 3; do
      run=$dir/run-$seed
      "$build/rcfd" run -db "$db" -t_end "$tend" -path_type random -path_seed $seed "${opt[@]}" -drift_model none \
        -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -fields 0 -plot 0 -quiet \
        -monitor_every 1000 -output_dir "$run" >/dev/null
      awk -v K="$K" -v rule="${entry%%|*}" -v seed=$seed '!/^#/ { u[$1]++ } END {
        n = 0; for (k = 1; k < K; k++) n += u[k]; mean = n / (K - 1); lo = 1e300; hi = 0; within = 0
        for (k = 1; k < K; k++) { v = u[k] + 0; if (v < lo) lo = v; if (v > hi) hi = v
          if (v >= mean / 2 && v <= 2 * mean) within++ }
        f = lo > 0 ? (hi / mean > mean / lo ? hi / mean : mean / lo) : "never used"
        total = n + u[0]; q = ""
        for (b = 0; b < 4; b++) { s = 0; for (k = int(b * K / 4); k < int((b + 1) * K / 4); k++) s += u[k]
          q = q sprintf("%s%.2f", b ? " " : "", s / total) }
        printf "| %s | %d | %s | %.2f | %.2f | %d / %d | %s |\n", rule, seed,
          (lo > 0 ? sprintf("%.2f", f) : f), hi / mean, lo / mean, within, K - 1, q }' "$run/path.txt"
    done
  done
} | tee "$out"
