#!/usr/bin/env bash
# A stitched run restarted from its mid-run checkpoint gives the same
# numbers, bit for bit, as one uninterrupted run, at 1 and 2 ranks; a
# checkpoint from another case is refused.
# usage: test_restart.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rcfd=$1 data=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
common=(-db "$data/default.h5" -db_frames 0,99 -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random
  -path_seed 11 -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436)
passed=0
for np in 1 2; do
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -output_dir "$work/full$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 1 -checkpoint_every 1 -output_dir "$work/first$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 2 -restart "$work/first$np/checkpoint.h5" \
    -output_dir "$work/second$np"
  cmp "$work/full$np/cog.csv" "$work/second$np/cog.csv"
  cmp "$work/full$np/path.txt" "$work/second$np/path.txt"
  # The path actually jumped, so the test covers carrying across jumps.
  awk 'NR > 2 && $1 != prev + 1 { j++ } { prev = $1 } END { exit !(j >= 5) }' "$work/full$np/path.txt"
  passed=$((passed + 1))
done
# Restarting with another number of fractions is refused with a sentence.
if out=$("$rcfd" run -db "$data/default.h5" -quiet -fields 0 -plot 0 -t_end 2 \
  -fractions_diameters 1e-3,2e-3,3e-3 -fractions_mass_shares 0.3,0.3,0.4 \
  -db_frames 0,99 -restart "$work/first1/checkpoint.h5" -output_dir "$work/wrong" 2>&1); then
  echo "FAIL: a restart with 3 fractions from a 2-fraction checkpoint succeeded"
  exit 1
fi
grep -q "holds 56000 cells x 2 fractions, but this run has 56000 x 3" <<<"$out" ||
  { echo "FAIL: unexpected message: $out"; exit 1; }
passed=$((passed + 1))
echo "$passed passed, 0 failed"
