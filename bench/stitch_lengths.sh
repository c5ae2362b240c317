#!/usr/bin/env bash
# Does the long-run segregation depend on how often a stitched path jumps?
# The default bed (rcfd synth) with the bi-narrow inventory and the recommended
# drift law of docs/validation.md, -path_type random, T_END s (150), for the four
# sequence-length settings of issue 28 (frames: 5-15, 15-60 (default), 60-150,
# 150-299), each carry kind of CARRIES and each seed of SEEDS.  Per run: the
# mean delta z over the second half, the largest bulk mismatch on the rows
# right after a jump (cog.csv) and the mean relative change of delta z per
# jump across the carry (jumps.csv).  Prints a table per carry (with every
# setting's deviation from the mean of the four) and writes it to
# bench/results/stitch_lengths.md and the runs' rows to
# bench/results/stitch_lengths.csv, and 1 s means of delta z over time to
# bench/results/stitch_lengths_series.csv, drawn by bench/stitch_lengths.py into docs/stitch-lengths.png.
# Runs already made (OUT/<carry>-<lengths>-s<seed>/done) are reused; RUN=0 makes none (the table of
# those there).  Carry "column-bed" is -carry_type column -carry_column_bed.
# usage: [CARRIES="remap column"] [SEEDS="1 2 3"] [JOBS=2] [RUN=0] bench/stitch_lengths.sh [BUILD_DIR] [T_END]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tend=${2:-150}
carries=${CARRIES:-remap column}
seeds=${SEEDS:-1 2 3}
jobs=${JOBS:-2}
work=${OUT:-/tmp/rcfd-stitch-lengths}
db=build/default-bed.h5
[ -s "$db" ] || "$build/rcfd" synth -o "$db" -quiet
mkdir -p bench/results "$work"
lengths="5:15 15:60 60:150 150:299"
one() { # one CARRY LENGTHS SEED
  local dir=$work/$1-${2/:/-}-s$3
  [ -e "$dir/done" ] || [ "${RUN:-1}" = 0 ] && return 0
  local carry=(-carry_type "$1")
  [ "$1" = column-bed ] && carry=(-carry_type column -carry_column_bed)
  "$build/rcfd" run -db "$db" -fractions_diameters 1.950e-3,2.820e-3 -fractions_mass_shares 0.473,0.527 \
    -drift_model B -drift_kd 1.73e4 -drift_agitation leaving -drift_agitation_exponent 2 \
    -path_type random -path_seed "$3" -path_min_length "${2%:*}" -path_max_length "${2#*:}" \
    -t_end "$tend" -fields 0 -plot 0 -quiet "${carry[@]}" -carry_view -output_dir "$dir" >"$dir.log" 2>&1 &&
    touch "$dir/done"
}
export -f one
export build db tend work
for s in $seeds; do for c in $carries; do for l in $lengths; do echo "$c $l $s"; done; done; done |
  xargs -P "$jobs" -L 1 bash -c 'one "$@"' _
csv=bench/results/stitch_lengths.csv
echo "carry,min_length,max_length,seed,mean_delta_z_mm,jumps,max_mismatch_after_jump,dz_change_per_jump" >"$csv"
for c in $carries; do for l in $lengths; do for s in $seeds; do
  dir=$work/$c-${l/:/-}-s$s
  [ -e "$dir/done" ] || continue
  awk -F, -v T="$tend" -v c="$c" -v l="${l/:/,}" -v s="$s" '
    NR == FNR { if (FNR > 2) { jump[$2 + 0] = 1; n++; b += $5; a += $(5 + (NF - 4) / 2) }; next }
    FNR > 1 && $1 >= T / 2 { k++; dz += $5 }
    FNR > 1 && (($1 + 0) in jump) && $NF > m { m = $NF }
    END { printf "%s,%s,%s,%.3f,%d,%.2e,%.4f\n", c, l, s, 1e3 * dz / k, n, m, (a - b) / b }' \
    "$dir/jumps.csv" "$dir/cog.csv" >>"$csv"
done; done; done
# Delta z over time, 1 s means over the seeds, for the figure (bench/stitch_lengths.py -> docs/stitch-lengths.png).
series=bench/results/stitch_lengths_series.csv
echo "carry,min_length,max_length,time_s,delta_z_mm,seeds" >"$series"
for c in $carries; do for l in $lengths; do
  dirs=()
  for s in $seeds; do [ -e "$work/$c-${l/:/-}-s$s/done" ] && dirs+=("$work/$c-${l/:/-}-s$s/cog.csv"); done
  [ ${#dirs[@]} -gt 0 ] || continue
  awk -F, -v c="$c" -v l="${l/:/,}" -v n=${#dirs[@]} 'FNR > 1 { b = int($1 - 1e-9); if (b < 0) b = 0; s[b] += $5; k[b]++
      if (b > last) last = b }
    END { for (b = 0; b <= last; ++b) printf "%s,%s,%g,%.3f,%d\n", c, l, b + 0.5, 1e3 * s[b] / k[b], n }' \
    "${dirs[@]}" >>"$series"
done; done
"${RCFD_PYTHON:-/usr/bin/python3}" bench/stitch_lengths.py "$series" docs/stitch-lengths.png || echo "(no figure: matplotlib missing?)"
{
  echo "# delta z against the stitched sequences' length, default bed, bi-narrow, B x (a/ā)^2, $tend s"
  echo "($(date -u +%Y-%m-%dT%H:%MZ); seeds $seeds; mean delta z over $((tend / 2))-$tend s; deviation from the mean of the four settings)"
  echo
  echo "| carry | 5-15 | 15-60 | 60-150 | 150-299 | mean | largest deviation | max bulk mismatch after a jump | delta z change per jump |"
  echo "|---|---|---|---|---|---|---|---|---|"
  awk -F, 'NR > 1 { k = $1 SUBSEP $2; sum[k] += $5; cnt[k]++; ch[$1] += $8; nch[$1]++; if ($7 > mm[$1]) mm[$1] = $7
      if (!($1 in seen)) { seen[$1] = 1; order[++nc] = $1 } }
    END { split("5 15 60 150", L, " ")
      for (o = 1; o <= nc; ++o) { c = order[o]; tot = 0; n = 0
        for (i = 1; i <= 4; ++i) { k = c SUBSEP L[i]; if (cnt[k]) { v[i] = sum[k] / cnt[k]; tot += v[i]; n++ } else v[i] = "" }
        mean = n ? tot / n : 0; dev = 0; line = "| " c
        for (i = 1; i <= 4; ++i) { if (v[i] == "") { line = line " | -"; continue }
          d = 100 * (v[i] - mean) / mean; if (d < 0 ? -d > dev : d > dev) dev = d < 0 ? -d : d
          line = line sprintf(" | %.1f (%+.0f %%, %d)", v[i], d, cnt[c SUBSEP L[i]]) }
        printf "%s | %.1f | %.0f %% | %.1e | %+.2f %% |\n", line, mean, dev, mm[c], 100 * ch[c] / nch[c] } }' "$csv"
  echo
  echo "(each cell: mean delta z [mm] over the seeds, its deviation from the carry's mean, seeds)"
} | tee bench/results/stitch_lengths.md
