#!/usr/bin/env bash
# The velocity schedule of case.yaml and the two databases alone, from any directory:
#   cases/velocity-schedule/run.sh [OUTPUT_DIR]     (default: rcfd-output/velocity-schedule)
# Environment: RCFD (default build/rcfd), NP (MPI ranks, default 2).  Makes three synthetic
# databases of one 20 x 5 x 70 bed, 200 frames each, steady nucleation, at u_sup 1.1, 1.2 and
# 1.3 m/s (rcfd synth -synth_superficial_velocity: two-phase scaling of the bubbles, docs/synthetic.md;
# build/velocity-{1.1,1.2,1.3}.h5, unless there), and runs schedule/ (1.3, 1.1 from 20 s, 1.3 from
# 40 s), slow/ and fast/ (each alone: a constant schedule), blend/ (1.1 and 1.3 blended at 1.2) and
# middle/ (the database recorded at 1.2 alone), then prints delta_z = z_CoG(small) - z_CoG(large)
# of all five at 10, 20, 30, 40, 50 and 60 s.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
out=${1:-$root/rcfd-output/velocity-schedule}
np=${NP:-2}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bed=(-synth_cells 20,5,70 -synth_frames 200 -synth_nucleation steady -synth_seed 1 -quiet)
slow=$root/build/velocity-1.1.h5 middle=$root/build/velocity-1.2.h5 fast=$root/build/velocity-1.3.h5
mkdir -p "$root/build" # absent in a checkout used with an installed rcfd (RCFD=...)
[ -s "$slow" ] || "$rcfd" synth -o "$slow" "${bed[@]}" -synth_superficial_velocity 1.1
[ -s "$middle" ] || "$rcfd" synth -o "$middle" "${bed[@]}" -synth_superficial_velocity 1.2
[ -s "$fast" ] || "$rcfd" synth -o "$fast" "${bed[@]}" -synth_superficial_velocity 1.3
run=(mpiexec -n "$np" "$rcfd" run -options_file "$root/cases/velocity-schedule/case.yaml")
"${run[@]}" -db "$fast,$slow" -output_dir "$out/schedule"
# Each database alone: the same set at a constant velocity, which never switches.
"${run[@]}" -db "$fast,$slow" -db_switch_schedule 0:1.1 -output_dir "$out/slow" -quiet
"${run[@]}" -db "$fast,$slow" -db_switch_schedule 0:1.3 -output_dir "$out/fast" -quiet
# The blend validated against a database recorded at the middle condition.
"${run[@]}" -db "$fast,$slow" -db_switch_type blend -db_switch_schedule 0:1.2 -output_dir "$out/blend" -quiet
"${run[@]}" -db "$fast,$middle,$slow" -db_switch_schedule 0:1.2 -output_dir "$out/middle" -quiet
echo "delta_z [mm] (z_CoG of 1.95 mm minus 2.82 mm; positive: the large sink)"
printf '%6s %10s %10s %10s %10s %10s\n' t_s schedule slow fast blend middle
for t in 10 20 30 40 50 60; do
  row=$t
  for r in schedule slow fast blend middle; do
    row="$row $(awk -F, -v t="$t" 'NR > 1 && ($1 - t) * ($1 - t) < 1e-12 { printf "%.3f", $5 * 1e3 }' "$out/$r/cog.csv")"
  done
  printf '%6s %10s %10s %10s %10s %10s\n' $row
done
echo "switches: $out/schedule/switches.csv"
