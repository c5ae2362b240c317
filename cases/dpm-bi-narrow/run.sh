#!/usr/bin/env bash
# The dpm-bi-narrow validation, from any directory:
#   cases/dpm-bi-narrow/run.sh [OUTPUT_DIR]      (default: rcfd-output/dpm-bi-narrow)
# Environment: RCFD (default build/rcfd), REFERENCE (default ../shared/reference/dpm-bi-narrow),
# NP (MPI ranks of the runs, default 1), CALIBRATE=1 also fits k_d for models A and B (about a minute).
# Needs only bash and the rcfd program.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
ref=${REFERENCE:-$root/../shared/reference/dpm-bi-narrow}
out=${1:-$root/rcfd-output/dpm-bi-narrow}
np=${NP:-1}
case_file=$root/cases/dpm-bi-narrow/case.yaml
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
launch=("$rcfd")
[ "$np" -gt 1 ] && launch=(mpiexec -n "$np" "$rcfd")

# The dumps: x in [-0.04, 0.04], y in [-0.006, 0.006], z in [0, 0.30] m; the mesh is the CFD mesh,
# 16 x 2 x 60 cells of 5 x 6 x 5 mm over the dump's box.
input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
# The physical time of the first snapshot: frame 0 of the databases, time 0 of the runs.
t0=$(awk '!/^#/ && NF { print $2; exit }' "$ref/dump/times.txt")

echo "== databases (stride 1: dt_rec 5 ms; stride 2: 10 ms) and the initial composition"
"$rcfd" build "${input[@]}" -o "$out/db-stride1.h5" -init_out "$out/init.h5"
"$rcfd" build "${input[@]}" -frame_stride 2 -o "$out/db-stride2.h5" -quiet
echo "== reference: centres of gravity, profiles and halves over 0.5-1.5 s"
"$rcfd" reference "${input[@]}" -average_window 0.5,1.5 -o "$out/reference"

echo "== replay runs"
run() { # run NAME DATABASE [options]
  local name=$1 db=$2
  shift 2
  # Profiles and halves over the reference's window 0.5-1.5 s (run time starts at the first dump, 5 ms).
  "${launch[@]}" run -options_file "$case_file" -db "$db" -init_file "$out/init.h5" \
    -output_dir "$out/$name" -quiet -plot false -profiles -profiles_window 0.495,1.495 \
    -halves -halves_window 0.495,1.495 "$@"
  echo "  $name"
}
run shift-only "$out/db-stride1.h5" -drift_model none
run B-kd5e3 "$out/db-stride1.h5"
run B-kd5e3-stride2 "$out/db-stride2.h5"
run A-kd5e2 "$out/db-stride1.h5" -drift_model A -drift_kd 5e2
# k_d of model B fitted to this reference with rcfd calibrate (see docs/validation.md): 9.4e3
# minimises the RMS of the whole curve, 2.2e4 zeroes the Eq. 7 error over 0.5-1.5 s.
run B-kd9.4e3 "$out/db-stride1.h5" -drift_kd 9.4e3
run B-kd2.2e4 "$out/db-stride1.h5" -drift_kd 2.2e4
run B-kd2.2e4-stride2 "$out/db-stride2.h5" -drift_kd 2.2e4

echo "== comparison (Eq. 7 over 0.5-1.5 s, the segregating phase, and 1.5-2.5 s, the remixing;"
echo "   RMS of the whole curve / reference peak)"
windows=0.5,1.5,1.5,2.5
compare() { # compare PNG NAME...
  local png=$1
  shift
  local files labels
  files=$(printf "$out/%s/cog.csv," "$@")
  labels=$(printf "%s," "$@")
  "$rcfd" compare -reference "$out/reference/cog.csv" -rcfd "${files%,}" -labels "${labels%,}" \
    -rcfd_time_offset "$t0" -score_window $windows -o "${png%.png}.csv" -png "$png" \
    -title "dpm-bi-narrow: Delta z(t) of the CFD-DEM reference and of rcfd replays"
}
compare "$out/delta_z-all.png" shift-only B-kd5e3 B-kd5e3-stride2 A-kd5e2 B-kd9.4e3 B-kd2.2e4 \
  B-kd2.2e4-stride2
compare "$out/delta_z.png" shift-only B-kd5e3 B-kd9.4e3 B-kd2.2e4 >/dev/null
echo "Wrote $out/delta_z.png, $out/delta_z-all-scores.csv"

# Profiles and halves over the reference's window, for the runs that wrote them (rcfd run writes
# profiles.csv and halves.csv when its case asks for them; the reference's window 0.5-1.5 s is
# 0.495-1.495 s of run time).
answers() { # answers FILE NAME...: compare the runs' FILE (profiles.csv or halves.csv) with the reference's
  local file=$1 files="" labels="" name
  shift
  for name in "$@"; do
    [ -f "$out/$name/$file" ] || continue
    files+="$out/$name/$file,"
    labels+="$name,"
  done
  if [ -z "$files" ]; then
    echo "  (no run wrote $file: not compared)"
    return
  fi
  "$rcfd" compare -reference "$out/reference/$file" -rcfd "${files%,}" -labels "${labels%,}" \
    -scores "$out/${file%.csv}-scores.csv" -png "$out/${file%.csv}.png" \
    -title "dpm-bi-narrow: ${file%.csv} over 0.5-1.5 s, CFD-DEM reference and rcfd replays"
}
echo "== profiles and halves against the reference (0.5-1.5 s)"
answers profiles.csv shift-only B-kd5e3 B-kd9.4e3 B-kd2.2e4
answers halves.csv shift-only B-kd5e3 B-kd9.4e3 B-kd2.2e4

echo "== stitching: a 1.5 s database window (0.205-1.705 s), 5 stitched paths run to 3.485 s (paper Fig. 3)"
"$rcfd" build "${input[@]}" -window 40,340 -o "$out/db-window.h5" -init_out "$out/init-window.h5" -quiet
tw=$(awk '!/^#/ && NF && $1 == 40 { print $2 }' "$ref/dump/times.txt")
for kd in 5e3 2.2e4; do
  "${launch[@]}" run -options_file "$case_file" -db "$out/db-window.h5" -init_file "$out/init-window.h5" \
    -drift_kd $kd -path_type random -ensemble 5 -t_end 3.28 -output_dir "$out/stitch-kd$kd" -quiet \
    -plot false >/dev/null
  files=$(printf "$out/stitch-kd$kd/member_%d/cog.csv," 0 1 2 3 4)
  "$rcfd" compare -reference "$out/reference/cog.csv" -rcfd "${files}$out/stitch-kd$kd/ensemble.csv" \
    -labels "seed 1,seed 2,seed 3,seed 4,seed 5,mean of 5" -rcfd_time_offset "$tw" -score_window $windows \
    -o "$out/stitch-kd$kd.csv" -png "$out/stitch-kd$kd.png" \
    -title "dpm-bi-narrow: stitched from 0.205-1.705 s, model B, k_d = $kd"
done

echo "== database distance: Delta DB = |Delta z_CoG,db - Delta z_CoG,ref| / Delta z_CoG,ref"
for db in db-stride1 db-window; do
  "$rcfd" compare -db_distance "$out/$db.h5,$out/reference/cog.csv" -scores "$out/db_distance-$db.csv"
done

if [ "${CALIBRATE:-0}" = 1 ]; then
  echo "== calibration of k_d (models A and B)"
  "$rcfd" calibrate -options_file "$case_file" -db "$out/db-stride1.h5" -init_file "$out/init.h5" \
    -reference "$out/reference/cog.csv" -rcfd_time_offset "$t0" -calibrate_models A,B \
    -output_dir "$out/calibrate"
fi
