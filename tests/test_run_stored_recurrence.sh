#!/usr/bin/env bash
# A recurrence matrix stored with `rcfd recurrence` is used by a stitched
# run, which says so and does not compute one; its path is the one a run
# that computes the matrix takes.  Also for the deprecated -recurrence_norm.
# usage: test_run_stored_recurrence.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
common=(-path_type markov -path_seed 3 -path_recurrence_norm absDiff -fields 0 -plot 0 -t_end 0.6
  -progress_interval 1e9)

for np in 1 2; do
  # Stored and computed on as many ranks (the sums' order sets the last bits).
  cp "$data/small.h5" "$work/stored.h5"
  run "rcfd recurrence" mpiexec -n $np "$rcfd" recurrence "$work/stored.h5" -recurrence_norm absDiff -quiet
  run "computed, $np ranks" mpiexec -n $np "$rcfd" run -db "$data/small.h5" "${common[@]}" \
    -output_dir "$work/computed$np"
  grep -q "Computed the absDiff recurrence matrix of 60 frames" "$work/out.txt" && ok ||
    fail "the run on a database without a stored matrix did not compute one: $(cat "$work/out.txt")"
  run "stored, $np ranks" mpiexec -n $np "$rcfd" run -db "$work/stored.h5" "${common[@]}" \
    -output_dir "$work/stored$np" -run_view "ascii:$work/view$np.txt"
  grep -q "Using the absDiff recurrence matrix stored in $work/stored.h5" "$work/out.txt" && ok ||
    fail "the run did not use the stored matrix: $(cat "$work/out.txt")"
  grep -q "Computed" "$work/out.txt" && fail "the run computed a matrix the database holds"
  grep -q "absDiff recurrence matrix, stored in the database" "$work/view$np.txt" && ok ||
    fail "-run_view: $(cat "$work/view$np.txt")"
  cmp -s "$work/computed$np/path.txt" "$work/stored$np/path.txt" && ok ||
    fail "the stored matrix gave another path than the computed one ($np ranks)"
  # The path jumped, so the matrix mattered.
  awk 'NR > 2 && $1 != prev + 1 { j++ } { prev = $1 } END { exit !(j >= 3) }' "$work/stored$np/path.txt" &&
    ok || fail "the markov path did not jump"
done
# The option's old name still works (with PETSc's deprecation warning).
run "old option name" mpiexec -n 2 "$rcfd" run -db "$work/stored.h5" "${common[@]/-path_recurrence_norm/-recurrence_norm}" \
  -output_dir "$work/old"
cmp -s "$work/old/path.txt" "$work/stored2/path.txt" && ok || fail "-recurrence_norm absDiff gave another path"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
