#!/usr/bin/env bash
# Tiny cut cells merged (-vessel_merge_below, docs/vessels.md) on the beds of cases/cylinder-bi-wide
# and cases/cone-bi-wide: for each threshold, the cells, the merged box cells, the smallest cell's
# share, rcfd synth's wall time and memory, alpha_s over every 10th frame in the settled bed (largest
# over all cells and over the cut cells; cut cells empty in every such frame; mean over cut and
# whole cells), the case's run (10 s on 2 ranks) and its answers (delta z at 10 s, the bottom
# layer's d32 over 9-10 s).
#
#   bench/vessel_merge.sh [THRESHOLDS]      default "0 0.1 0.25"; work in build/vessel-merge/
# Environment: RCFD (default build/rcfd), H5PRINT (default build/tests/h5_print), T_END (default 10).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
h5print=${H5PRINT:-$root/build/tests/h5_print}
t_end=${T_END:-10}
thresholds=${1:-0 0.1 0.25}
work=$root/build/vessel-merge
mkdir -p "$work"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
box=(-synth_cells 30,30,100 -synth_length 0.15,0.15,0.5 -synth_bed_height 0.15 -quiet)
cell=1.25e-7 # a box cell's volume [m^3]: 5 mm cubes
printf '| bed | S | cells | merged box cells | smallest share | synth wall / RSS | in the bed: max alpha_s (all / cut cells) | cut cells always empty | mean alpha_s (cut / whole cells) | run wall | dz at 10 s | bottom d32 9-10 s |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for bed in cylinder cone; do
  if [ $bed = cylinder ]; then
    vessel=(-vessel cylinder)
    case=$root/cases/cylinder-bi-wide/case.yaml
  else
    vessel=(-vessel body,bottom -vessel_body_cylinder 0.075,0.075,0.075,0.06,0.5
      -vessel_bottom_cone 0.075,0.075,0,0.025,0.06,0.075)
    case=$root/cases/cone-bi-wide/case.yaml
  fi
  for S in $thresholds; do
    db=$work/$bed-$S.h5
    /usr/bin/time -f '%e %M' -o "$work/synth.time" "$rcfd" synth -o "$db" "${box[@]}" "${vessel[@]}" -vessel_merge_below "$S"
    read -r wall rss < "$work/synth.time"
    "$h5print" "$db" /mesh/cell_volumes > "$work/volumes.txt"
    cells=$(wc -l < "$work/volumes.txt")
    merged=0
    if [ "$S" != 0 ]; then merged=$("$h5print" "$db" /mesh/merged_box_cell | wc -l); fi
    smallest=$(awk -v v=$cell 'NR == 1 || $1 < s { s = $1 } END { printf "%.3f", s / v }' "$work/volumes.txt")
    # alpha_s over every 10th frame, of the cells centred below the settled bed (0.15 m): the
    # largest over all of them and over the cut ones, the cut cells empty in every such frame, and
    # the mean over the cut cells against the whole ones.
    "$h5print" "$db" /mesh/cell_centres | awk 'NR % 3 == 0' | paste "$work/volumes.txt" - > "$work/cells.txt"
    frames=$("$h5print" "$db" /frames num_frames)
    : > "$work/alpha.txt"
    for ((k = 0; k < frames; k += 10)); do
      "$h5print" "$db" "$(printf '/frames/%06d/alpha_s' $k)" | paste "$work/cells.txt" - >> "$work/alpha.txt"
    done
    extremes=$(awk -v v=$cell -v n="$cells" '{ c = (NR - 1) % n; if ($2 >= 0.15) next; if ($3 > all) all = $3
        if ($1 < v * (1 - 1e-12)) { cut[c] = 1; sc += $3; nc++; if ($3 > cm) cm = $3; if ($3 > 0) held[c] = 1 }
        else { sw += $3; nw++ } }
      END { for (c in cut) { ncut++; if (!(c in held)) empty++ }
        printf "%.3f / %.3f|%d of %d|%.3f / %.3f", all, cm, empty, ncut, sc / nc, sw / nw }' "$work/alpha.txt")
    out=$work/run-$bed-$S
    start=$(date +%s.%N)
    mpiexec -n 2 "$rcfd" run -options_file "$case" -db "$db" -t_end "$t_end" -fields 0 -plot 0 -quiet \
      -output_dir "$out"
    runwall=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    dz=$(awk -F, '/^[0-9]/ && NF > 1 { last = $0 } NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "delta_z_m") col = i }
      END { split(last, f, ","); printf "%.1f", 1e3 * f[col] }' "$out/cog.csv")
    d32=$(awk -F, -v t0="$(awk -v t="$t_end" 'BEGIN { print t - 1 }')" \
      'NR == 1 { for (i = 1; i <= NF; ++i) if ($i == "d32_bottom_m") col = i; next }
      /^[0-9]/ && $1 >= t0 - 1e-9 { s += $col; n++ } END { printf "%.3f", 1e3 * s / n }' "$out/bottom.csv")
    IFS='|' read -r most empty mean <<< "$extremes"
    printf '| %s | %s | %d | %d | %s | %.1f s / %d MB | %s | %s | %s | %s s | %s mm | %s mm |\n' "$bed" "$S" "$cells" \
      "$merged" "$smallest" "$wall" $((rss / 1024)) "$most" "$empty" "$mean" "$runwall" "$dz" "$d32"
  done
done
