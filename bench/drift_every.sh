#!/usr/bin/env bash
# Run time against error for -drift_every N: the drift of N steps applied at
# once every N steps.  Penta-disperse default bed, model B, k_d = 5e3, replay,
# NP ranks (default 2), T simulated seconds (default 20).  Error: the
# segregation Delta z = z_CoG(smallest) - z_CoG(largest) against N = 1, as
# the RMS difference over the run relative to the RMS of Delta z, and the
# difference of its mean over the last quarter relative to that mean.
# Prints a table and writes it to bench/results/drift_every.md.
# usage: bench/drift_every.sh [BUILD_DIR] [DATABASE]   (env: NP, T, RUNS)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
np=${NP:-2} t=${T:-20} runs=${RUNS:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results
out=bench/results/drift_every.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
penta=(-fractions_diameters 1.783e-3,1.998e-3,2.284e-3,2.855e-3,3.426e-3 -fractions_mass_shares 0.100,0.205,0.445,0.150,0.100)
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# Delta z column of a cog.csv, one value per line (rows every 8 steps).
deltaz() { awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "delta_z_m") c = i; next } { print $c }' "$1"; }
{
  echo "# -drift_every: run time against error, $(date -u +%Y-%m-%dT%H:%MZ), $np ranks of $(nproc) cores"
  echo
  echo "Penta-disperse default bed, replay, model B, k_d = 5e3, $t s simulated, monitor every 8 steps; wall time: median of $runs runs."
  echo
  echo "| N | wall s / simulated s | simulated s / wall s | RMS error of Δz (relative) | error of late mean Δz (relative) |"
  echo "|---|---|---|---|---|"
  for every in 1 2 4 8; do
    pers=()
    for ((r = 0; r < runs; ++r)); do
      log=$(mpiexec -n "$np" "$build/rcfd" run -db "$db" -t_end "$t" -fields 0 -plot 0 -monitor_every 8 \
        -monitor_digits 12 -drift_every $every "${penta[@]}" -output_dir "$work/n$every" -progress_interval 1000)
      pers+=("$(sed -n 's/.*(\([0-9.e+-]*\) wall s per simulated s).*/\1/p' <<<"$log")")
    done
    per=$(printf '%s\n' "${pers[@]}" | median)
    err=$(paste <(deltaz "$work/n1/cog.csv") <(deltaz "$work/n$every/cog.csv") | awk '
      { a[NR] = $1; b[NR] = $2 }
      END {
        for (i = 1; i <= NR; ++i) { d2 += (b[i] - a[i])^2; r2 += a[i]^2 }
        for (i = int(0.75 * NR); i <= NR; ++i) { ma += a[i]; mb += b[i]; ++m }
        printf "%.2e | %.2e", sqrt(d2 / r2), (mb - ma) / ma }')
    echo "| $every | $per | $(awk -v p="$per" 'BEGIN { printf "%.1f", 1 / p }') | $err |"
  done
} | tee "$out"
echo "written to $out"
