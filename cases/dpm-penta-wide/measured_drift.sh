#!/usr/bin/env bash
# The measured-drift replay of the three shared CFD-DEM beds (issue 21, docs/validation.md,
# "Measured-drift replay"): each bed's database from the snapshot at 0.2 s with its measured drift
# field at several region sizes, replayed from that snapshot's composition with -drift_model measured,
# scored against the bed's reference (Delta_seg over 0.5-1.5 s, RMS of Delta z over the peak, the
# poly-disperse number E and E over the largest class's peak):
#   cases/dpm-penta-wide/measured_drift.sh [-o OUTPUT_DIR] [REGION ...]
# REGION: cells nx,ny,nz per region (default 1,1,1 2,2,2 4,2,4 8,2,8 16,2,60).  Prints one line per
# bed and region.  About 10 s per database and 5-20 s per replay on one core.  Environment: RCFD,
# SHARED (default ../shared/reference).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
shared=${SHARED:-$root/../shared/reference}
out=$root/rcfd-output/measured-drift
if [ "${1:-}" = -o ]; then
  out=$2
  shift 2
fi
regions=("$@")
[ ${#regions[@]} -gt 0 ] || regions=(1,1,1 2,2,2 4,2,4 8,2,8 16,2,60)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
printf '%-14s %-9s %9s %9s %9s %9s\n' bed region "Delta_seg" "RMS/peak" "E [mm]" "E/peak"
for bed in penta-wide bi-narrow bi-wide; do
  ref=$shared/dpm-$bed
  [ -f "$out/$bed-reference/cog.csv" ] || "$rcfd" reference -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" \
    -mesh_cells 16,2,60 -average_window 0.5,1.5 -o "$out/$bed-reference" >/dev/null
  # The reference of dpm-bi-narrow runs to 3.5 s, the others to 1.6 s: t_end from the first frame at 0.2 s.
  t_end=$([ $bed = bi-narrow ] && echo 3.28 || echo 1.39)
  for region in "${regions[@]}"; do
    tag=$bed-${region//,/x}
    [ -f "$out/$tag.h5" ] || "$rcfd" build -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60 \
      -window 39,-1 -measured_drift_region "$region" -o "$out/$tag.h5" -init_out "$out/$bed-init.h5" >"$out/$tag-build.txt"
    # The classes and mass shares -init_out found, as the build printed them.
    read -r -a classes <<<"$(grep -o -- '-fractions_diameters.*' "$out/$tag-build.txt")"
    "$rcfd" run -options_file "$root/cases/dpm-bi-narrow/case.yaml" "${classes[@]}" -db "$out/$tag.h5" -init file \
      -init_file "$out/$bed-init.h5" -drift_model measured -t_end "$t_end" -quiet -plot false -output_dir "$out/$tag" >/dev/null
    "$rcfd" compare -reference "$out/$bed-reference/cog.csv" -rcfd "$out/$tag/cog.csv" -labels measured \
      -rcfd_time_offset 0.2 -score_window 0.5,1.5 -png "$out/$tag-compare.png" >"$out/$tag-compare.txt"
    awk -F, -v bed="$bed" -v region="$region" '/^#/ || $1 == "run" { next }
      $2 == "delta_z" { seg = $11; rms = $17 } $2 == "polydisperse" { e = $15; ep = $17 }
      END { printf "%-14s %-9s %8.1f%% %9.3f %9.3f %9.3f\n", bed, region, seg, rms, 1e3 * e, ep }' \
      "$out/$tag-compare-scores.csv"
  done
done
