#!/usr/bin/env bash
# rcfd compare on hand-made files: Eq. 7 over two windows, the RMS over the
# peak, an ensemble.csv scored by its mean, every class against the bed and
# the poly-disperse number, the bottom layer's d32, profiles,
# halves and the database distance (a database against rcfd info's bed
# dynamics) give hand-computed numbers in the scores CSV; window labels read
# back exactly; bad input gets one sentence naming the file.  The figures of
# profiles and halves are drawn when matplotlib is there.
# usage: test_compare_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

# col FILE ROW NAME: field NAME of data row ROW (1 = first after the header).
col() {
  awk -F, -v row="$2" -v name="$3" '/^#/ { next } !h { for (i = 1; i <= NF; ++i) c[$i] = i; h = 1; next }
    ++n == row { print (name in c) ? $c[name] : "<no column " name ">" }' "$1"
}

# ---- Delta z: reference 0, 1, 2, 3, 4 mm at 0, 0.5, 1, 1.5, 2 s; the run 2 mm at
# 0.1, 1.1, 2.1 s of its own time, offset -0.1 s.  Windows [0, 1] and [1, 2]: reference
# means 1 and 3 mm, Eq. 7 +100 % and -33.33 %; RMS at 0, 1, 2 s: sqrt(8/3) mm, over the
# 4 mm peak.  The ensemble summary holds the same curve as its mean.
cat >"$work/ref.csv" <<'CSV'
time_s,z_cog_bed_m,z_cog_d1.950mm_m,z_cog_d2.820mm_m,delta_z_m
0,0.1,0.1,0.1,0
0.5,0.1,0.1005,0.0995,0.001
1,0.1,0.101,0.099,0.002
1.5,0.1,0.1015,0.0985,0.003
2,0.1,0.102,0.098,0.004
CSV
printf 'time_s,z_cog_bed_m,delta_z_m\n0.1,0.1,0.002\n1.1,0.1,0.002\n2.1,0.1,0.002\n' >"$work/run.csv"
printf '# 2 members\ntime_s,delta_z_m_mean,delta_z_m_std\n0.1,0.002,1e-3\n1.1,0.002,1e-3\n2.1,0.002,1e-3\n' \
  >"$work/ensemble.csv"
if run "compare two windows" "$rcfd" compare -reference "$work/ref.csv" -rcfd "$work/run.csv,$work/ensemble.csv" \
  -labels run,ens -rcfd_time_offset -0.1 -score_window 0,1,1,2 -o "$work/dz.csv"; then
  s=$work/dz-scores.csv
  same "rows: run, window, Eq. 7" "$(for r in 1 2 3 4; do col "$s" $r run; col "$s" $r window_begin_s
    col "$s" $r relative_difference_percent; done)" "run 0 100 run 1 -33.3333333 ens 0 100 ens 1 -33.3333333" 1e-8
  same "mean reference, mean run, RMS, RMS/peak" "$(for n in mean_reference mean_run rms_difference rms_over_peak; do
    col "$s" 2 $n; done)" "0.003 0.002 $(awk 'BEGIN { printf "%.12g %.12g", sqrt(8 / 3) * 1e-3, sqrt(8 / 3) / 4 }')" 1e-8
  same "the ensemble scores as its mean" "$(col "$s" 4 rms_difference)" "$(col "$s" 2 rms_difference)" 0
  # 2.1 - 0.1 is 2.0000000000000004 in binary: the label says so, and reads back as the run's last time.
  [ "$(col "$s" 1 curve_end_s)" = 2 ] && [ "$(col "$s" 1 unit)" = m ] && ok ||
    fail "curve end and unit: $(col "$s" 1 curve_end_s) $(col "$s" 1 unit)"
  grep -q "1-2 " "$work/out.txt" && grep -q "over \[1, 2\] s (3 samples)" "$work/out.txt" && ok ||
    fail "window labels in the table: $(cat "$work/out.txt")"
fi
printf 'time_s,delta_z_m\n0,0.001\n0.1,0.002\n0.30000000000000004,0.003\n' >"$work/odd.csv"
if run "compare exact labels" "$rcfd" compare -reference "$work/odd.csv" -rcfd "$work/odd.csv" \
  -score_window 0,0.30000000000000004 -scores "$work/odd-scores.csv"; then
  same "labels read back" "$(col "$work/odd-scores.csv" 1 window_end_s) $(col "$work/odd-scores.csv" 1 curve_end_s)" \
    "0.30000000000000004 0.30000000000000004" 0
  [ "$(col "$work/odd-scores.csv" 1 window_end_s)" = 0.30000000000000004 ] && ok || fail "window label not exact"
fi

# ---- every class: z_cog,i - z_cog,bed [mm] at 0..3 s, reference d1 -2 -4 -6 -8, d2 0 1 0 -1,
# d3 1 3 5 10 (bed 0.1, 0.12, ...); the run (bed 0.11, classes labelled within 1 %) -1 -4 -7 -8,
# 2 3 2 1, 1 3 5 7: RMS sqrt(1/2), 2, 1.5 mm over peaks 8, 1, 10 mm.  Mass shares 0.2 / 0.3 / 0.5:
# poly-disperse sqrt(2.425) mm over d3's peak.  A second run lacks d2: d1, d3 weighed 0.2, 0.5.
awk 'BEGIN { print "time_s,z_cog_bed_m,z_cog_d1.000mm_m,z_cog_d2.000mm_m,z_cog_d3.000mm_m"
  split("-2 -4 -6 -8", a, " "); split("0 1 0 -1", b, " "); split("1 3 5 10", c, " ")
  for (k = 0; k < 4; ++k) { z = k % 2 ? 0.12 : 0.1
    printf "%d,%.9g,%.9g,%.9g,%.9g\n", k, z, z + a[k+1] / 1e3, z + b[k+1] / 1e3, z + c[k+1] / 1e3 } }' >"$work/ref-classes.csv"
awk 'BEGIN { print "time_s,z_cog_bed_m,z_cog_d1.005mm_m,z_cog_d2.000mm_m,z_cog_d3.02mm_m,delta_z_m,mass_d1.005mm_kg,mass_d2.000mm_kg,mass_d3.02mm_kg"
  split("-1 -4 -7 -8", a, " "); split("2 3 2 1", b, " "); split("1 3 5 7", c, " ")
  for (k = 0; k < 4; ++k) printf "%d,0.11,%.9g,%.9g,%.9g,%.9g,0.2,0.3,0.5\n", k, 0.11 + a[k+1] / 1e3, 0.11 + b[k+1] / 1e3,
    0.11 + c[k+1] / 1e3, (a[k+1] - c[k+1]) / 1e3 }' >"$work/run-classes.csv"
cut -d, -f1-3,5,6,7,9 "$work/run-classes.csv" | sed 's/d1.005mm/d1.000mm/g; s/d3.02mm/d3.000mm/g' >"$work/lacking.csv"
if run "compare every class" "$rcfd" compare -reference "$work/ref-classes.csv" -rcfd "$work/run-classes.csv,$work/lacking.csv" \
  -labels run,lacking -score_window 0,3 -o "$work/classes.csv"; then
  s=$work/classes-scores.csv
  rows=$(for r in 1 2 3 4 5 6 7 8 9 10; do col "$s" $r curve; done | tr '\n' ' ')
  [ "$rows" = "delta_z delta_z class_d1.000mm class_d2.000mm class_d3.000mm class_d1.000mm class_d3.000mm \
polydisperse polydisperse " ] && ok || fail "rows: Delta z first, then classes, then the poly-disperse number: $rows"
  same "RMS/peak of each class, the poly-disperse number and its ratio" "$(for r in 3 4 5; do col "$s" $r rms_over_peak
    done; for r in 8 9; do col "$s" $r rms_difference; col "$s" $r rms_over_peak; done)" \
    "$(awk 'BEGIN { printf "%.12g 2 0.15 %.12g %.12g %.12g %.12g", sqrt(0.5) / 8, sqrt(2.425) / 1e3, sqrt(2.425) / 10,
      sqrt(1.225 / 0.7) / 1e3, sqrt(1.225 / 0.7) / 10 }')" 1e-8
  # Scripts read the Delta z row as the line starting with the run's label: the class lines do not.
  [ "$(grep -c "^lacking " "$work/out.txt")" = 1 ] && ok || fail "more than the Delta z row start with the label"
  grep -q "Note: lacking: '$work/lacking.csv' has no class d2.000mm (within 1 %): not scored." "$work/out.txt" && ok ||
    fail "no note of the missing class: $(cat "$work/out.txt")"
  [ "$(head -1 "$work/classes-classes.csv")" = "time_s,class_d1.000mm_reference_m,class_d1.000mm_run_m,\
class_d1.000mm_lacking_m,class_d2.000mm_reference_m,class_d2.000mm_run_m,class_d2.000mm_lacking_m,\
class_d3.000mm_reference_m,class_d3.000mm_run_m,class_d3.000mm_lacking_m" ] && ok ||
    fail "header of the classes CSV: $(head -1 "$work/classes-classes.csv")"
fi
sed '1s/mass_d3.02mm_kg/mass_d3.5mm_kg/' "$work/run-classes.csv" >"$work/wrong-mass.csv"
expect_error "'$work/wrong-mass.csv' has mass columns of the classes d1.005mm, d2.000mm, d3.5mm but centre-of-gravity \
columns of d1.005mm, d2.000mm, d3.02mm: each class needs both, in the same order." compare \
  -reference "$work/ref-classes.csv" -rcfd "$work/wrong-mass.csv"

# ---- bottom layer: reference 2.3, 2.4, (empty layer), 2.6 mm at 0, 1, 2, 3 s; run 2.2 mm.
# Window [0, 3]: means 7.3/3 and 2.2 mm; RMS at 0..3 s (reference 2.5 mm at 2 s): sqrt(0.075) mm.
printf 'time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized\n0,0.0023,0.9,1.1,0\n1,0.0024,0.9,1.1,0\n2,nan,nan,1.1,0\n3,0.0026,1,1.1,0\n' \
  >"$work/ref-bottom.csv"
printf 'time_s,d32_bottom_m,umf_m_s,usup_m_s,defluidized\n0,0.0022,0.9,1.1,0\n1,0.0022,0.9,1.1,0\n2,0.0022,0.9,1.1,0\n3,0.0022,0.9,1.1,0\n' \
  >"$work/run-bottom.csv"
if run "compare bottom" "$rcfd" compare -reference "$work/ref-bottom.csv" -rcfd "$work/run-bottom.csv" \
  -score_window 0,3 -scores "$work/bottom-scores.csv"; then
  same "d32: curve, mean difference, RMS" "$(col "$work/bottom-scores.csv" 1 curve | tr -d d_bottom)
    $(col "$work/bottom-scores.csv" 1 mean_difference) $(col "$work/bottom-scores.csv" 1 rms_difference)" \
    "32 $(awk 'BEGIN { printf "%.12g %.12g", 2.2e-3 - 7.3e-3 / 3, sqrt(0.075) * 1e-3 }')" 1e-8
fi

# ---- profiles (4 layers, the top one empty): total differences 0, 0, 0.1, RMS sqrt(0.01/3);
# the small class -0.05, 0, 0.05, RMS sqrt(0.005/3), peak 0.3.  Halves: -0.1 / +0.1.
printf 'z,alpha_d1.950mm,alpha_d2.820mm,alpha_total\n0.0025,0.3,0.2,0.5\n0.0075,0.2,0.2,0.4\n0.0125,0.1,0,0.1\n0.0175,0,0,0\n' \
  >"$work/ref-profiles.csv"
printf 'z,alpha_d1.950mm,alpha_d2.820mm,alpha_total\n0.0025,0.25,0.25,0.5\n0.0075,0.2,0.2,0.4\n0.0125,0.15,0.05,0.2\n0.0175,0,0,0\n' \
  >"$work/run-profiles.csv"
if run "compare profiles" "$rcfd" compare -reference "$work/ref-profiles.csv" -rcfd "$work/run-profiles.csv" \
  -labels run -scores "$work/profiles-scores.csv"; then
  p=$work/profiles-scores.csv
  same "profiles: layers, RMS small, RMS/peak small, RMS total, max total" "$(col "$p" 1 layers) $(col "$p" 1 rms_difference)
    $(col "$p" 1 rms_over_peak) $(col "$p" 3 rms_difference) $(col "$p" 3 max_abs_difference)" \
    "3 $(awk 'BEGIN { printf "%.12g %.12g %.12g", sqrt(0.005 / 3), sqrt(0.005 / 3) / 0.3, sqrt(0.01 / 3) }') 0.1" 1e-8
fi
printf 'class,diameter,bottom_mass_fraction,top_mass_fraction\nd1.950mm,0.00195,0.4,0.6\nd2.820mm,0.00282,0.6,0.4\n' \
  >"$work/ref-halves.csv"
printf 'class,diameter,bottom_mass_fraction,top_mass_fraction\nd1.950mm,0.00195,0.3,0.7\nd2.820mm,0.00282,0.7,0.3\n' \
  >"$work/run-halves.csv"
if run "compare halves" "$rcfd" compare -reference "$work/ref-halves.csv" -rcfd "$work/run-halves.csv" \
  -scores "$work/halves-scores.csv"; then
  h=$work/halves-scores.csv
  same "halves: bottom and top differences, d32 of the reference's bottom half" \
    "$(col "$h" 1 bottom_difference) $(col "$h" 1 top_difference) $(col "$h" 2 bottom_difference) $(col "$h" 3 bottom_reference)" \
    "-0.1 0.1 0.1 0.002392950391644909" 1e-8
fi

# ---- database distance: a small synthetic database against a hand-made bed series
# (Delta z_CoG 0.01 m) and against itself through rcfd info's number.
printf 'time_s,z_cog_bed_m,delta_z_m\n0,0.10,0\n1,0.12,0\n2,0.10,0\n3,0.12,0\n' >"$work/bed.csv"
printf 'samples,mean_z_cog_m,delta_z_cog_m\n4,0.1,0.008\n' >"$work/bed_dynamics.csv"
if run "db_distance files" "$rcfd" compare -db_distance "$work/bed.csv,$work/bed_dynamics.csv" -scores "$work/db.csv"; then
  same "Delta DB of two files" "$(col "$work/db.csv" 1 delta_z_cog_a_m) $(col "$work/db.csv" 1 database_distance)" "0.01 0.25" 1e-9
fi
if [ -f "$data/small.h5" ] && info=$("$rcfd" info "$data/small.h5" 2>&1); then
  dyn=$(sed -n 's/.*Delta z_CoG = mean |z_CoG - mean| = \([^ ]*\) m.*/\1/p' <<<"$info")
  if run "db_distance database" "$rcfd" compare -db_distance "$data/small.h5,$work/bed.csv" -scores "$work/db2.csv"; then
    same "Delta DB of a database" "$(col "$work/db2.csv" 1 delta_z_cog_a_m) $(col "$work/db2.csv" 1 database_distance)" \
      "$dyn $(awk -v a="$dyn" 'BEGIN { printf "%.9g", (a > 0.01 ? a - 0.01 : 0.01 - a) / 0.01 }')" 1e-5
  fi
else
  fail "no small database in $data (fixture small_db)"
fi

# ---- more runs than PETSc's array options used to hold (16): every one is scored, none dropped.
runs=$(for i in $(seq 1 20); do printf '%s,' "$work/run.csv"; done)
if run "compare 20 runs" "$rcfd" compare -reference "$work/ref.csv" -rcfd "${runs%,}" -rcfd_time_offset -0.1 \
  -score_window 0,1 -o "$work/many.csv"; then
  same "20 runs scored" "$(($(grep -vc "^#" "$work/many-scores.csv") - 1))" 20 0
fi
expect_error "-mesh_cells takes at most 3 comma-separated values" build -dumps "$work/none.*" -mesh_cells 2,2,2,2
expect_error "-calibrate_models names the size law 'A' twice" calibrate -calibrate_models A,B,A \
  -reference "$work/ref.csv"

# ---- bad input: one sentence naming the file.
expect_error "'$work/ref.csv', delta_z: the scoring window [5, 10] s holds no sample of the reference." compare \
  -reference "$work/ref.csv" -rcfd "$work/run.csv" -score_window 5,10
expect_error "'$work/run.csv', delta_z: the scoring window [0, 1] s holds no sample of the rcfd run." compare \
  -reference "$work/ref.csv" -rcfd "$work/run.csv" -rcfd_time_offset 5 -score_window 0,1
expect_error "'$work/ref-halves.csv' is a halves file but the reference '$work/ref.csv' is a centre-of-gravity file" \
  compare -reference "$work/ref.csv" -rcfd "$work/ref-halves.csv"
printf 'time_s,umf_m_s\n0,1\n' >"$work/other.csv"
expect_error "'$work/other.csv' is none of the files rcfd compare reads" compare -reference "$work/ref.csv" \
  -rcfd "$work/other.csv"
printf 'time_s,z_cog_bed_m,z_cog_d1.950mm_m\n0,0.1,0.1\n' >"$work/oneclass.csv"
expect_error "'$work/oneclass.csv' is not a centre-of-gravity file: its header needs a time_s column and delta_z_m" \
  compare -reference "$work/ref.csv" -rcfd "$work/oneclass.csv"
expect_error "'$work/ref-profiles.csv' has no z_cog_bed_m column" compare -db_distance "$work/ref-profiles.csv,$work/bed.csv"
expect_error "'$work/ensemble.csv' is an ensemble summary" compare -db_distance "$work/ensemble.csv,$work/bed.csv"
printf 'z,alpha_d1.950mm,alpha_total\n0.005,0.3,0.3\n0.015,0.1,0.1\n' >"$work/coarse.csv"
expect_error "'$work/coarse.csv' has other layers than the reference '$work/ref-profiles.csv'" compare \
  -reference "$work/ref-profiles.csv" -rcfd "$work/coarse.csv"
printf 'class,diameter,bottom_mass_fraction,top_mass_fraction\nd1.950mm,0.00195,0.4\n' >"$work/short.csv"
expect_error "'$work/short.csv', line 2: expected 4 values (as many as the header names), found 3" compare -reference "$work/ref-halves.csv" \
  -rcfd "$work/short.csv"
expect_error "-score_window takes pairs of times t0,t1[,t0,t1...] [s], not 3 numbers" compare \
  -reference "$work/ref.csv" -rcfd "$work/run.csv" -score_window 0,1,2
expect_error "-o writes curves over time, which the profiles file" compare -reference "$work/ref-profiles.csv" \
  -rcfd "$work/run-profiles.csv" -o "$work/x.csv"

# ---- figures of profiles and halves (when matplotlib is there).
python=${RCFD_PYTHON:-/usr/bin/python3}
[ -x "$python" ] || python=python3
if "$python" -c 'import matplotlib, numpy' 2>/dev/null; then
  run "figure of every class" "$rcfd" compare -reference "$work/ref-classes.csv" \
    -rcfd "$work/run-classes.csv,$work/lacking.csv" -labels run,lacking -png "$work/classes.png" &&
    [ "$(stat -c %s "$work/classes.png" 2>/dev/null || echo 0)" -gt 10000 ] && [ -s "$work/classes-classes.csv" ] &&
    ok || fail "no sensible classes.png"
  for kind in profiles halves; do
    run "figure of $kind" "$rcfd" compare -reference "$work/ref-$kind.csv" -rcfd "$work/run-$kind.csv" \
      -png "$work/$kind.png" -title "$kind" && [ "$(stat -c %s "$work/$kind.png" 2>/dev/null || echo 0)" -gt 10000 ] &&
      ok || fail "no sensible $kind.png"
  done
fi

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
