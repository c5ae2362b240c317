#!/usr/bin/env bash
# Stitched against replayed, on the three shared CFD-DEM beds (issue 28, docs/paths.md "Databases
# that record a transient"):
#   cases/dpm-penta-wide/stitched.sh [OUTPUT_DIR] [CLOCK_WINDOWS...]
# Uses the databases of recommended.sh in OUTPUT_DIR (it runs that first if they are missing).
# For every bed: the replay of its own database from 0.2 s, and random paths (-ensemble SEEDS,
# default 40) over the database's own span with each clock window given (frames; "off" = the
# path draws from the whole database; default: off 60 30 15), all with cases/recommended-drift.yaml.
# Prints Delta_seg (Eq. 7 over 0.5-1.5 s) and RMS/peak of the ensemble's mean Delta z(t), and the
# mean Delta z change per jump and how far a jump goes (frames, |to - from - 1|) from the members'
# jumps.csv.  About 15 min on one core.
# Environment: RCFD, SHARED, SEEDS, EXTRA (more run options, e.g. "-path_least_used").
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
out=${1:-$root/rcfd-output/recommended-drift}
shift $(($# > 0 ? 1 : 0))
windows=("$@")
[ ${#windows[@]} -gt 0 ] || windows=(off 60 30 15)
seeds=${SEEDS:-40}
read -r -a extra <<<"${EXTRA:-}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
[ -f "$out/penta-wide.h5" ] && [ -f "$out/bi-wide.h5" ] && [ -f "$out/bi-narrow.h5" ] ||
  RCFD=$rcfd bash "$root/cases/dpm-penta-wide/recommended.sh" "$out" >/dev/null
declare -A classes=(
  [bi-narrow]="-fractions_diameters 1.95e-3,2.82e-3 -fractions_mass_shares 0.470000917,0.529999083"
  [bi-wide]="-fractions_diameters 1.6e-3,3e-3 -fractions_mass_shares 0.50005661,0.49994339"
  [penta-wide]="-fractions_diameters 1.4e-3,1.75e-3,2.3e-3,2.9e-3,3.6e-3 -fractions_mass_shares 0.100015358,0.123053589,0.427060664,0.1999672,0.149903189")
declare -A tend=([bi-narrow]=3.29 [bi-wide]=1.39 [penta-wide]=1.39)

score() { # score BED CSV NAME: Delta_seg and RMS/peak of the delta_z curve in CSV
  "$rcfd" compare -reference "$out/$1-ref/cog.csv" -rcfd "$2" -labels "$3" -rcfd_time_offset 0.2 \
    -score_window 0.5,1.5 -o "$out/stitched/$3-compare.csv" >/dev/null
  awk -F, '$2 == "delta_z" { printf "%8.1f%% %9.3f", $11, $17 }' "$out/stitched/$3-compare-scores.csv"
}
mkdir -p "$out/stitched"
printf '%-12s %-10s %9s %9s %12s %15s %12s\n' bed path "Delta_seg" "RMS/peak" "jumps/path" "dz per jump" "frames away"
for bed in penta-wide bi-wide bi-narrow; do
  read -r -a inv <<<"${classes[$bed]}"
  common=(-options_file "$root/cases/dpm-bi-narrow/case.yaml" -options_file "$root/cases/recommended-drift.yaml"
    -db "$out/$bed.h5" -init_file "$out/$bed-init.h5" "${inv[@]}" -t_end "${tend[$bed]}" -quiet -plot false)
  "$rcfd" run "${common[@]}" -output_dir "$out/stitched/$bed-replay" >/dev/null
  printf '%-12s %-10s %s\n' "$bed" replay "$(score "$bed" "$out/stitched/$bed-replay/cog.csv" "$bed-replay")"
  for w in "${windows[@]}"; do
    name=$bed-clock-$w
    clock=()
    [ "$w" = off ] || clock=(-path_clock_window "$w")
    "$rcfd" run "${common[@]}" -path_type random "${clock[@]}" "${extra[@]}" -ensemble "$seeds" \
      -output_dir "$out/stitched/$name" >/dev/null
    # jumps.csv: one row per jump; delta_z before and after the carry (columns by name).
    jumps=$(awk -F, '/^#/ { next } $1 == "step" { for (c = 1; c <= NF; ++c) col[$c] = c; next }
      { n++; d = $col["to_frame"] - $col["from_frame"] - 1; a += d < 0 ? -d : d
        if ($col["delta_z_before_m"] != 0) s += $col["delta_z_after_m"] / $col["delta_z_before_m"] - 1 }
      END { printf "%d %.2f %.0f", n, n ? 100 * s / n : 0, n ? a / n : 0 }' "$out/stitched/$name"/member_*/jumps.csv)
    read -r njumps perjump reach <<<"$jumps"
    printf '%-12s %-10s %s %12.1f %14s%% %12s\n' "" "clock $w" "$(score "$bed" "$out/stitched/$name/ensemble.csv" "$name")" \
      "$(awk -v n="$njumps" -v s="$seeds" 'BEGIN { print n / s }')" "$perjump" "$reach"
  done
done
