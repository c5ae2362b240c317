#!/usr/bin/env bash
# Stitching that follows the run's clock (-path_clock_window, issue 28) on the
# small database, run past the database's end: every jump of step n lands
# within W frames of min(n, K - 1) and at least the band away from where it
# left; past the end the path stays in the last frames; mass per fraction is
# conserved to 1e-12 and no cell goes negative; 1 rank writes the same path
# as 2 and the same series to round-off; a restart across jumps is byte-identical; a restart
# without the window is refused.
# usage: test_clock_window_path.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 data=$3
source "$4/tests/script_helpers.sh"
K=$("$rcfd" info "$data/small.h5" | awk '$1 == "frames:" { print $2 }')
W=6
common=(-db "$data/small.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 3
  -path_min_length 2 -path_max_length 5 -path_candidates 16 -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436)
for np in 1 2; do
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_clock_window $W -t_end 8 -output_dir "$work/full$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_clock_window $W -t_end 4 -checkpoint_every 2.5 \
    -output_dir "$work/first$np"
  mpiexec -n $np "$rcfd" run "${common[@]}" -path_clock_window $W -t_end 8 \
    -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np"
  for f in path.txt cog.csv; do
    cmp -s "$work/full$np/$f" "$work/second$np/$f" && ok ||
      fail "restart at 2.5 s, $np rank(s): $f differs from the uninterrupted run's"
  done
done
cmp -s "$work/full1/path.txt" "$work/full2/path.txt" && ok || fail "the path differs between 1 and 2 ranks"
# The series to round-off, as test_rank_equivalence compares them (sums over ranks in another order).
"$2" "$work/full1/cog.csv" "$work/full2/cog.csv" 1e-12 1e-15 bulk_mismatch=1e-12 && ok ||
  fail "cog.csv differs between 1 and 2 ranks by more than round-off"
grep -q "clockWindow=$W" "$work/full1/path.txt" && ok || fail "path.txt does not name the window: $(head -1 "$work/full1/path.txt")"
# Every jump within the window of the clock and outside the band (default max(1, W/6) = 1);
# past the end (step >= K) every frame within the last W + 1.
report=$(awk -v K="$K" -v W="$W" '/^#/ { next } {
    f = $1 + 0; c = n < K - 1 ? n : K - 1
    if (n > 0 && f != prev + 1) { jumps++; d = f - c; if (d < 0) d = -d; if (d > W || f - 1 == prev) bad++ }
    if (n >= K && f < K - 1 - W) late++
    prev = f; n++ }
  END { printf "%d %d %d %d", n, jumps, bad, late }' "$work/full1/path.txt")
read -r steps jumps bad late <<<"$report"
echo "$steps steps on $K frames, $jumps jumps, clock window $W: $bad outside the window, $late early frames past the end"
[ "$jumps" -ge 10 ] && [ "$steps" -gt "$K" ] && ok || fail "too few jumps ($jumps) or steps ($steps) to tell"
[ "$bad" -eq 0 ] && [ "$late" -eq 0 ] && ok || fail "$bad jumps outside the clock window, $late frames before the last W past the end"
# Mass per fraction conserved, no negative cell (cog.csv's mass and min_cell_mass columns).
awk -F, '/^#/ { next } $1 == "time_s" { for (c = 1; c <= NF; ++c) col[$c] = c; next } {
    for (name in col) if (name ~ /^mass_/) { v = $col[name]; if (!(name in m0)) m0[name] = v
      r = (v - m0[name]) / m0[name]; if (r < 0) r = -r; if (r > worst) worst = r }
    if ($col["min_cell_mass_kg"] < 0) neg++ }
  END { printf "largest relative change of a fraction mass %.3g, %d rows with a negative cell\n", worst, neg
        exit !(worst <= 1e-12 && neg == 0) }' "$work/full1/cog.csv" && ok || fail "mass not conserved or a negative cell"
# The window is part of the path's configuration: a restart without it is refused.
if mpiexec -n 1 "$rcfd" run "${common[@]}" -t_end 8 -restart "$work/first1/checkpoint.h5" \
  -output_dir "$work/other" >"$work/other.txt" 2>&1; then
  fail "a restart without -path_clock_window continued a clock-following path"
else ok; fi
if mpiexec -n 1 "$rcfd" run "${common[@]}" -path_clock_window 3 -path_band 4 -t_end 1 \
  -output_dir "$work/bad" >"$work/bad.txt" 2>&1; then
  fail "a band wider than the clock window was accepted"
else grep -q "clock" "$work/bad.txt" && ok || fail "the refusal does not name the clock window: $(cat "$work/bad.txt")"; fi
# -run_view reports how much more frames far apart differ than nearby ones (a transient's sign).
"$rcfd" run "${common[@]}" -t_end 0.1 -run_view -output_dir "$work/view" >"$work/view.txt" 2>&1
grep -Eq "frames far apart differ [0-9.]+ times as much as frames nearby" "$work/view.txt" && ok ||
  fail "-run_view does not report the recurrence trend: $(grep -i recurrence "$work/view.txt")"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
