#!/usr/bin/env bash
# Speed of replay runs of the default bed: wall seconds per simulated second
# (time stepping only, the median of RUNS runs; loading is timed apart), peak
# memory per rank, and the shift step's memory bandwidth next to a triad
# measured in the same run.  Prints a table and writes it to bench/results/.
# usage: bench/replay_speed.sh [BUILD_DIR] [DATABASE]   (env: RUNS, default 3; ROWS=granulator: only
# the granulator's row: cases/granulator/case.yaml with growth, feed and discharge on a stitched path,
# GRANULATOR_T_END simulated seconds, default the case's 60, on 2 ranks; its last column says which
# share of the stepping's wall time the three zone operators took, from the run's "operators:" line;
# written to bench/results/replay_speed_granulator.md)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
runs=${RUNS:-3}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results
out=bench/results/replay_speed.md
[ "${ROWS:-all}" = granulator ] && out=bench/results/replay_speed_granulator.md
penta=(-fractions_diameters 1.783e-3,1.998e-3,2.284e-3,2.855e-3,3.426e-3 -fractions_mass_shares 0.100,0.205,0.445,0.150,0.100)
bi=(-fractions_diameters 1.950e-3,2.820e-3 -fractions_mass_shares 0.473,0.527)
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# The shipped granulator (docs/granulation.md) as a user runs it, stitched: a row of the table whose
# shift-step columns are left empty and whose last column is the zone operators' share of the step.
granulator_row() {
  local pers=() loads=() shares=() mem=0 log t0 t1 wall t=${GRANULATOR_T_END:-60}
  local window; window=$(awk -v t="$t" 'BEGIN { printf "%g,%g", (t > 10 ? t - 10 : 0), t }') # the case's 50,60 at 60 s
  for ((r = 0; r < runs; ++r)); do
    t0=$(date +%s.%N)
    log=$(mpiexec -n 2 "$build/rcfd" run -options_file cases/granulator/case.yaml -db "$db" \
      -pipeline shift,drift,carry,growth,feed,discharge -growth_rate 1 -feed_rate 0.2 -discharge_rate 0.2 \
      -path_type random -path_seed 1 -t_end "$t" -halves_window "$window" -plot 0 \
      -output_dir /tmp/rcfd-bench-granulator -progress_interval 1000)
    t1=$(date +%s.%N)
    wall=$(sed -n 's/.* in \([0-9.e+-]*\) s wall.*/\1/p' <<<"$log")
    pers+=("$(sed -n 's/.*(\([0-9.e+-]*\) wall s per simulated s).*/\1/p' <<<"$log")")
    mem=$(sed -n 's/.*peak memory \([0-9]*\) MB.*/\1/p' <<<"$log")
    loads+=("$(awk -v a="$t0" -v b="$t1" -v w="$wall" 'BEGIN { printf "%.2f", b - a - w }')")
    shares+=("$(sed -n 's/.*operators: \([0-9.e+-]*\) s of the wall.*growth \([0-9.e+-]*\) s, feed \([0-9.e+-]*\) s, discharge \([0-9.e+-]*\) s.*/\1 \2 \3 \4/p' <<<"$log" |
      awk -v w="$wall" '{ printf "%.0f", 100 * ($2 + $3 + $4) / w }')")
  done
  local per load share
  per=$(printf '%s\n' "${pers[@]}" | median)
  load=$(printf '%s\n' "${loads[@]}" | median)
  share=$(printf '%s\n' "${shares[@]}" | median)
  echo "| 5 | 2 | granulator (shift,drift,carry,growth,feed,discharge; stitched, $t s) | moving | $per | $(awk -v p="$per" 'BEGIN { printf "%.1f", 1 / p }') | $load | $mem | | | | growth, feed, discharge: $share % of the stepping |"
}
{
  echo "# replay speed, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  echo
  echo "Median of $runs runs of 10 simulated seconds each (monitor every 20 steps, no fields); load = whole process minus stepping."
  echo
  echo "| nf | ranks | pipeline | shift kernel | wall s / simulated s | simulated s / wall s | load s | peak MB/rank | shift step ms | shift GB/s | triad GB/s | % of triad |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  granulator_row
  [ "${ROWS:-all}" = granulator ] && exit 0
  for nf in 2 5; do
    if [ $nf = 2 ]; then fr=("${bi[@]}"); else fr=("${penta[@]}"); fi
    for np in 1 2; do
      for pipe in shift shift,drift; do
        kernels=(moving)
        [ $nf = 5 ] && [ $pipe = shift ] && kernels=(moving maij)
        for kernel in "${kernels[@]}"; do
          pers=() loads=() mem=0
          for ((r = 0; r < runs; ++r)); do
            t0=$(date +%s.%N)
            log=$(mpiexec -n $np "$build/rcfd" run -db "$db" -t_end 10 -fields 0 -plot 0 -monitor_every 20 \
              -pipeline $pipe -shift_kernel $kernel "${fr[@]}" -output_dir /tmp/rcfd-bench -progress_interval 1000)
            t1=$(date +%s.%N)
            wall=$(sed -n 's/.* in \([0-9.e+-]*\) s wall.*/\1/p' <<<"$log")
            pers+=("$(sed -n 's/.*(\([0-9.e+-]*\) wall s per simulated s).*/\1/p' <<<"$log")")
            mem=$(sed -n 's/.*peak memory \([0-9]*\) MB.*/\1/p' <<<"$log")
            loads+=("$(awk -v a="$t0" -v b="$t1" -v w="$wall" 'BEGIN { printf "%.2f", b - a - w }')")
          done
          per=$(printf '%s\n' "${pers[@]}" | median)
          load=$(printf '%s\n' "${loads[@]}" | median)
          bw=$(mpiexec -n $np "$build/shift_bandwidth" "$db" $nf 3000 $kernel)
          ms=$(sed -n 's/.*shift step \([0-9.]*\) ms.*/\1/p' <<<"$bw")
          gbs=$(sed -n 's/.*ms  \([0-9.]*\) GB\/s.*/\1/p' <<<"$bw")
          triad=$(sed -n 's/.*triad \([0-9.]*\) GB\/s.*/\1/p' <<<"$bw")
          pct=$(sed -n 's/.*GB\/s  \([0-9]*\) % of triad.*/\1/p' <<<"$bw")
          rate=$(awk -v p="$per" 'BEGIN { printf "%.1f", 1 / p }')
          echo "| $nf | $np | $pipe | $kernel | $per | $rate | $load | $mem | $ms | $gbs | $triad | $pct |"
        done
      done
    done
  done
} | tee "$out"
echo "written to $out"
