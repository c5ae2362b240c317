#!/usr/bin/env bash
# Every size law fitted to the drift measured from the particles of the three shared CFD-DEM beds
# (issue 21), relative to the bulk, in seconds and without replays:
#   cases/dpm-bi-narrow/size_laws.sh [OUTPUT_DIR]     (default: rcfd-output/drift-laws, as drift_laws.sh)
# Databases from t = 0.2 s to the end (-mesh_cells 16,2,60 -window 39,-1; made once and shared with
# drift_laws.sh), then rcfd calibrate -calibrate_from measured -calibrate_models A,B,drag,log,power
# with each bed's own classes, and the figure drift-size-laws.png (the classes of all beds against
# d_i/d32 with each law's curve; docs/drift.md), and drift-size-means.png with drift_size_means.csv
# (the same drift against d_i over the inventory's d32 and d43 and over the local mixture's d32 and
# d43, from the field rcfd info -extra_csv writes, with one common curve per law, and the local bins
# scored like for like against the inventory d32; docs/drift.md).
# Environment: RCFD, SHARED (default
# ../shared/reference).  A few minutes for the databases the first time, seconds afterwards.
set -euo pipefail
here=$(dirname "${BASH_SOURCE[0]}")
root=$(cd "$here/../.." && pwd)
out=${1:-$root/rcfd-output/drift-laws}
rcfd=${RCFD:-$root/build/rcfd} shared=${SHARED:-$root/../shared/reference}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$out"

# bed: short name, reference folder, diameters, mass shares (of the particles at 0.2 s).
beds=("narrow|dpm-bi-narrow|1.95e-3,2.82e-3|0.470000917,0.529999083"
  "wide|dpm-bi-wide|1.6e-3,3e-3|0.50005661,0.49994339"
  "penta|dpm-penta-wide|1.4e-3,1.75e-3,2.3e-3,2.9e-3,3.6e-3|0.100015358,0.123053589,0.427060664,0.1999672,0.149903189")
fits=() labels=() dirs=()
for entry in "${beds[@]}"; do
  IFS='|' read -r name folder diameters shares <<<"$entry"
  ref=$shared/$folder
  [ -f "$out/$name-t02.h5" ] || "$rcfd" build -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" \
    -mesh_cells 16,2,60 -window 39,-1 -o "$out/$name-t02.h5" -init_out "$out/$name-init.h5" -quiet
  echo "== $folder"
  "$rcfd" calibrate -db "$out/$name-t02.h5" -fractions_diameters "$diameters" -fractions_mass_shares "$shares" \
    -calibrate_from measured -calibrate_models A,B,drag,log,power -t_end 0.01 -output_dir "$out/size-laws-$name" |
    grep -E "^model|measured:"
  # The measured drift per frame and region, for the local mixture's mean (drift-size-means.png).
  for extra in measured_drift_field measured_drift_field_layout; do
    "$rcfd" info "$out/$name-t02.h5" -extra_csv "$extra,$out/size-laws-$name/$extra.csv" >/dev/null
  done
  fits+=("$out/size-laws-$name/measured_law_fits.csv")
  dirs+=("$out/size-laws-$name")
  labels+=("$folder")
done
py=/usr/bin/python3 # Debian's python3 has python3-matplotlib
[ -x "$py" ] || py=python3
"$py" "$root/src/cli/figures/drift_size_laws.py" "${fits[@]}" --labels "$(IFS=,; echo "${labels[*]}")" \
  -o "$out/drift-size-laws.png" || echo "(no matplotlib: drift-size-laws.png not drawn)"
"$py" "$root/src/cli/figures/drift_size_means.py" "${dirs[@]}" --labels "$(IFS=,; echo "${labels[*]}")" \
  -o "$out/drift-size-means.png" --table "$out/drift_size_means.csv" \
  --title "Measured drift against d_i / mean diameter: one curve per law, one constant for the three beds" ||
  echo "(no matplotlib: drift-size-means.png not drawn)"
echo "Wrote ${fits[*]}, $out/drift_size_means.csv, $out/drift-size-laws.png and $out/drift-size-means.png"
