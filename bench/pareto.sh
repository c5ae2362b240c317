#!/usr/bin/env bash
# The Pareto front of run time against error (issue 14) on dpm-bi-narrow, from any directory:
#   bench/pareto.sh [OUTPUT_DIR]          (default rcfd-output/pareto; about 10 minutes on one core)
# For each combination of
#   space coarsening  rcfd coarsen -factor 1,1,1 | 2,1,1 | 1,1,2 | 2,1,2   (the bed is 12 cells deep at rest)
#   time stride       1 | 2 | 4  (-time_factor 2, once or twice: frames composed, dt_rec 5, 10, 20 ms)
#   drift every       1 | 4 steps (-drift_every)
#   frame precision   PRECISIONS (default "full"; "full q16" adds 16-bit weights; precision_options below)
# the drift law B scaled by the agitation, (a/a_bar)^2 (-drift_agitation leaving
# -drift_agitation_exponent 2), is calibrated for that resolution on the database of 0.2-1.7 s
# (rcfd calibrate, RMS objective, a coarse scan of k_d and a short golden section), then the whole
# replay 0.2-3.49 s is run with that k_d and scored against the CFD-DEM reference: Delta_seg over
# 0.5-1.5 s (Eq. 7) and the RMS of Delta z over the whole replay divided by the reference's peak.
# Costs of the scoring replay (median of REPEATS runs, default 5): wall seconds of the time loop per
# simulated second, wall seconds of the whole process (load included) and its peak memory.
# Writes OUTPUT_DIR/pareto.csv and bench/results/pareto.{md,csv,png} (the figure: bench/pareto.py).
# Environment: RCFD (default build/rcfd), REFERENCE (default ../shared/reference/dpm-bi-narrow),
# PRECISIONS, REPEATS, SPACE ("1,1,1 2,1,1 1,1,2 2,1,2"), STRIDES ("1 2 4"), DRIFT_EVERY ("1 4").
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
ref=${REFERENCE:-$root/../shared/reference/dpm-bi-narrow}
out=${1:-$root/rcfd-output/pareto}
results=$root/bench/results
precisions=${PRECISIONS:-full}
repeats=${REPEATS:-5}
spaces=${SPACE:-"1,1,1 2,1,1 1,1,2 2,1,2"}
strides=${STRIDES:-"1 2 4"}
drift_everys=${DRIFT_EVERY:-"1 4"}
mkdir -p "$out" "$results"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# ---- HOOK: reduced-precision frames (issue 14, "Compact frames"; another change adds them) ----------
# precision_options P: the options that make `rcfd coarsen` write frames of precision P: "full"
# (double weights) or "q16", "q12", "q8" (weights quantised to multiples of 2^-16 ... with exact column
# sums, held in 2 bytes: docs/performance.md, "Compact frames").
precision_options() {
  case $1 in
    full) echo "" ;;
    q16 | q12 | q8) echo "-weights ${1#q}" ;;
    *) echo "bench/pareto.sh: frame precision '$1' is not known yet; add it to precision_options" >&2; return 1 ;;
  esac
}
# -----------------------------------------------------------------------------------------------

# The databases of the full replay (0.2-3.49 s) and of the fit window (0.2-1.7 s), both starting from
# the snapshot at 0.2 s, its composition, and the reference (as cases/dpm-bi-narrow/drift_laws.sh).
input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
[ -f "$out/replay.h5" ] || "$rcfd" build "${input[@]}" -window 39,-1 -o "$out/replay.h5" -init_out "$out/init.h5" -quiet
[ -f "$out/fit.h5" ] || "$rcfd" build "${input[@]}" -window 39,339 -o "$out/fit.h5" -quiet
[ -f "$out/reference/cog.csv" ] || "$rcfd" reference "${input[@]}" -average_window 0.5,1.5 -o "$out/reference" >/dev/null
offset=0.2 # run time 0 is the snapshot at 0.2 s
physics=(-fractions_diameters 1.95e-3,2.82e-3 -fractions_mass_shares 0.470000917,0.529999083 -init file -fields 0
  -drift_model B -drift_agitation leaving -drift_agitation_exponent 2)

# coarsened SOURCE SPACE STRIDE PRECISION NAME: OUTPUT_DIR/dbs/NAME-{fit,replay}.h5 and NAME-init.h5.
coarsened() {
  local space=$1 stride=$2 precision=$3 name=$4 dbs=$out/dbs
  mkdir -p "$dbs"
  [ -f "$dbs/$name-replay.h5" ] && return 0
  local extra first
  extra=$(precision_options "$precision")
  first=1
  [ "$stride" -ge 2 ] && first=2
  for part in fit replay; do
    local init=()
    [ $part = fit ] && init=(-init_file "$out/init.h5" -init_out "$dbs/$name-init.h5")
    # The weights are quantised in the last coarsening: composed quantised frames are not quantised.
    local now=$extra
    [ "$stride" -eq 4 ] && now=""
    # shellcheck disable=SC2086
    "$rcfd" coarsen "$out/$part.h5" -factor "$space" -time_factor $first "${init[@]}" $now -o "$dbs/$name-$part.h5" -quiet
    if [ "$stride" -eq 4 ]; then # twice two frames composed
      # shellcheck disable=SC2086
      "$rcfd" coarsen "$dbs/$name-$part.h5" -factor 1,1,1 -time_factor 2 $extra -o "$dbs/$name-$part.tmp.h5" -quiet
      mv "$dbs/$name-$part.tmp.h5" "$dbs/$name-$part.h5"
    fi
  done
}

median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

csv=$out/pareto.csv
echo "space,stride,drift_every,precision,cells,frames,dt_rec_s,kd,fit_rms_over_peak,step_wall_per_sim_s,process_wall_s,peak_mb,delta_seg_percent,rms_over_peak" >"$csv"
for precision in $precisions; do
  for space in $spaces; do
    for stride in $strides; do
      name=s${space//,/x}-t$stride-$precision
      coarsened "$space" "$stride" "$precision" "$name"
      db=$out/dbs/$name
      for every in $drift_everys; do
        dir=$out/runs/$name-d$every
        mkdir -p "$dir"
        # Calibration on 0.2-1.7 s at this resolution: 5 scan points over 1e3-1e6, then to 0.1 decades.
        "$rcfd" calibrate "${physics[@]}" -drift_every "$every" -db "$db-fit.h5" -init_file "$db-init.h5" \
          -reference "$out/reference/cog.csv" -rcfd_time_offset $offset -calibrate_models B -calibrate_scan 5 \
          -calibrate_kd_range 1e3,1e6 -calibrate_tolerance 0.1 -output_dir "$dir/calibrate" >"$dir/calibrate.txt"
        read -r kd fit < <(awk -F, '$1 == "B" { print $3, $8 }' "$dir/calibrate/calibrate_best.csv")
        # The whole replay with that k_d, REPEATS times for its cost.
        steps="" walls="" peaks=""
        for ((r = 0; r < repeats; ++r)); do
          start=$(date +%s.%N)
          "$rcfd" run "${physics[@]}" -drift_every "$every" -db "$db-replay.h5" -init_file "$db-init.h5" -drift_kd "$kd" \
            -plot 0 -progress_interval 1e9 -output_dir "$dir/replay" >"$dir/replay.txt"
          end=$(date +%s.%N)
          walls+="$(echo "$end - $start" | bc -l) "
          steps+="$(sed -n 's/.*(\([0-9.e+-]*\) wall s per simulated s).*/\1/p' "$dir/replay.txt") "
          peaks+="$(sed -n 's/.*peak memory \([0-9.]*\) MB per rank.*/\1/p' "$dir/replay.txt") "
        done
        step=$(tr ' ' '\n' <<<"$steps" | grep . | median)
        wall=$(tr ' ' '\n' <<<"$walls" | grep . | median)
        peak=$(tr ' ' '\n' <<<"$peaks" | grep . | median)
        "$rcfd" compare -reference "$out/reference/cog.csv" -rcfd "$dir/replay/cog.csv" -labels run \
          -rcfd_time_offset $offset -score_window 0.5,1.5 -o "$dir/scores.csv" >/dev/null
        read -r seg rms < <(awk -F, 'NR > 2 && $1 == "run" && $2 == "delta_z" { print $11, $17 }' "$dir/scores-scores.csv")
        read -r cells frames dt < <("$rcfd" info "$db-replay.h5" 2>/dev/null | awk '
          /^  mesh:/ { for (i = 1; i < NF; ++i) if ($i == "=") c = $(i + 1) + 0 }
          /^  frames:/ { f = $2; d = $4 } END { print c, f, d }')
        row="${space//,/x},$stride,$every,$precision,$cells,$frames,$dt,$kd,$fit,$step,$wall,$peak,$seg,$rms"
        echo "$row" >>"$csv"
        echo "  $row"
      done
    done
  done
done

cp "$csv" "$results/pareto.csv"
py=/usr/bin/python3 # Debian's python3 has python3-matplotlib
[ -x "$py" ] || py=python3
"$py" "$root/bench/pareto.py" "$results/pareto.csv" -o "$results/pareto.png" --markdown "$results/pareto.md"
echo "Wrote $results/pareto.md, $results/pareto.csv, $results/pareto.png"
