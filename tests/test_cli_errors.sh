#!/usr/bin/env bash
# Bad input gets one sentence naming the file or option and what was
# expected: no traceback, no crash, a non-zero exit code.
# usage: test_cli_errors.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

db=$data/default.h5
expect_error "unknown command 'rnu'" rnu
expect_error "No database given: pass -db FILE" run
expect_error "cannot open file '$work/none.h5': it does not exist" run -db "$work/none.h5"
echo "plain text" >"$work/text.h5"
expect_error "file '$work/text.h5' is not an HDF5 file" run -db "$work/text.h5"
expect_error "Unknown option -t_edn" run -db "$db" -t_edn 1
expect_error "-fractions_diameters: diameter 2 is -0.002" run -db "$db" \
  -fractions_diameters 1e-3,-2e-3 -fractions_mass_shares 0.5,0.5
expect_error "-fractions_mass_shares sum to 0.9" run -db "$db" \
  -fractions_diameters 1e-3,2e-3 -fractions_mass_shares 0.5,0.4
expect_error "-fractions_mass_shares has 1 values but -fractions_diameters has 2" run -db "$db" \
  -fractions_diameters 1e-3,2e-3 -fractions_mass_shares 1
many_d=$(seq -s, 1 65 | sed 's/[0-9]\+/1e-3/g') many_w=$(seq -s, 1 65 | sed 's/[0-9]\+/0.015384615384615385/g')
expect_error "-fractions_diameters has 65 diameters; rcfd handles at most 64 fractions" run -db "$db" \
  -fractions_diameters "$many_d" -fractions_mass_shares "$many_w"
expect_error "-pipeline: unknown operator 'shfit'" run -db "$db" -pipeline shfit
expect_error "-init sideways is not known" run -db "$db" -init sideways
expect_error "-init file needs -init_file FILE" run -db "$db" -init file
expect_error "-db_frames 5:2 is outside" run -db "$db" -db_frames 5,2
expect_error "Unknown option -bogus" info "$db" -bogus
expect_error "cannot open file 'nope.h5'" info nope.h5
expect_error "-extra_csv takes NAME,FILE" info "$db" -extra_csv measured_drift_field
expect_error "has no dataset /extra/measured_drift_field to write with -extra_csv" info "$db" \
  -extra_csv "measured_drift_field,$work/field.csv"

# Words PETSc would ignore, options files it cannot read, lists that are empty or repeat.
expect_error "unexpected argument 'strayword'" run -db "$db" strayword
expect_error "unexpected argument 'b.h5'" info "$db" b.h5
expect_error "unexpected argument 'dump.2.gz'" build -dumps dump.1.gz dump.2.gz -o x.h5
expect_error "-options_file '$work/none.yaml' cannot be read" run -options_file "$work/none.yaml"
printf 'db: x.h5\nt_end 5\n' >"$work/bad.yaml"
expect_error "-options_file '$work/bad.yaml' line 2 is not 'name: value'" run -options_file "$work/bad.yaml"
printf 'db: x.h5\n\tt_end: 5\n' >"$work/tab.yaml"
expect_error "line 2 is indented with a tab" run -options_file "$work/tab.yaml"
printf 'db: "x.h5\n' >"$work/quote.yaml"
expect_error "line 1 opens a quote it does not close" run -options_file "$work/quote.yaml"
# A key given twice: YAML forbids it and PETSc would take the last value without a word.
printf 'db: x.h5\nt_end: 0.1\n# t_end: 2\nfields: false\nt_end: 5\n' >"$work/twice.yaml"
expect_error "-options_file '$work/twice.yaml' gives 't_end' on line 2 and again on line 5" \
  run -options_file "$work/twice.yaml"
# ... also inside a nested mapping, and as a nested key and its flat option name.
printf 'drift:\n  kd: 5e3\n  model: B\n  kd: 6e3\n' >"$work/nested.yaml"
expect_error "-options_file '$work/nested.yaml' gives 'drift_kd' on line 2 and again on line 4" \
  run -options_file "$work/nested.yaml"
printf 'drift_kd: 5e3\ndrift:\n  model: B\n  kd: 6e3\nt_end: 1\n' >"$work/flat.yaml"
expect_error "-options_file '$work/flat.yaml' gives 'drift_kd' on line 1 and again on line 4" \
  run -options_file "$work/flat.yaml"
# The same name under two parents is two options (read: carry_kd is then unknown); a key repeated in
# another file is a later file's choice.
printf 'drift:\n  kd: 5e3\ncarry:\n  kd: 5e3\n' >"$work/two-parents.yaml"
printf 'drift_kd: 6e3\n' >"$work/later.yaml"
expect_error "Unknown option -carry_kd" run -options_file "$work/two-parents.yaml" \
  -options_file "$work/later.yaml" -db "$work/none.h5"
expect_error "-fractions_diameters is empty" run -db "$db" -fractions_diameters ""
expect_error "-fractions_mass_shares was given without -fractions_diameters" run -db "$db" \
  -fractions_mass_shares 0.5,0.5
expect_error "diameters 1 and 2 are equal" run -db "$db" -fractions_diameters 2e-3,2e-3 \
  -fractions_mass_shares 0.5,0.5
# Diameters that print alike at three decimals get labels that tell them apart.
if "$rcfd" run -db "$db" -fractions_diameters 2.0001e-3,2.0004e-3 -fractions_mass_shares 0.5,0.5 \
  -t_end 0.01 -output_dir "$work/alike" -quiet -fields false -plot false &&
  head -1 "$work/alike/cog.csv" | grep -q "z_cog_d2.0001mm_m,z_cog_d2.0004mm_m"; then ok
else fail "labels of 2.0001 and 2.0004 mm: $(head -1 "$work/alike/cog.csv" 2>&1)"; fi
expect_error "-synth_cells 2000,2000,2000 asks for 8e+09 cells" synth -synth_cells 2000,2000,2000 -o "$work/s.h5"
# A fraction without mass has no centre of gravity: nan, not 0 m.
if "$rcfd" run -db "$db" -fractions_diameters 2e-3,3e-3 -fractions_mass_shares 1,0 -t_end 0.01 \
  -output_dir "$work/empty" -quiet -fields false -plot false &&
  awk -F, 'NR == 2 { exit !($4 == "nan" && $5 == "nan" && $3 + 0 > 0) }' "$work/empty/cog.csv"; then ok
else fail "a fraction without mass: $(sed -n 2p "$work/empty/cog.csv" 2>&1)"; fi
# Every numeric option checked where it is read: not finite, out of range, or meaningless.
expect_error "-t_end nan: expected a positive time in s" run -db "$db" -t_end nan
expect_error "-t_end inf: expected a positive time in s" run -db "$db" -t_end inf
expect_error "-t_end 1e+300: expected a positive time in s" run -db "$db" -t_end 1e300
expect_error "-t_end -5: expected a positive time in s" run -db "$db" -t_end -5
expect_error "-t_end 1e-05 s is 0.002 steps of dt_rec" run -db "$db" -t_end 1e-5
expect_error "-solid_density 0: expected a positive density" run -db "$db" -solid_density 0
expect_error "-fields_every -1: expected a number >= 0" run -db "$db" -fields_every -1
expect_error "-drift_kd -5: expected a number >= 0" run -db "$db" -drift_kd -5
expect_error "-drift_alpha_max 1.5: expected a number in (0, 1]" run -db "$db" -drift_alpha_max 1.5
expect_error "-drift_size_law drga is not a known size law; known: A, B, drag, log, power" run -db "$db" \
  -drift_size_law drga
expect_error "-drift_size_law_exponent 0: expected an exponent m in (0, 20]" run -db "$db" -drift_size_law power \
  -drift_kd 0.01 -drift_size_law_exponent 0
expect_error "-drift_size_law_exponent -1: expected an exponent m in (0, 20]" run -db "$db" -drift_size_law power \
  -drift_kd 0.01 -drift_size_law_exponent -1
expect_error "-drift_size_law drag has no default k_d: give -drift_kd (in m/s)" run -db "$db" -drift_size_law drag
expect_error "-drift_size_law log cannot be used with -drift_model constant" run -db "$db" -drift_size_law log \
  -drift_model constant -drift_velocities 0.01,-0.01
expect_error "-drift_agitation_reference needs -drift_agitation leaving or dispersion" run -db "$db" \
  -drift_agitation_reference 20
expect_error "-drift_agitation_reference -2: expected a positive agitation" run -db "$db" -drift_agitation leaving \
  -drift_agitation_reference -2
expect_error "-calibrate_models: size law 'C' is not known; use any of A, B, drag, log, power" calibrate -db "$db" \
  -calibrate_from measured -calibrate_models A,C
expect_error "-monitor_every 0: expected a whole number from 1" run -db "$db" -monitor_every 0
expect_error "-synth_packing 1: expected a number between 0 and 1" synth -synth_packing 1 -o "$work/s.h5"
expect_error "-pipeline is empty" run -db "$db" -pipeline ""
expect_error "-pipeline names 'shift' twice" run -db "$db" -pipeline shift,drift,shift
# Outputs that cannot be made: one sentence, nothing written.
expect_error "-output_dir is empty" run -db "$db" -output_dir ""
touch "$work/plain"
expect_error "-output_dir '$work/plain' is a file; expected a directory" run -db "$db" -output_dir "$work/plain"
expect_error "-checkpoint_file '$work' is a directory" run -db "$db" -checkpoint_file "$work" \
  -checkpoint_every 0.01 -output_dir "$work/cp"
[ ! -e "$work/cp" ] && ok || fail "a refused checkpoint file left $work/cp behind"
# Scalars (docs/scalars.md): negative or NaN values, bad names, a feed without their values.
expect_error "-scalar_temperature_initial -1: expected a value >= 0 (no negative or NaN values)" run -db "$db" \
  -scalars temperature -scalar_temperature_initial -1 -output_dir "$work/sc"
expect_error "-scalar_temperature_initial nan: expected a value >= 0 (no negative or NaN values)" run -db "$db" \
  -scalars temperature -scalar_temperature_initial nan -output_dir "$work/sc"
expect_error "-scalar_moisture_zone_values: value 1 is -0.5; expected a value >= 0" run -db "$db" -scalars moisture \
  -zones low -zone_low_layers 0,3 -scalar_moisture_zones low -scalar_moisture_zone_values -0.5 -output_dir "$work/sc"
expect_error "-scalars: 'bad-name' is not a scalar name" run -db "$db" -scalars bad-name -output_dir "$work/sc"
expect_error "-feed_scalar_tracer is not given; the feed needs the value of every scalar it brings" run -db "$db" \
  -scalars tracer -pipeline shift,drift,carry,feed -zones f -zone_f_layers 0,3 -feed_zone f -feed_rate 0.1 \
  -output_dir "$work/sc"
[ ! -e "$work/sc" ] && ok || fail "a refused run with scalars left $work/sc behind"
expect_error "-moisture_umf_coefficient needs a scalar named moisture in -scalars" run -db "$db" -bottom_layer \
  -moisture_umf_coefficient 50 -output_dir "$work/wet-umf"
# Help from the program itself, not "unknown command".
if "$rcfd" -help | grep -q "usage: rcfd <command>"; then ok; else fail "rcfd -help"; fi

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
