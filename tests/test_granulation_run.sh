#!/usr/bin/env bash
# The granulation chamber in whole runs on the small synthetic database
# (growth, feed and discharge together, stitched path with jumps):
# - a run restarted from a checkpoint writes the same product.csv,
#   mass_account.csv and cog.csv, bit for bit, as one uninterrupted run (1 and 2 ranks);
# - 1 and 2 ranks give the same files within round-off;
# - the per-class balance closes in every row of mass_account.csv;
# - a case without the granulation operators writes none of their files;
# - a zone that is not defined, or holds no solid in any frame, is refused with one sentence.
# usage: test_granulation_run.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rcfd=$1 compare=$2 data=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
db=$data/small.h5
chamber=(-db "$db" -quiet -fields 0 -plot 0 -fractions_diameters 1.459e-3,2.0e-3,2.8e-3,4.075e-3
  -fractions_mass_shares 0.25,0.25,0.25,0.25 -pipeline shift,drift,carry,growth,feed,discharge
  -zones spray,feed,discharge -zone_spray_box 0.06,0.14,0,0.05,0.15,0.25 -zone_feed_box 0,0.04,0,0.05,0,0.07
  -zone_discharge_box 0.16,0.2,0,0.05,0,0.07 -growth_rate 5 -feed_rate 0.5 -discharge_rate 0.5
  -feed_mass_shares 0.7,0.1,0.1,0.1 -discharge_sample_interval 0.05 -monitor_every 5
  -path_type random -path_seed 5)
files="product mass_account cog"

for np in 1 2; do
  run "full run np$np" mpiexec -n $np "$rcfd" run "${chamber[@]}" -t_end 0.8 -output_dir "$work/full$np" &&
    run "first half np$np" mpiexec -n $np "$rcfd" run "${chamber[@]}" -t_end 0.4 -checkpoint_every 0.4 \
      -output_dir "$work/first$np" &&
    run "restart np$np" mpiexec -n $np "$rcfd" run "${chamber[@]}" -t_end 0.8 \
      -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np" || continue
  for f in $files; do
    if cmp -s "$work/full$np/$f.csv" "$work/second$np/$f.csv"; then ok; else fail "np$np: restarted $f.csv differs"; fi
  done
  # The operators really acted: mass was discharged and moved up.
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) if ($i ~ /^discharge_/) d[i] = 1 }
           END { for (i in d) s -= $i; exit !(s > 0.3) }' "$work/full$np/mass_account.csv" && ok ||
    fail "np$np: nothing discharged: $(tail -1 "$work/full$np/mass_account.csv")"
done
for f in $files; do
  if "$compare" "$work/full1/$f.csv" "$work/full2/$f.csv" 1e-10 1e-14 >/dev/null; then ok; else
    fail "1 and 2 ranks differ in $f.csv: $("$compare" "$work/full1/$f.csv" "$work/full2/$f.csv" 1e-10 1e-14 2>&1)"
  fi
done

# Every row: holdup_i - holdup_i(0) - growth_i - feed_i - discharge_i = 0 to the file's 10 digits.
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { split($i, p, "_"); kind[i] = p[1]; cls[i] = $i; sub(/^[a-z]+_/, "", cls[i]) } next }
  NR == 2 { for (i = 1; i <= NF; ++i) if (kind[i] == "holdup") h0[cls[i]] = $i }
  { for (c in h0) s[c] = 0; for (i = 1; i <= NF; ++i) {
      if (kind[i] == "holdup") s[cls[i]] += $i - h0[cls[i]]
      else if (kind[i] == "growth" || kind[i] == "feed" || kind[i] == "discharge") s[cls[i]] -= $i }
    for (c in s) { d = s[c] < 0 ? -s[c] : s[c]; if (d > 2e-9) bad = 1 } }
  END { exit bad }' "$work/full2/mass_account.csv" && ok || fail "mass_account.csv does not close per class"

# A case without the granulation operators pays nothing and writes none of their files.
run "plain" "$rcfd" run -db "$db" -quiet -fields 0 -plot 0 -t_end 0.05 -output_dir "$work/plain"
for f in product mass_account steady_state; do
  [ ! -e "$work/plain/$f.csv" ] && ok || fail "a run without granulation wrote $f.csv"
done

short=("${chamber[@]}" -t_end 0.05 -output_dir "$work/bad")
expect_error "-discharge_zone outlet names no zone of the case (-zones spray,feed,discharge)" run "${short[@]}" \
  -discharge_zone outlet
expect_error "Zone 'feed' of the feed operator (feed: box 0,0.2,0,0.05,0.6,0.7, 60 cells, 0.00105 m^3) holds no solid in any of the database's 60 frames" \
  run "${short[@]}" -zone_feed_box 0,0.2,0,0.05,0.6,0.7
expect_error "-feed_mass_shares needs 4 shares >= 0 (one per fraction) that sum to 1; got 2 summing to 1" run "${short[@]}" \
  -feed_mass_shares 0.5,0.5
expect_error "-growth_mass coating is not known" run "${short[@]}" -growth_mass coating

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
