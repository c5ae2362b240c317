#!/usr/bin/env bash
# What `rcfd markov` costs on the default bed, and how far each size class's period stationary
# distribution lies from a run's (docs/markov.md, "Size classes"): the bulk alone (zones spray and
# bottom), the two classes of the recommended drift with each class's drift read off as matrices
# (and, with OPERATOR=1, with the drift operator at every step: about 4.5 min more), and the
# classes' period chains with the wrap carried on the mean composition and on the stationary
# background, whose centres are compared with a 60 s run's at frame 0.
# Wall seconds and peak memory of each command (memory needs /usr/bin/time), the seconds the size
# classes took (the command's own "seconds:" line), and the largest distance of a class's centre
# from the run's.  Prints a table and writes it to bench/results/markov_cost.md.
# usage: bench/markov_cost.sh [BUILD_DIR] [DATABASE]   (env: NP, default 1; OPERATOR, default 0)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
db=${2:-build/default-bed.h5}
np=${NP:-1}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results
out=bench/results/markov_cost.md
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
zones=(-zones spray,bottom -zone_spray_heights 0.25,0.3 -zone_bottom_layers 0,9)
classes=(-options_file cases/recommended-drift.yaml -superficial_velocity 1.1
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436)
period=(-markov_spectrum period -markov_wrap carry -markov_mix 0)

wall="" rss="" log=""
timed() { # runs the command; sets wall (s), rss (MB) and log
  local t0 t1
  log="$work/log"
  t0=$(date +%s.%N)
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -f %M -o "$work/mem" "$@" >"$log" 2>&1
    rss=$(awk '{ printf "%.0f", $1 / 1024 }' "$work/mem")
  else
    "$@" >"$log" 2>&1
    rss="—"
  fi
  t1=$(date +%s.%N)
  wall=$(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }')
}
classSeconds() { sed -n 's/.*size classes \([0-9.]*\);.*/\1/p' "$log"; }
backgroundSeconds() { sed -n 's/.*background \([0-9.]*\), size classes.*/\1/p' "$log"; }
markov() { timed mpiexec -n "$np" "$build/rcfd" markov "$db" -plot 0 "$@"; } # the report gives the seconds

# The run's centres at 60 s (40 periods of 1.5 s: frame 0 after the carry).
"$build/rcfd" run -db "$db" "${classes[@]}" -t_end 60 -profiles -profiles_window 60,60 -observables_every 300 \
  -output_dir "$work/run" -quiet -plot 0 -fields 0
read -r runSmall runLarge < <(awk -F, '!/^#/ && $1 != "z" { s += $1 * $2; n += $2; l += $1 * $3; m += $3 }
  END { printf "%.6f %.6f\n", s / n, l / m }' "$work/run/profiles.csv")
offset() { # the largest |centre - run's| of the two classes in summary.csv of $1, in mm
  awk -F, -v s="$runSmall" -v l="$runLarge" '$1 == "class_d1.459mm_period_height" { a = $2 - s }
    $1 == "class_d4.075mm_period_height" { b = $2 - l }
    END { a = a < 0 ? -a : a; b = b < 0 ? -b : b; printf "%.2f", 1000 * (a > b ? a : b) }' "$1/summary.csv"
}

{
  echo "# rcfd markov's cost, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $np rank(s)"
  echo
  echo "Default bed ($db). Run's class centres at 60 s: $runSmall m (1.459 mm), $runLarge m (4.075 mm)."
  echo
  echo "| analysis | wall s | peak MB | size classes s | background s | largest class centre − run's [mm] |"
  echo "|---|---|---|---|---|---|"
  markov "${zones[@]}" -o "$work/bulk"
  echo "| bulk: mixing (13 starts, 120 s), zones spray and bottom | $wall | $rss | | | |"
  markov "${zones[@]}" "${classes[@]}" -o "$work/matrix"
  echo "| the same with two classes, drift as matrices | $wall | $rss | $(classSeconds) | | |"
  if [ "${OPERATOR:-0}" = 1 ]; then
    markov "${zones[@]}" "${classes[@]}" -markov_class_drift operator -o "$work/operator"
    echo "| the same, the drift operator at every step | $wall | $rss | $(classSeconds) | | |"
  fi
  markov "${classes[@]}" "${period[@]}" -o "$work/mean"
  echo "| classes' period chains (carry), mean composition | $wall | $rss | $(classSeconds) | | $(offset "$work/mean") |"
  markov "${classes[@]}" "${period[@]}" -markov_class_background stationary -o "$work/stationary"
  echo "| classes' period chains (carry), stationary background | $wall | $rss | $(classSeconds) | $(backgroundSeconds) | $(offset "$work/stationary") |"
} | tee "$out"
