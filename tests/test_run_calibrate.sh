#!/usr/bin/env bash
# rcfd calibrate recovers a known drift coefficient: a reference cog.csv made
# by a replay run at k_d = 2e5 on the small synthetic database, then
# calibrate (model B, 2 ranks) must return 2e5 within 2 % (its golden section
# stops at 0.01 decades, 2.3 %, around a minimum of exactly zero).
# usage: test_run_calibrate.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
common=(-db "$data/small.h5" -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436
  -fields 0)

run "reference run" "$rcfd" run "${common[@]}" -drift_kd 2e5 -quiet -plot 0 -monitor_digits 17 \
  -output_dir "$work/reference"
if run "calibrate" mpiexec -n 2 "$rcfd" calibrate "${common[@]}" -reference "$work/reference/cog.csv" \
  -score_window 0.1,0.3 -calibrate_kd_range 1e4,1e7 -calibrate_scan 7 -output_dir "$work/calibrate"; then
  kd=$(sed -n 's/^model B: best k_d = \([^ ]*\) .*/\1/p' "$work/out.txt")
  same "calibrated k_d" "$(awk -v k="$kd" 'BEGIN { print k / 2e5 }')" 1 0.02
  # The drift the runs used is the calibrated one, not the options' 5e3:
  # the table holds k_d far from 5e3 and their curves differ.
  grep -q "^ *1e+07 " "$work/out.txt" || fail "the scan did not reach k_d = 1e7: $(cat "$work/out.txt")"
  # The files: one scan row per printed evaluation, the best k_d as printed, the best run's curve.
  same "best k_d in calibrate_best.csv" "$(awk -F, '$1 == "B" { print $3 }' "$work/calibrate/calibrate_best.csv")" "$kd" 1e-3
  same "scan rows" "$(grep -c '^B,' "$work/calibrate/calibrate_scan.csv")" \
    "$(sed -n 's/^\([0-9]*\) replay runs.*/\1/p' "$work/out.txt")"
  cmp -s "$work/calibrate/best-B/cog.csv" "$work/calibrate/cog.csv" && ok || fail "best-B/cog.csv is not the last run's"
fi
# Batched (the default) and one by one (-calibrate_batch false): the same files, byte for byte.
if run "calibrate one by one" mpiexec -n 2 "$rcfd" calibrate "${common[@]}" -reference "$work/reference/cog.csv" \
  -score_window 0.1,0.3 -calibrate_kd_range 1e4,1e7 -calibrate_scan 7 -output_dir "$work/alone" -calibrate_batch false; then
  for f in calibrate_scan.csv calibrate_best.csv best-B/cog.csv; do
    cmp -s "$work/calibrate/$f" "$work/alone/$f" && ok || fail "$f differs between batched and one-by-one calibration"
  done
fi
# -calibrate_candidates: each named replay's cog.csv equals that of rcfd run with its options.
printf '# name, then its drift options\nA-4e4 -drift_model A -drift_kd 4e4 -drift_local_d32\nB-2e5 -drift_kd 2e5 # the reference\n' \
  >"$work/laws.txt"
if run "candidates" mpiexec -n 2 "$rcfd" calibrate "${common[@]}" -reference "$work/reference/cog.csv" \
  -score_window 0.1,0.3 -monitor_digits 17 -calibrate_candidates "$work/laws.txt" -output_dir "$work/laws"; then
  # On as many ranks (1 and 2 ranks agree to round-off, not bit for bit).
  run "A alone" mpiexec -n 2 "$rcfd" run "${common[@]}" -drift_model A -drift_kd 4e4 -drift_local_d32 -quiet -plot 0 \
    -monitor_digits 17 -output_dir "$work/A-alone"
  cmp -s "$work/laws/A-4e4/cog.csv" "$work/A-alone/cog.csv" && ok || fail "a candidate's cog.csv is not its run's"
  same "Eq. 7 of the reference's own law" "$(awk -F, '$1 == "B-2e5" { print $5 }' "$work/laws/calibrate_candidates.csv")" 0 1e-9
fi
echo "x -drift_kdd 3" >"$work/typo.txt"
if mpiexec -n 2 "$rcfd" calibrate "${common[@]}" -calibrate_candidates "$work/typo.txt" -output_dir "$work/typo" \
  >"$work/out.txt" 2>&1; then
  fail "a misspelt candidate option was accepted"
else
  grep -q "candidate option -drift_kdd" "$work/out.txt" && ok || fail "no sentence naming -drift_kdd: $(cat "$work/out.txt")"
fi
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
