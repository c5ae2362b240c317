#!/usr/bin/env bash
# rcfd build / reference / run / compare on three hand-made dump files, with
# every number worked out by hand.  (Bad particle input: test_particle_cli_errors.sh.)
#
# Mesh 2 x 1 x 2 cells of 1 cm: cell = i + 2 k (0: low left, 1: low right,
# 2: high left, 3: high right).  Particle 1 (d = 1 mm, mass m) and particle
# 2 (d = 2 mm, mass 8 m) start in cell 0, at z = 4 and 6 mm; then
#   t = 0.2 s: 1 -> cell 2 (centre), 2 -> cell 1 (centre)
#   t = 0.3 s: 1 -> cell 3 (centre), 2 stays in cell 1.
# So T_0 = {(1,0): 8/9, (2,0): 1/9} plus identity columns 1, 2, 3 (empty at
# t_0), T_1 = identity except (3,2) = 1; with stride 2, T(1,0) = 8/9, T(3,0) = 1/9.
# usage: test_particle_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
h5print=$(dirname "$2")/h5_print
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
write_two_particle_dumps

# ---- build: metadata, alpha_s and both shift matrices.
db=$work/db.h5
if run "build" "$rcfd" build "${common[@]}" -o "$db" -init_out "$work/init.h5" -quiet; then
  m=$(awk 'BEGIN { printf "%.17g", 1440 * atan2(0, -1) / 6 * 1e-9 }') # kg, the 1 mm particle
  same "dt_rec" "$("$h5print" "$db" /metadata dt_rec)" "0.1"
  same "solid_density" "$("$h5print" "$db" /metadata solid_density)" "1440"
  same "gravity" "$("$h5print" "$db" /metadata gravity)" "0 0 -9.81"
  same "box_length" "$("$h5print" "$db" /mesh box_length)" "0.02 0.01 0.02"
  same "num_frames" "$("$h5print" "$db" /frames num_frames)" "2"
  # alpha_s of frame 0: both particles in cell 0 of volume 1e-6 m^3.
  same "alpha_s 0" "$("$h5print" "$db" /frames/000000/alpha_s)" \
    "$(awk 'BEGIN { printf "%.17g 0 0 0", atan2(0, -1) / 6 * 9e-9 / 1e-6 }')"
  same "alpha_s 1" "$("$h5print" "$db" /frames/000001/alpha_s)" \
    "0 $(awk 'BEGIN { printf "%.17g %.17g 0", atan2(0, -1) / 6 * 8e-9 / 1e-6, atan2(0, -1) / 6 * 1e-9 / 1e-6 }')"
  same "T_0 row_ptr" "$("$h5print" "$db" /frames/000000/shift_row_ptr)" "0 0 2 4 5"
  same "T_0 col" "$("$h5print" "$db" /frames/000000/shift_col)" "0 1 0 2 3"
  same "T_0 val" "$("$h5print" "$db" /frames/000000/shift_val)" \
    "$(awk 'BEGIN { printf "%.17g 1 %.17g 1 1", 8 / 9, 1 / 9 }')"
  same "T_1 row_ptr" "$("$h5print" "$db" /frames/000001/shift_row_ptr)" "0 1 2 2 4"
  same "T_1 col" "$("$h5print" "$db" /frames/000001/shift_col)" "0 1 2 3"
  same "T_1 val" "$("$h5print" "$db" /frames/000001/shift_val)" "1 1 1 1"
  grep -q "^snapshots 3, frames 2, cells 4, particles 2" \
    <<<"$("$h5print" "$db" /metadata build_report string)" && ok || fail "build_report attribute"
  # The measured drift field: one region (2 x 2 x 2 cells by default) holds the mesh.  Frame 0: in
  # cell 0 the small particle rises 11 mm and the large sinks 1 mm, the cell's bulk (11 m - 8 m) / 9 m
  # = 1/3 mm; frame 1: each alone in its cell, so no velocity relative to its bulk.
  same "drift field layout" "$("$h5print" "$db" /extra/measured_drift_field_layout)" "2 2 2 0.001 0.002"
  same "drift field" "$("$h5print" "$db" /extra/measured_drift_field)" \
    "$(awk -v m="$m" 'BEGIN { printf "%.17g 1 %.17g %.17g 1 %.17g 0 1 %.17g 0 1 %.17g",
                              (0.011 - 0.001 / 3) / 0.1, m, (-0.001 - 0.001 / 3) / 0.1, 8 * m, m, 8 * m }')" 1e-14
  # rcfd info -extra_csv writes the same numbers as CSV (a header c0 ... c5, one row per frame and region).
  if run "info -extra_csv" "$rcfd" info "$db" -extra_csv "measured_drift_field,$work/field.csv"; then
    same "drift field csv" "$(grep -v '^#' "$work/field.csv" | tail -n +2 | tr ',' ' ')" \
      "$("$h5print" "$db" /extra/measured_drift_field)" 0
    same "drift field csv header" "$(grep -v '^#' "$work/field.csv" | head -1 | tr -d 'c' | tr ',' ' ')" "0 1 2 3 4 5" 0
  fi
  # The initial composition: both classes in cell 0, ascending diameters.
  same "init masses" "$("$h5print" "$work/init.h5" /masses)" \
    "$m $(awk -v m="$m" 'BEGIN { printf "%.17g", 8 * m }') 0 0 0 0 0 0"
  same "init diameters" "$("$h5print" "$work/init.h5" /masses diameters)" "0.001 0.002"
  same "init shares" "$("$h5print" "$work/init.h5" /masses mass_shares)" \
    "$(awk 'BEGIN { printf "%.17g %.17g", 1 / 9, 8 / 9 }')"
fi

# ---- stride 2: one frame straight from t = 0.1 to 0.3 s.
if run "build stride 2" "$rcfd" build "${common[@]}" -frame_stride 2 -o "$work/db2.h5" -quiet; then
  same "stride 2 dt_rec" "$("$h5print" "$work/db2.h5" /metadata dt_rec)" "0.2"
  same "stride 2 row_ptr" "$("$h5print" "$work/db2.h5" /frames/000000/shift_row_ptr)" "0 0 2 3 5"
  same "stride 2 col" "$("$h5print" "$work/db2.h5" /frames/000000/shift_col)" "0 1 2 0 3"
  same "stride 2 val" "$("$h5print" "$work/db2.h5" /frames/000000/shift_val)" \
    "$(awk 'BEGIN { printf "%.17g 1 1 %.17g 1", 8 / 9, 1 / 9 }')"
fi

# ---- reference: hand-computed centres of gravity.
# t = 0.1: z_bed = (4 m + 6 * 8 m) / 9 m mm, delta_z = 4 - 6 = -2 mm;
# t = 0.2 and 0.3: small at 15 mm, large at 5 mm, bed (15 + 40) / 9 mm.
if run "reference" "$rcfd" reference "${common[@]}" -o "$work/ref" -average_window 0.15,0.35 -quiet; then
  [ "$(head -n 1 "$work/ref/cog.csv")" = "time_s,z_cog_bed_m,z_cog_d1.000mm_m,z_cog_d2.000mm_m,delta_z_m" ] &&
    ok || fail "reference header: $(head -n 1 "$work/ref/cog.csv")"
  same "reference rows" "$(tail -n +2 "$work/ref/cog.csv" | tr ',' ' ')" \
    "$(awk 'BEGIN { printf "0.1 %.17g 0.004 0.006 -0.002 0.2 %.17g 0.015 0.005 0.01 0.3 %.17g 0.015 0.005 0.01",
                    0.052 / 9, 0.055 / 9, 0.055 / 9 }')" 1e-8
  # Halves over t = 0.2, 0.3: the mass median is the large particle (8/9 of
  # the mass) at 5 mm.  Counted by centre (the default), bottom all large,
  # top all small; counted by overlap half of it is below: bottom 4 m all
  # large, top m small + 4 m large (0.2, 0.8).
  same "halves" "$(tail -n +3 "$work/ref/halves.csv" | cut -d, -f3,4 | tr ',' ' ')" "0 1 1 0" 1e-8
fi
if run "reference by overlap" "$rcfd" reference "${common[@]}" -o "$work/ref-overlap" \
  -average_window 0.15,0.35 -particle_volume overlap -quiet; then
  same "halves by overlap" "$(tail -n +3 "$work/ref-overlap/halves.csv" | cut -d, -f3,4 | tr ',' ' ')" \
    "0 0.2 1 0.8" 1e-8
fi

# ---- a replay run from -init_out: both classes start in cell 0; the shift
# moves the cell's *mixture*, 8/9 to cell 1 (z = 5 mm) and 1/9 to cell 2
# (z = 15 mm), so after one step every class has z_cog = (8 * 5 + 15) / 9 mm
# = the reference's bed centre at 0.2 s, and delta_z = 0 (the shift cannot
# separate sizes within a cell; that is the drift operator's job).
# compare against the reference, runs shifted by 0.1 s: curve samples at
# 0.1 and 0.2 s with differences 2 and -10 mm: RMS sqrt((4 + 100) / 2) mm,
# peak 10 mm; Eq. 7 over [0.15, 0.35] s: run 0, reference 10 mm: -100 %.
if run "run from init_out" "$rcfd" run -db "$db" -init file -init_file "$work/init.h5" \
  -fractions_diameters 0.001,0.002 -fractions_mass_shares 0.111111111111,0.888888888889 \
  -pipeline shift -t_end 0.1 -fields false -quiet -output_dir "$work/run"; then
  same "run rows" "$(tail -n +2 "$work/run/cog.csv" | cut -d, -f1-7 | tr ',' ' ')" \
    "$(awk -v m="$m" 'BEGIN { z = 0.055 / 9; printf "0 0.005 0.005 0.005 0 %.17g %.17g 0.1 %.17g %.17g %.17g 0 %.17g %.17g",
                               m, 8 * m, z, z, z, m, 8 * m }')" 1e-9
  if run "compare" "$rcfd" compare -reference "$work/ref/cog.csv" -rcfd "$work/run/cog.csv" \
    -labels shift -rcfd_time_offset 0.1 -score_window 0.15,0.35 -o "$work/curves.csv"; then
    line=$(grep "^shift " "$work/out.txt")
    same "compare mean, Delta_seg, RMS, RMS/peak" "$(awk '{ print $2, $3, $4, $5 }' <<<"$line")" \
      "0.0000 -100.0 $(awk 'BEGIN { printf "%.4f %.3f", sqrt(52), sqrt(52e-6) / 0.01 }')" 1e-9
    # The curves at the reference's times; the run ends at 0.2 s.
    [ "$(sed -n 4p "$work/curves.csv")" = "0.3,0.01," ] && ok || fail "curves row 3: $(sed -n 4p "$work/curves.csv")"
    same "compare curves" "$(sed -n 2,3p "$work/curves.csv" | tr ',' ' ')" "0.1 -0.002 0 0.2 0.01 0" 1e-12
  fi
fi

# ---- runs that stay inside their database: two frames, so the default t_end
# is one step (the second would wrap from frame 1 to frame 0) and no jumps.csv;
# -t_end 0.3 takes frames 0, 1, 0: one note, and the row at t = 0.2 s (after
# step 2) follows the wrap from frame 1 to frame 0.
run_short() { # run_short DIR [options]
  local dir=$1
  shift
  "$rcfd" run -db "$db" -init file -init_file "$work/init.h5" -fractions_diameters 0.001,0.002 \
    -fractions_mass_shares 0.111111111111,0.888888888889 -pipeline shift -fields false \
    -plot false -output_dir "$dir" "$@"
}
# -init_out writes checksums: a flipped bit in the masses is refused with rcfd's sentence naming the
# file (PETSc's VecLoad used to report only HDF5's failure to close it).
h5bytes=$(dirname "$2")/h5_bytes
cp "$work/init.h5" "$work/damaged-init.h5"
"$h5bytes" "$work/damaged-init.h5" flip $(($("$h5bytes" "$work/init.h5" locate /masses) + 8)) 2
[ "$("$h5print" "$work/init.h5" / checksums string)" = fletcher32 ] && ok || fail "-init_out wrote no checksums"
expect_error "HDF5 file '$work/damaged-init.h5': '/masses' is damaged" run -db "$db" -init file \
  -init_file "$work/damaged-init.h5" -fractions_diameters 0.001,0.002 -fractions_mass_shares 0.111111111111,0.888888888889 \
  -output_dir "$work/refused-init"
if run "run with the default t_end" run_short "$work/one-pass"; then
  same "one pass: rows" "$(tail -n +2 "$work/one-pass/cog.csv" | cut -d, -f1 | paste -sd' ')" "0 0.1"
  [ ! -e "$work/one-pass/jumps.csv" ] && ok || fail "a run inside its database wrote jumps.csv"
  ! grep -q "wraps" "$work/out.txt" && ok || fail "a run inside its database printed a wrap note"
fi
if run "run past the database" run_short "$work/wrapped" -t_end 0.3; then
  [ "$(grep -c "wraps to frame 0 at t = 0.2 s" "$work/out.txt")" = 1 ] && ok ||
    fail "wrap note: $(cat "$work/out.txt")"
  same "jumps.csv" "$(tail -n +3 "$work/wrapped/jumps.csv" | cut -d, -f1-4 | tr ',' ' ')" "2 0.2 1 0"
  # The same directory again with one pass: the stale jumps.csv goes.
  run "run again inside" run_short "$work/wrapped" -quiet &&
    { [ ! -e "$work/wrapped/jumps.csv" ] && ok || fail "a stale jumps.csv stayed"; }
fi

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
