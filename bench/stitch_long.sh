#!/usr/bin/env bash
# A 1,000 s stitched run (200,000 steps) of the default bed with the paper's
# bi-wide inventory and model B: conservation of every fraction, the smallest
# mass, and the bulk mismatch between state and database over time (it must
# not grow).  Prints a table and writes it to bench/results/stitch_long.md.
# usage: bench/stitch_long.sh [BUILD_DIR] [DATABASE] [T_END]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
tend=${3:-1000}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results
out=bench/results/stitch_long.md
dir=/tmp/rcfd-stitch-long
start=$(date +%s)
np=${NP:-1}
log=$(mpiexec -n $np "$build/rcfd" run -db "$db" -t_end "$tend" -path_type random -path_seed 5 \
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -fields 0 \
  -monitor_every 200 -output_dir $dir -progress_interval 60 -carry_view -drift_view 2>&1)
end=$(date +%s)
{
  echo "# stitched run of $tend s, $(date -u +%Y-%m-%dT%H:%MZ), $np rank(s), $((end - start)) s wall"
  echo '```'
  grep -E "carry:|sub-steps|largest relative|Done" <<<"$log"
  echo '```'
  echo
  echo "| window [s] | mean bulk mismatch | max bulk mismatch | mean delta z [mm] |"
  echo "|---|---|---|---|"
  awk -F, -v T="$tend" 'NR > 1 {
      w = int($1 / (T / 10)); if (w > 9) w = 9
      n[w]++; s[w] += $NF; if ($NF > m[w]) m[w] = $NF; dz[w] += $5 }
    END { for (w = 0; w < 10; ++w)
      printf "| %g-%g | %.2e | %.2e | %.2f |\n", w * T / 10, (w + 1) * T / 10, s[w] / n[w], m[w], 1e3 * dz[w] / n[w] }' $dir/cog.csv
  first=$(sed -n 2p $dir/cog.csv | cut -d, -f6,7)
  last=$(tail -n 1 $dir/cog.csv | cut -d, -f6,7)
  echo
  echo "fraction masses at t = 0: $first kg; at t = $tend s: $last kg"
} | tee "$out"
