#!/usr/bin/env bash
# A stitched run restarted from its mid-run checkpoint writes the same files,
# byte for byte, as one uninterrupted run, at 1 and 2 ranks: restarted into
# its own output directory (the time series are cut back to the checkpoint's
# step and appended to) and into another one (they are copied first;
# jumps.csv, with delta z and z_cog around every carry, among them), with
# another -t_end.  A restart that would change the physics -- another
# database of the same mesh, other diameters, another pipeline, another
# operator option -- is refused with one sentence naming what differs.
# usage: test_restart.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
series=(cog.csv mixing.csv bottom.csv path.txt jumps.csv)
common=(-db "$data/default.h5" -db_frames 0,99 -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random
  -path_seed 11 -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -mixing_index
  -bottom_layer)
same_series() { # same_series LABEL DIR_A DIR_B: every time series byte-identical
  local f
  for f in "${series[@]}"; do
    if cmp -s "$2/$f" "$3/$f"; then ok; else fail "$1: $3/$f differs from $2/$f"; fi
  done
}
for np in 1 2; do
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -output_dir "$work/full$np"
  # Stopped at 1.5 s with its checkpoint at 1 s: the files run past the checkpoint.
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 1.5 -checkpoint_every 1 -output_dir "$work/first$np"
  [ "$(wc -l <"$work/first$np/cog.csv")" -eq 302 ] || fail "first$np/cog.csv should hold 301 rows to 1.5 s"
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -restart "$work/first$np/checkpoint.h5" \
    -output_dir "$work/second$np"
  same_series "restart into another directory, $np rank(s)" "$work/full$np" "$work/second$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -restart "$work/first$np/checkpoint.h5" \
    -output_dir "$work/first$np"
  same_series "restart into its own directory, $np rank(s)" "$work/full$np" "$work/first$np"
  # The path actually jumped, so the test covers carrying across jumps.
  awk 'NR > 2 && $1 != prev + 1 { j++ } { prev = $1 } END { exit !(j >= 5) }' "$work/full$np/path.txt" ||
    fail "the path of full$np did not jump"
done
# The checkpoint holds no time series: its size does not depend on the step.
size1=$(stat -c %s "$work/first1/checkpoint.h5")
mpiexec -n 1 "$rcfd" run "${common[@]}" -t_end 0.2 -checkpoint_every 0.1 -output_dir "$work/early1"
size0=$(stat -c %s "$work/early1/checkpoint.h5")
[ "$size0" -eq "$size1" ] && ok || fail "checkpoint at 0.1 s holds $size0 bytes, at 1 s $size1"

# A checkpoint on the small database, and the refusals of restarts that change the physics.
small=(-quiet -fields 0 -plot 0 -path_type random -path_seed 11 -fractions_diameters 1.459e-3,4.075e-3
  -fractions_mass_shares 0.564,0.436)
"$rcfd" synth -o "$work/a.h5" -synth_cells 10,2,20 -synth_frames 60 -quiet
"$rcfd" synth -o "$work/b.h5" -synth_cells 10,2,20 -synth_frames 60 -synth_seed 2 -quiet
"$rcfd" run -db "$work/a.h5" "${small[@]}" -t_end 0.2 -checkpoint_every 0.1 -output_dir "$work/s"
restart=(run "${small[@]}" -t_end 0.4 -restart "$work/s/checkpoint.h5" -output_dir "$work/refused")
expect_error "continues a run made with another database (content " "${restart[@]}" -db "$work/b.h5"
expect_error "continues a run made with another set of diameters (0.001459,0.004075 there, 0.0015,0.004075 here)" "${restart[@]}" \
  -db "$work/a.h5" -fractions_diameters 1.5e-3,4.075e-3
expect_error "continues a run made with other options of the drift operator ((defaults) there, -drift_kd 2000 here)" \
  "${restart[@]}" -db "$work/a.h5" -drift_kd 2000
expect_error "continues a run made with another pipeline (shift,drift,carry there, shift,carry here)" \
  "${restart[@]}" -db "$work/a.h5" -pipeline shift,carry
[ ! -e "$work/refused/cog.csv" ] && ok || fail "a refused restart wrote $work/refused/cog.csv"
# Run control may change: another -t_end, the progress and the viewers; and the same database made
# again is the same database (its identity is a hash of its contents).
"$rcfd" synth -o "$work/a_again.h5" -synth_cells 10,2,20 -synth_frames 60 -quiet
"$rcfd" run -db "$work/a.h5" "${small[@]}" -t_end 0.3 -output_dir "$work/s_full"
"$rcfd" run -db "$work/a_again.h5" "${small[@]}" -t_end 0.3 -progress_interval 5 -drift_view \
  -restart "$work/s/checkpoint.h5" -output_dir "$work/s" >/dev/null
cmp -s "$work/s_full/cog.csv" "$work/s/cog.csv" && ok || fail "a restart with another -t_end differs"
# Restarting with another number of fractions is refused with a sentence.
expect_error "holds 400 cells x 2 fractions, but this run has 400 x 3" run -db "$work/a.h5" -quiet -fields 0 \
  -plot 0 -t_end 0.4 -fractions_diameters 1e-3,2e-3,3e-3 -fractions_mass_shares 0.3,0.3,0.4 \
  -restart "$work/s/checkpoint.h5" -output_dir "$work/wrong"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
