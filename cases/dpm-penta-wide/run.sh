#!/usr/bin/env bash
# The five-class CFD-DEM bed (../shared/reference/dpm-penta-wide) replayed with the drift options given,
# scored per class (issue 21):
#   cases/dpm-penta-wide/run.sh [-o OUTPUT_DIR] [DRIFT_OPTIONS...]
# (default options: the recommended law, -drift_model B -drift_kd 1.732e4 -drift_agitation leaving
# -drift_agitation_exponent 2; default OUTPUT_DIR rcfd-output/dpm-penta-wide).  Two replays from t = 0.2 s:
#   penta        on its own database (-window 39,-1), from that snapshot's composition (-init_out);
#   penta-on-bi  the same five classes and mass shares on dpm-bi-narrow's database from 0.2 s, mixed start.
# Both are scored against the penta bed's reference: Delta_seg (Eq. 7 over 0.5-1.5 s), the RMS of
# Delta z(t) over the reference's peak, and the poly-disperse number E = sqrt(sum w_i RMS_i^2) of the
# classes' z_CoG,i - z_CoG,bed, in mm and over the largest class's peak (docs/validation.md, "Reading
# rcfd compare").  Prints one line per replay; the figures and scores are under OUTPUT_DIR/runs/TAG,
# TAG made from the options.  Databases and reference are built once and reused (about 30 s; a pair
# of replays about 10 s on one core).  Environment: RCFD, SHARED (default ../shared/reference).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
shared=${SHARED:-$root/../shared/reference}
out=$root/rcfd-output/dpm-penta-wide
if [ "${1:-}" = -o ]; then
  out=$2
  shift 2
fi
drift=("$@")
[ ${#drift[@]} -gt 0 ] || drift=(-drift_model B -drift_kd 1.732e4 -drift_agitation leaving -drift_agitation_exponent 2)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# Databases from the snapshot at 0.2 s (index 39: the settling of the first 0.2 s is in none), the
# penta bed's composition there and its reference.
for bed in penta-wide bi-narrow; do
  ref=$shared/dpm-$bed
  [ -f "$out/$bed-t02.h5" ] || "$rcfd" build -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" \
    -mesh_cells 16,2,60 -window 39,-1 -o "$out/$bed-t02.h5" -init_out "$out/$bed-init.h5" -quiet
done
ref=$shared/dpm-penta-wide
[ -f "$out/reference/cog.csv" ] || "$rcfd" reference -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" \
  -mesh_cells 16,2,60 -average_window 0.5,1.5 -o "$out/reference" >/dev/null

# The five classes with the mass shares of the particles (2405, 1515, 2316, 541, 212 of 1.4 ... 3.6 mm,
# rho_p 1440 kg/m^3 as dpm-bi-narrow); the reference ends at 1.6 s, 1.39 s after the first frame.
penta=(-options_file "$root/cases/dpm-bi-narrow/case.yaml" -fractions_diameters 1.4e-3,1.75e-3,2.3e-3,2.9e-3,3.6e-3
  -fractions_mass_shares 0.10001536,0.12305359,0.42706066,0.19996720,0.14990319 -t_end 1.39 -quiet -plot false)
# TAG: -drift_model B -drift_kd 5e3 -> drift_model=B_drift_kd=5e3
tag=$(printf ' %s' "${drift[@]}" | sed 's/ -\([A-Za-z]\)/_\1/g; s/ /=/g; s/^_//' | tr -c 'A-Za-z0-9.+=_-' '_')
dir=$out/runs/${tag:-defaults}
"$rcfd" run "${penta[@]}" -db "$out/penta-wide-t02.h5" -init_file "$out/penta-wide-init.h5" "${drift[@]}" \
  -output_dir "$dir/penta" >/dev/null
"$rcfd" run "${penta[@]}" -db "$out/bi-narrow-t02.h5" -init mixed "${drift[@]}" -output_dir "$dir/penta-on-bi" >/dev/null

echo "drift options: ${drift[*]}"
printf '%-12s %9s %9s %9s %9s\n' replay "Delta_seg" "RMS/peak" "E [mm]" "E/peak"
for run in penta penta-on-bi; do
  "$rcfd" compare -reference "$out/reference/cog.csv" -rcfd "$dir/$run/cog.csv" -labels "$run" \
    -rcfd_time_offset 0.2 -score_window 0.5,1.5 -png "$dir/$run-compare.png" \
    -title "dpm-penta-wide: $run, ${drift[*]}" >"$dir/$run-compare.txt"
  awk -F, -v run="$run" '/^#/ || $1 == "run" { next }
    $2 == "delta_z" { seg = $11; rms = $17 } $2 == "polydisperse" { e = $15; ep = $17 }
    END { printf "%-12s %8.1f%% %9.3f %9.3f %9.3f\n", run, seg, rms, 1e3 * e, ep }' "$dir/$run-compare-scores.csv"
done
echo "(per class: $dir/*-compare.txt and *-compare-scores.csv; figures $dir/*-compare.png)"
