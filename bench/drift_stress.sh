#!/usr/bin/env bash
# Long stress run of the drift operator: a small synthetic bed, 20 fractions
# from 0.5 to 6 mm, model B with k_d 100x the paper's, one million steps.
# The run stops with an error on any leak or non-finite mass (mass ledger);
# the table reports conservation, the smallest mass and the sub-steps taken.
# usage: bench/drift_stress.sh [BUILD_DIR] [STEPS]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
steps=${2:-1000000}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# CELLS (default 10,4,40 over 0.05 x 0.02 x 0.2 m) sets the bed's resolution; the cell size
# follows, so a coarser bed takes fewer, larger cells.
cells=${CELLS:-10,4,40}
db=/tmp/rcfd-stress-bed-${cells//,/x}.h5
[ -s $db ] || "$build/rcfd" synth -o $db -synth_cells $cells -synth_length 0.05,0.02,0.2 \
  -synth_bed_height 0.08 -synth_frames 100 -quiet
d=$(awk 'BEGIN { for (i = 0; i < 20; ++i) printf "%s%.4e", (i ? "," : ""), 0.5e-3 + 5.5e-3 * i / 19 }')
w=$(awk 'BEGIN { for (i = 0; i < 20; ++i) printf "%s0.05", (i ? "," : "") }')
tend=$(awk -v n="$steps" 'BEGIN { print n * 5e-3 }')
mkdir -p bench/results
out=bench/results/drift_stress-${steps}-${cells//,/x}.md
start=$(date +%s)
np=${NP:-1}
log=$(mpiexec -n $np "$build/rcfd" run -db $db -t_end "$tend" -fractions_diameters "$d" \
  -fractions_mass_shares "$w" -drift_model B -drift_kd 5e5 -drift_hindered -fields 0 -plot 0 \
  -monitor_every 10000 -output_dir /tmp/rcfd-stress -drift_view -progress_interval 60 2>&1)
end=$(date +%s)
{
  echo "# drift stress, $(date -u +%Y-%m-%dT%H:%MZ), $steps steps, $cells cells, $np rank(s), $((end - start)) s wall"
  echo '```'
  grep -E "drift:|sub-steps|largest relative|Done" <<<"$log"
  echo '```'
  min=$(awk -F, 'NR > 1 { v = $(NF - 1); if (m == "" || v < m) m = v } END { print m }' /tmp/rcfd-stress/cog.csv)
  echo "smallest cell mass over the run's samples: $min kg"
} | tee "$out"
