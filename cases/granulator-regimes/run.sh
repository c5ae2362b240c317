#!/usr/bin/env bash
# A granulator whose bed changes regime as it grows (issue 15), from any directory:
#   cases/granulator-regimes/run.sh [OUTPUT_DIR]     (default: rcfd-output/granulator-regimes)
# Environment: RCFD (default build/rcfd), NP (MPI ranks, default 2).  Makes two synthetic databases
# of the default bed with steady nucleation (build/regimes-{1.1,0.9}.h5, unless there), then runs
# growth (cases/granulator/case.yaml + case.yaml) for 240 s three times:
#   switching/   the state rule: the low-agitation database once the bottom layer's d32 passes 2.38 mm
#   bubbling/    the 1.1 m/s database throughout (a threshold never reached)
#   calm/        the low-agitation database throughout
# and prints the bottom layer's d32 and u_mf/u_sup of the three every 40 s, with the switch and the
# de-fluidization times.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
out=${1:-$root/rcfd-output/granulator-regimes}
np=${NP:-2}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bubbling=$root/build/regimes-1.1.h5 calm=$root/build/regimes-0.9.h5
mkdir -p "$root/build" # absent in a checkout used with an installed rcfd (RCFD=...)
[ -s "$bubbling" ] || "$rcfd" synth -o "$bubbling" -synth_nucleation steady -synth_superficial_velocity 1.1 -quiet
[ -s "$calm" ] || "$rcfd" synth -o "$calm" -synth_nucleation steady -synth_superficial_velocity 0.9 -quiet
run=(mpiexec -n "$np" "$rcfd" run -options_file "$root/cases/granulator/case.yaml"
  -options_file "$root/cases/granulator-regimes/case.yaml" -db "$bubbling,$calm")
"${run[@]}" -output_dir "$out/switching" | grep -E "^(Switched|Warning|WARNING|Done)"
"${run[@]}" -db_switch_thresholds 1 -output_dir "$out/bubbling" -quiet
"${run[@]}" -db_switch_thresholds 1e-6 -db_switch_initial 1 -output_dir "$out/calm" -quiet
echo "bottom layer: d32 [mm] and u_mf/u_sup"
printf '%6s %18s %18s %18s\n' t_s switching bubbling calm
for t in 0 40 80 120 160 200 240; do
  row=$t
  for r in switching bubbling calm; do
    row="$row $(awk -F, -v t="$t" 'NR > 1 && ($1 - t) * ($1 - t) < 1e-12 { printf "%.3f/%.3f", $2 * 1e3, $3 / $4 }' \
      "$out/$r/bottom.csv")"
  done
  printf '%6s %18s %18s %18s\n' $row
done
for r in switching bubbling calm; do
  printf '%-10s de-fluidized from: %s\n' "$r" \
    "$(awk -F, 'NR > 1 && $5 == 1 { print $1 " s"; exit }' "$out/$r/bottom.csv")"
done
echo "switches: $out/switching/switches.csv"
