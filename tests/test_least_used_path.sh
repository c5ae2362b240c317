#!/usr/bin/env bash
# The least-used jump rule of the stitching paths (-path_least_used, issue 15)
# on the small database: the same path on 1 and 2 ranks; a run restarted from
# its checkpoint writes the same path and time series, byte for byte; over a
# 60 s path every frame but frame 0 (entered only at the start) is used within
# a factor 2 of the mean use, which the uniform draw among the same candidates
# is far from.
# usage: test_least_used_path.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
K=$("$rcfd" info "$data/small.h5" | awk '$1 == "frames:" { print $2 }')
common=(-db "$data/small.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 4
  -path_candidates 16 -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436)
# unevenness PATH_TXT: max(largest / mean, mean / smallest) of the steps spent in frames 1..K-1.
unevenness() {
  awk -v K="$K" '!/^#/ { u[$1]++ } END {
    n = 0; for (k = 1; k < K; k++) n += u[k]; mean = n / (K - 1); lo = 1e300; hi = 0
    for (k = 1; k < K; k++) { v = u[k] + 0; if (v < lo) lo = v; if (v > hi) hi = v }
    f = hi / mean; if (lo == 0) f = 1e300; else if (mean / lo > f) f = mean / lo
    printf "%.3g\n", f }' "$1"  # 1e+300: a frame never used
}
for np in 1 2; do
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_least_used -t_end 60 -output_dir "$work/full$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_least_used -t_end 30 -checkpoint_every 20 \
    -output_dir "$work/first$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_least_used -t_end 60 \
    -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np"
  for f in path.txt cog.csv; do
    cmp -s "$work/full$np/$f" "$work/second$np/$f" && ok ||
      fail "restart at 20 s, $np rank(s): $f differs from the uninterrupted run's"
  done
  grep -q "leastUsed" "$work/full$np/path.txt" && ok || fail "path.txt does not name the rule: $(head -1 "$work/full$np/path.txt")"
done
cmp -s "$work/full1/path.txt" "$work/full2/path.txt" && ok || fail "the path differs between 1 and 2 ranks"
mpiexec -n 1 "$rcfd" run "${common[@]}" -t_end 60 -output_dir "$work/drawn"
fair=$(unevenness "$work/full1/path.txt") drawn=$(unevenness "$work/drawn/path.txt")
echo "60 s random path on $K frames, 16 candidates: frames 1..K-1 used within a factor $fair of uniform" \
  "with -path_least_used, $drawn with the uniform draw"
awk -v f="$fair" 'BEGIN { exit !(f <= 2) }' && ok || fail "least used: a factor $fair from uniform (more than 2)"
awk -v f="$drawn" 'BEGIN { exit !(f > 4) }' && ok ||
  fail "the uniform draw is already within a factor $drawn of uniform: the test no longer tells the rules apart"
# The rule is part of the path's configuration: a restart without it is refused.
if mpiexec -n 1 "$rcfd" run "${common[@]}" -t_end 60 -restart "$work/first1/checkpoint.h5" \
  -output_dir "$work/other" >"$work/other.txt" 2>&1; then
  fail "a restart without -path_least_used continued a least-used path"
else ok; fi
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
