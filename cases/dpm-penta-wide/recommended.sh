#!/usr/bin/env bash
# The recommended drift (cases/recommended-drift.yaml) on the three shared CFD-DEM beds and on the
# paper's penta-on-bi (issue 21), scored per class:
#   cases/dpm-penta-wide/recommended.sh [OUTPUT_DIR] [EXTRA_DRIFT_OPTIONS...]
# Replays from t = 0.2 s of dpm-bi-narrow and dpm-penta-wide (the fitting beds), dpm-bi-wide (the
# check) and the five penta classes on dpm-bi-narrow's database (mixed start).  Each database records
# its bed's superficial gas velocity (rcfd build -superficial_velocity), which the drift's excess-gas
# scale reads.  Prints Delta_seg (Eq. 7 over 0.5-1.5 s), RMS/peak of Delta z and the poly-disperse
# number E/peak per replay (docs/validation.md, "Five classes: one law for every bed").  About a
# minute on one core once the databases exist.  Environment: RCFD, SHARED (default ../shared/reference).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
shared=${SHARED:-$root/../shared/reference}
out=${1:-$root/rcfd-output/recommended-drift}
shift $(($# > 0 ? 1 : 0))
extra=("$@")
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
declare -A usup=([bi-narrow]=1.3 [bi-wide]=1.35 [penta-wide]=1.4)
declare -A classes=(
  [bi-narrow]="-fractions_diameters 1.95e-3,2.82e-3 -fractions_mass_shares 0.470000917,0.529999083"
  [bi-wide]="-fractions_diameters 1.6e-3,3e-3 -fractions_mass_shares 0.50005661,0.49994339"
  [penta-wide]="-fractions_diameters 1.4e-3,1.75e-3,2.3e-3,2.9e-3,3.6e-3 -fractions_mass_shares 0.100015358,0.123053589,0.427060664,0.1999672,0.149903189")
for bed in bi-narrow bi-wide penta-wide; do
  ref=$shared/dpm-$bed
  input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
  [ -f "$out/$bed.h5" ] || "$rcfd" build "${input[@]}" -window 39,-1 -superficial_velocity "${usup[$bed]}" -particle_volume overlap \
    -o "$out/$bed.h5" -init_out "$out/$bed-init.h5" -quiet
  [ -f "$out/$bed-ref/cog.csv" ] || "$rcfd" reference "${input[@]}" -average_window 0.5,1.5 -o "$out/$bed-ref" >/dev/null
done
printf '%-24s %9s %9s %9s\n' replay "Delta_seg" "RMS/peak" "E/peak"
# replay NAME DATABASE INVENTORY START t_end
replay() {
  local name=$1 db=$2 inventory=$3 start=$4 tend=$5
  read -r -a inv <<<"${classes[$inventory]}"
  "$rcfd" run -options_file "$root/cases/dpm-bi-narrow/case.yaml" -options_file "$root/cases/recommended-drift.yaml" \
    "${extra[@]}" -db "$out/$db.h5" $start "${inv[@]}" -t_end "$tend" -output_dir "$out/$name" -quiet -plot false >/dev/null
  "$rcfd" compare -reference "$out/$inventory-ref/cog.csv" -rcfd "$out/$name/cog.csv" -labels "$name" \
    -rcfd_time_offset 0.2 -score_window 0.5,1.5 -o "$out/$name-compare.csv" >/dev/null
  awk -F, -v run="$name" '/^#/ || $1 == "run" { next }
    $2 == "delta_z" { seg = $11; rms = $17 } $2 == "polydisperse" { ep = $17 }
    END { printf "%-24s %8.1f%% %9.3f %9.3f\n", run, seg, rms, ep }' "$out/$name-compare-scores.csv"
}
replay dpm-bi-narrow bi-narrow bi-narrow "-init_file $out/bi-narrow-init.h5" 3.29
replay dpm-penta-wide penta-wide penta-wide "-init_file $out/penta-wide-init.h5" 1.39
replay dpm-bi-wide bi-wide bi-wide "-init_file $out/bi-wide-init.h5" 1.39
replay penta-on-bi bi-narrow penta-wide "-init mixed" 1.39
