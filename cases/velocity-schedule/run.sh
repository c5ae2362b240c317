#!/usr/bin/env bash
# The velocity schedule of case.yaml and the two databases alone, from any directory:
#   cases/velocity-schedule/run.sh [OUTPUT_DIR]     (default: rcfd-output/velocity-schedule)
# Environment: RCFD (default build/rcfd), NP (MPI ranks, default 2).  Makes two synthetic
# databases of one 20 x 5 x 70 bed, 200 frames each (build/velocity-{slow,fast}.h5, unless there):
#   slow  u_sup 1.1 m/s: 1500 bubbles per s and m^2 of distributor
#   fast  u_sup 1.3 m/s: 4000 bubbles per s and m^2 (more gas, more bubbles)
# and runs schedule/ (fast, slow from 20 s, fast from 40 s), slow/ and fast/ (each alone: a constant
# schedule), then
# prints delta_z = z_CoG(small) - z_CoG(large) of the three at 10, 20, 30, 40, 50 and 60 s.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
out=${1:-$root/rcfd-output/velocity-schedule}
np=${NP:-2}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bed=(-synth_cells 20,5,70 -synth_frames 200 -quiet)
slow=$root/build/velocity-slow.h5 fast=$root/build/velocity-fast.h5
[ -s "$slow" ] || "$rcfd" synth -o "$slow" "${bed[@]}" -synth_nucleation_rate 1500 -synth_seed 1 -superficial_velocity 1.1
[ -s "$fast" ] || "$rcfd" synth -o "$fast" "${bed[@]}" -synth_nucleation_rate 4000 -synth_seed 2 -superficial_velocity 1.3
run=(mpiexec -n "$np" "$rcfd" run -options_file "$root/cases/velocity-schedule/case.yaml")
"${run[@]}" -db "$fast,$slow" -output_dir "$out/schedule"
# Each database alone: the same set at a constant velocity, which never switches.
"${run[@]}" -db "$fast,$slow" -db_switch_schedule 0:1.1 -output_dir "$out/slow" -quiet
"${run[@]}" -db "$fast,$slow" -db_switch_schedule 0:1.3 -output_dir "$out/fast" -quiet
echo "delta_z [mm] (z_CoG of 1.95 mm minus 2.82 mm; positive: the large sink)"
printf '%6s %10s %10s %10s\n' t_s schedule slow fast
for t in 10 20 30 40 50 60; do
  row=$t
  for r in schedule slow fast; do
    row="$row $(awk -F, -v t="$t" 'NR > 1 && ($1 - t) * ($1 - t) < 1e-12 { printf "%.3f", $5 * 1e3 }' "$out/$r/cog.csv")"
  done
  printf '%6s %10s %10s %10s\n' $row
done
echo "switches: $out/schedule/switches.csv"
