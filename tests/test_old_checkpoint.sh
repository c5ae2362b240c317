#!/usr/bin/env bash
# Checkpoints of an older rcfd, made from today's by deleting what that rcfd did not write
# (tests/h5_edit): no root attribute jumps_csv_bytes (jumps.csv was written at the run's end), no
# /operators group (before the granulation operators), cog.csv's state without its signals (before
# several databases).  A stitched run restarted from one writes the same cog.csv, mixing.csv,
# path.txt and jumps.csv, byte for byte, as one uninterrupted run, at 1 and 2 ranks, into its own
# output directory and into another; jumps.csv's earlier rows are rebuilt from path.txt, including
# a jump at the checkpoint's own step and none before it: their step, time and frames byte for byte,
# and nan for what the carry did (that rcfd did not record it), the rows after the checkpoint whole.  A checkpoint missing something a restart
# cannot do without is refused with one sentence naming the file and what is missing, writing nothing.
# usage: test_old_checkpoint.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
edit=$(dirname "$2")/h5_edit
source "$4/tests/script_helpers.sh"
common=(-db "$data/small.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 11
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -mixing_index)
files=(cog.csv mixing.csv path.txt jumps.csv)

older() { # older CHECKPOINT: as the rcfd of checkpoint version 2's first day wrote it
  "$edit" "$1" delete / jumps_csv_bytes && "$edit" "$1" delete /operators && "$edit" "$1" keep /monitors/cog.csv 1
}
same_files() { # same_files LABEL DIR_A DIR_B CHECKPOINT_STEP
  local f
  for f in "${files[@]}"; do
    if [ $f = jumps.csv ]; then # rows up to the checkpoint rebuilt: their first four columns, nan after them
      if cmp -s <(awk -F, -v s="$4" '/^[0-9]/ && $1 <= s { n = NF; $0 = $1 "," $2 "," $3 "," $4
               for (i = 5; i <= n; ++i) $0 = $0 ",nan" } 1' "$2/$f") "$3/$f"; then ok
      else fail "$1: $3/$f differs from $2/$f with nan for the carry in its rows up to step $4"; fi
    elif cmp -s "$2/$f" "$3/$f"; then ok; else fail "$1: $3/$f differs from $2/$f"; fi
  done
}

for np in 1 2; do
  run "full run np$np" mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -output_dir "$work/full$np" || continue
  # Stopped at 1.5 s with its checkpoint at 1 s (step 200): the files run past the checkpoint.
  run "first part np$np" mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 1.5 -checkpoint_every 1 \
    -output_dir "$work/first$np" && run "older np$np" older "$work/first$np/checkpoint.h5" || continue
  run "restart into another directory np$np" mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 \
    -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np" &&
    same_files "older checkpoint into another directory, $np rank(s)" "$work/full$np" "$work/second$np" 200
  run "restart into its own directory np$np" mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 \
    -restart "$work/first$np/checkpoint.h5" -output_dir "$work/first$np" &&
    same_files "older checkpoint into its own directory, $np rank(s)" "$work/full$np" "$work/first$np" 200
done
# The rows rebuilt are really there: jumps before and after the checkpoint's step 200, the first at step 8.
awk -F, '/^[0-9]/ { if ($1 <= 200) b++; else a++ } END { exit !(b >= 5 && a >= 5) }' "$work/full1/jumps.csv" && ok ||
  fail "full1/jumps.csv should hold at least 5 jumps before step 200 and 5 after"
grep -q '^8,0.04,' "$work/full1/jumps.csv" && ! grep -q '^[1-7],' "$work/full1/jumps.csv" && ok ||
  fail "the first jump of full1/jumps.csv should be at step 8"
# Checkpoints at step 6 (no jump yet; the file holds step 8's row, written after it) and at step 8 (a
# jump into the checkpoint's own step), 1 rank.
for at in 0.03 0.04; do
  run "first part to $at s" "$rcfd" run "${common[@]}" -t_end 0.05 -checkpoint_every $at \
    -output_dir "$work/at$at" && run "older at $at s" older "$work/at$at/checkpoint.h5" &&
    run "restart at $at s" "$rcfd" run "${common[@]}" -t_end 2 -restart "$work/at$at/checkpoint.h5" \
      -output_dir "$work/at$at" && same_files "older checkpoint at $at s" "$work/full1" "$work/at$at" $(awk -v t=$at 'BEGIN { print int(t / 0.005 + 0.5) }')
done

# Refusals: each broken copy of a checkpoint (today's) names the file and what is missing.
"$rcfd" run "${common[@]}" -t_end 0.2 -checkpoint_every 0.1 -output_dir "$work/s"
broken=$work/broken.h5
refused() { # refused "expected text" h5_edit-arguments...: a restart from the edited copy fails so
  local expected=$1
  shift
  cp "$work/s/checkpoint.h5" "$broken" && "$edit" "$broken" "$@" &&
    expect_error "$expected" run "${common[@]}" -t_end 0.4 -restart "$broken" -output_dir "$work/refused"
}
refused "HDF5 file '$broken' has no dataset '/masses'" delete /masses
refused "-restart '$broken' holds 799 masses in /masses, expected 400 cells x 2 fractions" keep /masses 799
refused "HDF5 file '$broken' has no dataset '/path_state'" delete /path_state
refused "HDF5 file '$broken' has no dataset '/ledger_reference'" delete /ledger_reference
refused "HDF5 file '$broken' has no attribute 'step' on '/'" delete / step
refused "HDF5 file '$broken' has no attribute 'path_txt_bytes' on '/'" delete / path_txt_bytes
refused "-restart '$broken' holds no record of the physics entry 'solid_density' (an attribute of /physics)" \
  delete /physics solid_density
refused "-restart '$broken' holds no state of the monitor cog.csv" delete /monitors/cog.csv
# At 2 ranks: one sentence, not one per rank, and no PETSc traceback.
cp "$work/s/checkpoint.h5" "$broken" && "$edit" "$broken" delete /masses
out=$(mpiexec -n 2 "$rcfd" run "${common[@]}" -t_end 0.4 -restart "$broken" -output_dir "$work/refused" 2>&1)
[ $? -ne 0 ] && [ "$(grep -c "error: HDF5 file '$broken' has no dataset '/masses'" <<<"$out")" -eq 1 ] &&
  ! grep -q "PETSC ERROR" <<<"$out" && ok || fail "2 ranks, no /masses: $out"
# Without /operators, an operator that keeps state (growth's ledger) cannot continue.
growth=(-pipeline shift,drift,carry,growth -zones spray -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -growth_rate 5)
"$rcfd" run "${common[@]}" "${growth[@]}" -t_end 0.1 -checkpoint_every 0.05 -output_dir "$work/g"
"$edit" "$work/g/checkpoint.h5" delete /operators
expect_error "-restart '$work/g/checkpoint.h5' holds no state of the operator growth" run "${common[@]}" \
  "${growth[@]}" -t_end 0.2 -restart "$work/g/checkpoint.h5" -output_dir "$work/refused"
[ ! -e "$work/refused/cog.csv" ] && ok || fail "a refused restart wrote $work/refused/cog.csv"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
