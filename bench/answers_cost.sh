#!/usr/bin/env bash
# What the answers cost: a penta replay of the default bed (shift, drift, carry; cog.csv every 20
# steps) with none of the answers' monitors, and with all of them every 20 steps (profiles, halves,
# bottom layer with a zone, mixing index, bed dynamics; snapshots at 2 times).  Wall seconds of the
# time stepping (the run's own "Done" line), the median of RUNS runs, and their ratio (target: all
# at most 20 % slower than none); on a shared machine that ratio is noisy, so the table also gives
# the answers' own share measured inside each "all" run (the run's "monitors:" line: their seconds
# over the rest of the stepping), which other processes slow down alike.
# Prints a table and writes it to bench/results/answers_cost.md.
# usage: bench/answers_cost.sh [BUILD_DIR] [DATABASE]   (env: RUNS, default 3; NP, default "1 2"; T_END, default 10)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
runs=${RUNS:-3}
ranks=${NP:-1 2}
tend=${T_END:-10}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results
out=bench/results/answers_cost.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
penta=(-fractions_diameters 1.783e-3,1.998e-3,2.284e-3,2.855e-3,3.426e-3 -fractions_mass_shares 0.100,0.205,0.445,0.150,0.100)
all=(-observables_every 20 -profiles -halves -bottom_layer -zones low -zone_low_layers 0,3 -mixing_index -bed_dynamics
  -snapshots_times 1,$tend)
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
wall() { # wall seconds of the stepping, from the run's Done line
  sed -n 's/.* in \([0-9.e+-]*\) s wall.*/\1/p' <<<"$1"
}
share() { # the answers' monitors' seconds over the rest of the stepping, from the Done and monitors lines
  local w m c
  w=$(wall "$1")
  m=$(sed -n 's/.*monitors: \([0-9.e+-]*\) s of the wall.*/\1/p' <<<"$1")
  c=$(sed -n 's/.*(cog.csv \([0-9.e+-]*\) s.*/\1/p' <<<"$1")
  awk -v w="$w" -v m="$m" -v c="$c" 'BEGIN { printf "%.4f", (m - c) / (w - (m - c)) }'
}
{
  echo "# answers' cost, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo
  echo "Penta replay of the default bed, $tend simulated s, pipeline shift,drift,carry, cog.csv every 20 steps, no"
  echo "fields; median of $runs runs of the stepping's wall time. \"all\": every answer every 20 steps."
  echo
  echo "| ranks | none: wall s | all: wall s | all / none | answers' own share in the all runs |"
  echo "|---|---|---|---|---|"
  for np in $ranks; do
    none=() some=() shares=()
    for ((r = 0; r < runs; ++r)); do
      common=(-db "$db" -t_end "$tend" -fields 0 -plot 0 -monitor_every 20 "${penta[@]}" -progress_interval 1000)
      none+=("$(wall "$(mpiexec -n $np "$build/rcfd" run "${common[@]}" -output_dir "$work/none")")")
      log=$(mpiexec -n $np "$build/rcfd" run "${common[@]}" "${all[@]}" -output_dir "$work/all")
      some+=("$(wall "$log")")
      shares+=("$(share "$log")")
    done
    a=$(printf '%s\n' "${none[@]}" | median)
    b=$(printf '%s\n' "${some[@]}" | median)
    c=$(printf '%s\n' "${shares[@]}" | median)
    echo "| $np | $a | $b | $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.3f", b / a }') | $(awk -v c="$c" 'BEGIN { printf "%.1f %%", 100 * c }') |"
  done
} | tee "$out"
