#!/usr/bin/env bash
# rcfd calibrate -calibrate_from measured recovers the k_d that made a drift: hand-made dumps of
# 8 particles of 1 mm and 1 of 2 mm (mass shares 1/2, 1/2; d32 4/3 mm) in one 2 cm cell, moving
# with a common bulk displacement plus u_i dt, u_i = -k_d (x_i - sum_j s_j x_j) with model A's
# x_i = d_i^2 - d32^2 and k_d = 2000 1/(m s): +-3 mm/s, times 1.1 in the first frame and 0.9 in the
# second (so the standard error is not zero and the mean is exact).  Model B's k_d follows from the
# same velocities: 3e-3 / ((d_l - d32)^2 - sum s_j x_j) by hand.  Also: calibrate's files.
# usage: test_calibrate_measured.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
source "$4/tests/script_helpers.sh"
mkdir -p "$work/dump"
# snapshot FILE STEP BULK FACTOR: small particles at z = 5 mm + BULK + FACTOR * 0.3 mm, the large one -.
snapshot() {
  awk -v step="$2" -v bulk="$3" -v f="$4" 'BEGIN {
    printf "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n9\nITEM: BOX BOUNDS ff ff ff\n0 0.02\n0 0.02\n0 0.02\n", step
    print "ITEM: ATOMS id type x y z radius"
    for (p = 1; p <= 8; ++p) printf "%d 1 %.17g 0.01 %.17g 0.0005\n", p, 0.002 * p, 0.005 + bulk + f * 3e-4
    printf "9 2 0.01 0.005 %.17g 0.001\n", 0.012 + bulk - f * 3e-4
  }' >"$1"
}
snapshot "$work/dump/dump.0.txt" 0 0 0
snapshot "$work/dump/dump.1.txt" 1 0.001 1.1
snapshot "$work/dump/dump.2.txt" 2 0.0005 2.0
printf '# index time\n0 0.1\n1 0.2\n2 0.3\n' >"$work/dump/times.txt"
run "build" "$rcfd" build -dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 1,1,1 \
  -o "$work/db.h5" -quiet
if run "calibrate" "$rcfd" calibrate -db "$work/db.h5" -fractions_diameters 1e-3,2e-3 \
  -fractions_mass_shares 0.5,0.5 -calibrate_from measured -calibrate_models A,B,drag,log,power -t_end 0.1 \
  -output_dir "$work/calibrate"; then
  best=$work/calibrate/calibrate_best.csv
  [ -f "$best" ] && ok || fail "calibrate_best.csv not written"
  [ -f "$work/calibrate/calibrate_scan.csv" ] && ok || fail "calibrate_scan.csv not written"
  same "model A k_d" "$(awk -F, '$1 == "A" { print $3 }' "$best")" 2000 1e-9
  # Model B: x = (d - d32)|d - d32| = -1/9, 4/9 mm^2; mean 1/6 mm^2; x_l - mean = 5/18 mm^2.
  same "model B k_d" "$(awk -F, '$1 == "B" { print $3 }' "$best")" \
    "$(awk 'BEGIN { printf "%.17g", 3e-3 / (5.0 / 18 * 1e-6) }')" 1e-9
  # drag: g = d32/d - 1 = 1/3, -1/3 (mean 0), so k = 3e-3 / (1/3) = 9e-3 m/s; log: g = ln(4/3),
  # ln(2/3), g_l - mean = ln(1/2)/2, so k = 6e-3 / ln 2; power: two classes fix no exponent (m stays 1).
  # (k in mm/s, so that same's tolerance is relative)
  same "drag k [mm/s]" "$(awk -F, '$1 == "drag" { printf "%.17g", 1e3 * $3 }' "$best")" 9 1e-9
  same "log k [mm/s]" "$(awk -F, '$1 == "log" { printf "%.17g", 1e3 * $3 }' "$best")" "$(awk 'BEGIN { printf "%.17g", 6 / log(2) }')" 1e-8
  same "power k [mm/s]" "$(awk -F, '$1 == "power" { printf "%.17g", 1e3 * $3 }' "$best")" 9 1e-9
  units=$(awk -F, 'NR > 2 { printf "%s;", $11 }' "$best")
  [ "$units" = "1/(m s);1/(m s);m/s;m/s;m/s;" ] && ok || fail "units of k in calibrate_best.csv: '$units'"
  fits=$work/calibrate/measured_law_fits.csv
  same "rows of measured_law_fits.csv (5 laws x 2 classes)" "$(grep -vc '^#\|^model' "$fits")" 10
  same "largest residual of the exact fits [m/s]" \
    "$(awk -F, 'NR > 2 { r = $13 < 0 ? -$13 : $13; if (r > m) m = r } END { print m < 1e-15 ? 0 : m }' "$fits")" 0
  shape=$(awk -F, '$1 == "power" { printf "[%s]", $4 }' "$fits")
  [ "$shape" = "[][]" ] && ok || fail "power's exponent on two classes: '$shape', expected none (not fitted)"
fi
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
