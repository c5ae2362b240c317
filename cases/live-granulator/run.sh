#!/usr/bin/env bash
# A live granulator, from any directory:
#   cases/live-granulator/run.sh [OUTPUT_DIR]     (default: rcfd-output/live-granulator)
# Environment: RCFD (default build/rcfd), NP (MPI ranks, default 2), SPEED (process seconds the log
# advances per wall second, default 10).  Makes cases/velocity-schedule's databases unless they are
# in build/, then writes an operating log into OUTPUT_DIR/plant.csv while rcfd follows it: a start-up
# (u_sup 1.1 -> 1.3 m/s over 10 s), a drop of the gas to 0.98 m/s at 60 s, recovery to 1.3 m/s at
# 90 s, the end at 120 s (then the stop file).  Prints the forecasts (forecast.csv) and when the live
# bottom layer warned of de-fluidization (bottom.csv).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
out=${1:-$root/rcfd-output/live-granulator}
np=${NP:-2} speed=${SPEED:-10}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
bed=(-synth_cells 20,5,70 -synth_frames 200 -synth_nucleation steady -synth_seed 1 -quiet)
slow=$root/build/velocity-1.1.h5 fast=$root/build/velocity-1.3.h5
mkdir -p "$root/build" "$out"
[ -s "$slow" ] || "$rcfd" synth -o "$slow" "${bed[@]}" -synth_superficial_velocity 1.1
[ -s "$fast" ] || "$rcfd" synth -o "$fast" "${bed[@]}" -synth_superficial_velocity 1.3
log=$out/plant.csv stop=$out/plant.stop
rm -f "$log" "$stop"
# The plant: a row every process second, written as the process goes (SPEED times the wall clock).
(
  echo "time_s,u_sup" >"$log"
  for t in $(seq 0 120); do
    if [ "$t" -le 10 ]; then u=$(awk -v t="$t" 'BEGIN { printf "%.3f", 1.1 + 0.02 * t }')
    elif [ "$t" -lt 60 ] || [ "$t" -ge 90 ]; then u=1.3
    else u=0.98; fi
    echo "$t,$u" >>"$log"
    sleep "$(awk -v s="$speed" 'BEGIN { print 1 / s }')"
  done
  touch "$stop"
) &
writer=$!
mpiexec -n "$np" "$rcfd" run -options_file "$root/cases/live-granulator/case.yaml" -db "$fast,$slow" \
  -live "$log" -live_stop_file "$stop" -output_dir "$out"
wait $writer
echo "forecasts (issued at, members warning, mean time to the warning [s], u_mf/u_sup at the horizon):"
awk -F, 'NR > 1 { printf "  %5g s  %s of %s  %8s  %.4f\n", $1, $10, $3, $11, $8 }' "$out/forecast.csv"
warned=$(awk -F, 'NR > 1 && $5 == 1 { print $1; exit }' "$out/bottom.csv")
echo "live bottom layer: de-fluidization warned at ${warned:-never} s (bottom.csv)"
