#!/usr/bin/env bash
# The penta-on-bi case, from any directory:
#   cases/penta-on-bi/run.sh [OUTPUT_DIR]      (default: rcfd-output/penta-on-bi)
# Environment: RCFD (default build/rcfd), REFERENCE (default ../shared/reference/dpm-bi-narrow),
# NP (MPI ranks, default 2).  Builds the dpm-bi-narrow database from the reference's particle dumps
# (unless OUTPUT_DIR/db.h5 exists), the reference's profiles and halves over 0.5-1.5 s, then runs the
# penta-disperse inventory (case.yaml) and the bi-disperse inventory of the database's own bed
# (1.95 / 2.82 mm) with the same options, and draws each run's profiles and halves against the other.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
ref=${REFERENCE:-$root/../shared/reference/dpm-bi-narrow}
out=${1:-$root/rcfd-output/penta-on-bi}
np=${NP:-2}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$out"
input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
if [ ! -s "$out/db.h5" ]; then
  echo "== the dpm-bi-narrow database (as cases/dpm-bi-narrow/run.sh)"
  "$rcfd" build "${input[@]}" -o "$out/db.h5" -quiet
fi
if [ ! -s "$out/reference/profiles.csv" ]; then
  echo "== the bi-disperse CFD-DEM reference's profiles and halves over 0.5-1.5 s"
  "$rcfd" reference "${input[@]}" -average_window 0.5,1.5 -o "$out/reference" >/dev/null
fi
case_file=$root/cases/penta-on-bi/case.yaml
runs=(mpiexec -n "$np" "$rcfd" run -options_file "$case_file" -db "$out/db.h5" -progress_interval 100)
echo "== bi-disperse run (the database's own inventory), against the CFD-DEM reference"
"${runs[@]}" -fractions_diameters 1.95e-3,2.82e-3 -fractions_mass_shares 0.470000917,0.529999083 \
  -output_dir "$out/bi" -plot_reference "$out/reference"
echo "== penta-disperse run, against the bi-disperse run"
"${runs[@]}" -output_dir "$out/penta" -plot_reference "$out/bi"
echo "== the database's bed dynamics (rcfd info)"
"$rcfd" info -db "$out/db.h5" | grep -i "bed dynamics" || true
echo "Wrote $out/{bi,penta}/{profiles,halves,bottom}.{csv,png}"
