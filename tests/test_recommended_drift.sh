#!/usr/bin/env bash
# cases/recommended-drift.yaml, the drift options the docs recommend for every bed (issue 21):
# - added to a run with a second options file it is accepted and sets what docs/validation.md
#   says (drag law, c, excess gas, the cell's own d32, the leaving share to the power n), and the
#   README and docs/validation.md quote the same c and n as the file;
# - the speeds it prints are c (u_sup - u_mf) (d32/d_i - 1) with the u_mf and d32 it prints (to
#   1e-3: it prints four digits);
# - on the small synthetic bed the small class rises above the large one, mass is kept to 1e-12
#   and no cell goes negative, and 2 ranks give the same cog.csv as 1 (to round-off: the bulk
#   mismatch column is a sum of round-off, 1e-15, that the partition changes).
# usage: test_recommended_drift.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 compare=$2 data=$3 source_dir=$4
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
yaml=$source_dir/cases/recommended-drift.yaml

value() { awk -v key="$1:" '$1 == key { print $2 }' "$yaml"; }
kd=$(value drift_kd) n=$(value drift_agitation_exponent)
[ "$(value drift_size_law)" = drag ] && [ "$(value drift_excess_gas)" = true ] &&
  [ "$(value drift_local_d32)" = true ] && [ "$(value drift_agitation)" = leaving ] && [ -n "$kd" ] && [ -n "$n" ] &&
  ok || fail "$yaml does not set the law docs/validation.md recommends: $(grep -v '^#' "$yaml" | tr '\n' ' ')"
grep -q -- "-drift_kd $kd -drift_excess_gas" "$source_dir/docs/validation.md" &&
  grep -q -- "-drift_agitation_exponent $n\`" "$source_dir/docs/validation.md" &&
  grep -q "(a/a_bar)^$n\$" "$source_dir/README.md" && ok ||
  fail "docs/validation.md or README.md quote another c or n than $yaml (c $kd, n $n)"

run_with() { # run_with NP DIR: the small bed, two classes, the recommended drift at u_sup 1.3 m/s
  mpiexec -n "$1" "$rcfd" run -db "$data/small.h5" -t_end 0.3 -fractions_diameters 1.459e-3,4.075e-3 \
    -fractions_mass_shares 0.564,0.436 -options_file "$yaml" -superficial_velocity 1.3 -drift_view \
    -output_dir "$2" -fields 0 -plot 0
}
for np in 1 2; do
  run_with $np "$work/np$np" >"$work/view$np" 2>&1 && ok || fail "recommended drift on $np rank(s): $(tail -3 "$work/view$np")"
done

# The printed speeds against c (u_sup - u_mf)(d32/d - 1) from the printed u_mf and d32.
awk -v kd="$kd" '
  /times the excess gas u_sup - u_mf/ { split($0, a, "="); split(a[3], b, " "); excess = b[1] }
  /^drift: model drag/ { for (i = 1; i <= NF; ++i) if ($i == "d32") d32 = $(i + 2) }
  /^  fraction [0-9]+ \(d = / { d[++n] = $5; u[n] = $(NF - 1) }
  END {
    if (n != 2 || excess <= 0 || d32 <= 0) { print "no drift view (" n " fractions)"; exit 1 }
    for (i = 1; i <= n; ++i) {
      want = kd * excess * (d32 / d[i] - 1)
      if (want - u[i] > 1e-3 * (want > 0 ? want : -want) || u[i] - want > 1e-3 * (want > 0 ? want : -want)) {
        printf "fraction %d: u_d %s, c (u_sup - u_mf)(d32/d - 1) = %.5g\n", i, u[i], want; exit 1 }
    }
  }' "$work/view1" >"$work/speeds" && ok || fail "drift speeds: $(cat "$work/speeds")"

# Segregation, mass and signs from cog.csv (columns by name).
awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) col[$c] = c; next }
  NR == 2 { m0 = $col["mass_d1.459mm_kg"]; m1 = $col["mass_d4.075mm_kg"] }
  { last_dz = $col["delta_z_m"]
    if ($col["min_cell_mass_kg"] < 0) { print "negative cell mass at t = " $1; exit 1 }
    e0 = $col["mass_d1.459mm_kg"] / m0 - 1; e1 = $col["mass_d4.075mm_kg"] / m1 - 1
    if (e0 > 1e-12 || e0 < -1e-12 || e1 > 1e-12 || e1 < -1e-12) { print "mass changed at t = " $1; exit 1 } }
  END { if (last_dz < 0.005) { print "small class only " last_dz " m above the large"; exit 1 } }' \
  "$work/np1/cog.csv" >"$work/cog_check" && ok || fail "$(cat "$work/cog_check")"
"$compare" "$work/np1/cog.csv" "$work/np2/cog.csv" 1e-12 1e-13 >"$work/ranks" 2>&1 && ok ||
  fail "1 and 2 ranks differ: $(tail -2 "$work/ranks")"

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
