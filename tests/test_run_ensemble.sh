#!/usr/bin/env bash
# rcfd run -ensemble 3 on a stitched path: member_0..2 hold their own runs
# with path seeds s, s+1, s+2 (different paths), and ensemble.csv holds,
# per row and column, the mean of the members' values and their sample
# standard deviation.
# usage: test_run_ensemble.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
out=$work/ensemble

run "ensemble" mpiexec -n 2 "$rcfd" run -db "$data/small.h5" -path_type random -path_seed 5 -ensemble 3 \
  -quiet -fields 1 -plot 0 -monitor_digits 17 -output_dir "$out" || { echo "$failures failed"; exit 1; }
for k in 0 1 2; do
  [ -s "$out/member_$k/cog.csv" ] || fail "no $out/member_$k/cog.csv"
  grep -q "seed=$((5 + k)) " "$out/member_$k/path.txt" || fail "member $k: $(head -1 "$out/member_$k/path.txt")"
  [ ! -e "$out/member_$k/fields.xmf" ] || fail "member $k wrote fields"
done
cmp -s "$out/member_0/path.txt" "$out/member_1/path.txt" && fail "members 0 and 1 took the same path"
[ ! -e "$out/cog.csv" ] || fail "the ensemble wrote a cog.csv of its own"

# Columns of the members: time_s, then values; ensemble.csv: time_s, then
# <column>_mean,<column>_std for each.  Compare every number.
check=$(awk -F, '
  FNR == 1 { file++ }
  file <= 3 && FNR > 1 { for (c = 1; c <= NF; ++c) { v[file, FNR - 1, c] = $c } rows = FNR - 1; cols = NF; next }
  file == 4 && /^#/ { next }
  file == 4 && !header { header = 1; next }
  file == 4 {
    r++
    d = $1 - v[1, r, 1]; if (d < 0) d = -d
    if (d > 1e-12) { print "time of row " r ": " $1 " vs " v[1, r, 1]; bad++ }
    for (c = 2; c <= cols; ++c) {
      mean = (v[1, r, c] + v[2, r, c] + v[3, r, c]) / 3
      ss = 0; for (m = 1; m <= 3; ++m) ss += (v[m, r, c] - mean) ^ 2
      sd = sqrt(ss / 2)
      got = $(2 * c - 2); gotsd = $(2 * c - 1)
      scale = (mean < 0 ? -mean : mean); if (scale < 1e-300) scale = 1e-300
      d = got - mean; if (d < 0) d = -d
      if (d > 1e-9 * scale + 1e-15) { print "row " r " column " c ": mean " got " vs " mean; bad++ }
      d = gotsd - sd; if (d < 0) d = -d
      if (d > 1e-8 * (sd > scale ? sd : scale) + 1e-15) { print "row " r " column " c ": std " gotsd " vs " sd; bad++ }
      if (c == 5 && sd > 0) spread++ # delta_z_m differs between members somewhere
    }
  }
  END { if (r != rows || r == 0) { print "ensemble.csv has " r " rows, the members " rows; bad++ }
        if (!spread) { print "the members never differ in delta_z"; bad++ }
        print bad + 0 }' "$out"/member_{0,1,2}/cog.csv "$out/ensemble.csv")
[ "$(tail -1 <<<"$check")" = 0 ] && ok || fail "ensemble.csv: $check"

# A deterministic path cannot make an ensemble.
expect_error "needs a stochastic -path_type" run -db "$data/small.h5" -ensemble 2 -quiet -fields 0 -plot 0 \
  -output_dir "$work/replay"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
