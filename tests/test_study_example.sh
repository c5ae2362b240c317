#!/usr/bin/env bash
# docs/examples/study, a study as a program: configured against the INSTALLED package (installed
# once into PREFIX by the fixture installed_package), built, and run at 2 ranks on the small
# synthetic database against a reference made at k_d = 2e5.  Its calibration (rcfd::Calibration)
# fits the k_d that `rcfd calibrate` prints for the same options, to the printed digits; each
# member of its ensemble (rcfd::Ensemble) keeps its mass to 1e-12; its comparison
# (rcfd::Comparison) scores the ensemble's mean curve, as `rcfd compare` does.
# usage: test_study_example.sh RCFD BUILD_DIR SOURCE_DIR CMAKE CXX_COMPILER DATA_DIR PREFIX
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
build=$2 src=$3 cmake=$4 cxx=$5 data=$6 prefix=$7
work=$build/test-data/study
rm -rf "$work"
mkdir -p "$work"
source "$src/tests/script_helpers.sh"
rcfd=$prefix/bin/rcfd

build_example study "$src" "$prefix" "$cmake" "$cxx"

common=(-db "$data/small.h5" -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -fields 0)
fit=(-score_window 0.1,0.3 -calibrate_kd_range 1e4,1e7 -calibrate_scan 7)
run "reference run" "$rcfd" run "${common[@]}" -drift_kd 2e5 -quiet -plot 0 -monitor_digits 17 \
  -output_dir "$work/reference"
run "rcfd calibrate" mpiexec -n 2 "$rcfd" calibrate "${common[@]}" -reference "$work/reference/cog.csv" "${fit[@]}" \
  -output_dir "$work/calibrate" -calibrate_view
program_kd=$(sed -n 's/^model B: best k_d = \([^ ]*\) .*/\1/p' "$work/out.txt")
# -calibrate_view: the calibration's view, its k_d as printed.
grep -q "^  B: k_d = $program_kd 1/(m s), mean" "$work/out.txt" && ok || fail "-calibrate_view printed no view: $(cat "$work/out.txt")"

if run "study" mpiexec -n 2 "$work/study/study" "${common[@]}" -reference "$work/reference/cog.csv" "${fit[@]}" \
  -study_members 3 -output_dir "$work/out"; then
  cp "$work/out.txt" "$work/study.txt"
  study_kd=$(sed -n 's/^study: fitted k_d = \([^ ]*\) .*/\1/p' "$work/study.txt")
  [ -n "$program_kd" ] && [ "$study_kd" = "$program_kd" ] && ok ||
    fail "the study fitted k_d = '$study_kd', rcfd calibrate '$program_kd'"
  same "fitted k_d / 2e5" "$(awk -v k="$study_kd" 'BEGIN { print k / 2e5 }')" 1 0.02
  # The calibration's files are those of rcfd calibrate.
  for f in calibrate_scan.csv calibrate_best.csv; do
    cmp -s "$work/calibrate/$f" "$work/out/$f" && ok || fail "$f differs between the study and rcfd calibrate"
  done
  # Three members, each keeping its mass.
  changes=$(sed -n 's/^study: member [0-9] mass .* relative change \(.*\)$/\1/p' "$work/study.txt")
  [ "$(grep -c . <<<"$changes")" -eq 3 ] && ok || fail "expected 3 members: $(cat "$work/study.txt")"
  same "members' relative mass change" "$changes" "0 0 0" 1e-12
  [ -s "$work/out/ensemble.csv" ] && [ -s "$work/out/member_2/cog.csv" ] && ok || fail "no ensemble.csv or member_2/cog.csv"
  # The comparison scores delta_z over the window; rcfd compare gives the same Delta_seg.
  seg=$(sed -n 's/^study: ensemble delta_z Delta_seg \([^ ]*\) % .*/\1/p' "$work/study.txt")
  [ -n "$seg" ] && ok || fail "the study printed no comparison: $(cat "$work/study.txt")"
  if run "rcfd compare" "$rcfd" compare -reference "$work/reference/cog.csv" -rcfd "$work/out/ensemble.csv" \
    -labels ensemble -score_window 0.1,0.3; then
    compare_seg=$(awk '$1 == "ensemble" { print $3 }' "$work/out.txt")
    same "Delta_seg of the study and of rcfd compare" "$seg" "$compare_seg" 0.051
  fi
fi

# rcfd run -ensemble is the same rcfd::Ensemble: -ensemble_view prints its view.
if run "rcfd run -ensemble 2" "$rcfd" run "${common[@]}" -path_type random -ensemble 2 -plot 0 -quiet \
  -output_dir "$work/ensemble" -ensemble_view; then
  grep -q "^Ensemble: 2 members, path seeds 1 to 2, summary $work/ensemble/ensemble.csv" "$work/out.txt" && ok ||
    fail "-ensemble_view printed no view: $(cat "$work/out.txt")"
fi

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
