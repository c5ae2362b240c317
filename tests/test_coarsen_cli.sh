#!/usr/bin/env bash
# rcfd coarsen on a small synthetic database: the coarse databases (space,
# time, both) load and stay mass-consistent to round-off, factor 1 gives the
# same shifts, a run on the coarse database conserves its fractions, and bad
# factors are refused naming the axis.
# usage: test_coarsen_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
dbcompare=$(dirname "$2")/db_compare
db=$data/small.h5

consistency() { # the largest mass mismatch rcfd info prints
  "$rcfd" info "$1" | sed -n 's/.*mass consistency.*largest \([^ ]*\) over.*/\1/p'
}
for args in "-factor 2,1,2" "-time_factor 2" "-factor 2,2,2 -time_factor 2"; do
  # shellcheck disable=SC2086
  if "$rcfd" coarsen "$db" $args -o "$work/c.h5" -quiet; then
    r=$(consistency "$work/c.h5")
    awk -v r="$r" 'BEGIN { exit !(r != "" && r < 1e-14) }' && ok || fail "coarsen $args: mass consistency '$r'"
  else
    fail "coarsen $args failed"
  fi
done
"$rcfd" coarsen "$db" -factor 2,1,2 -o "$work/c.h5" -quiet
"$rcfd" info "$work/c.h5" | grep -q "box 5 x 2 x 10 cells = 100" && ok || fail "coarse mesh"
# Factor 1: the same shifts (the db_compare helper reads both files).
"$rcfd" coarsen "$db" -factor 1,1,1 -o "$work/same.h5" -quiet
if [ -x "$dbcompare" ]; then
  "$dbcompare" "$db" "$work/same.h5" | awk '$1 == "max" { exit !($2 == 0 && $4 == 0 && $6 == 0) }' && ok ||
    fail "factor 1 changed the shifts: $("$dbcompare" "$db" "$work/same.h5" | tail -1)"
fi
# rcfd info names the file's format version (coarsen writes the current one, 3) and its size.
"$rcfd" info "$work/same.h5" | grep -q "file: format version 3, [0-9.]* MB$" && ok || fail "rcfd info: no format version 3 line"
# A run on the coarse database conserves every fraction.
run "run on the coarse database" "$rcfd" run -db "$work/c.h5" -t_end 0.3 -quiet -plot false -fields false \
  -output_dir "$work/out" -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436
awk -F, 'NR == 2 { a = $6; b = $7 } END { d1 = ($6 - a) / a; d2 = ($7 - b) / b
  exit !(d1 < 1e-12 && d1 > -1e-12 && d2 < 1e-12 && d2 > -1e-12) }' "$work/out/cog.csv" && ok ||
  fail "masses changed on the coarse database"
# An initial composition from rcfd build -init_out, coarsened with its database: the one coarse
# cell holds the two particles' masses.
write_two_particle_dumps
h5print=$(dirname "$2")/h5_print
if "$rcfd" build "${common[@]}" -o "$work/p.h5" -init_out "$work/p-init.h5" -quiet &&
  "$rcfd" coarsen "$work/p.h5" -factor 2,1,2 -o "$work/pc.h5" -init_file "$work/p-init.h5" \
    -init_out "$work/pc-init.h5" -quiet; then
  fine=$("$h5print" "$work/p-init.h5" /masses | awk '{ s += $1 } END { printf "%.17g", s }')
  coarse=$("$h5print" "$work/pc-init.h5" /masses | tr '\n' ' ')
  same "coarse initial masses" "$(echo $coarse | awk '{ printf "%.17g", $1 + $2 }')" "$fine" 1e-15
  [ "$(echo $coarse | wc -w)" -eq 2 ] && ok || fail "coarse /masses: $coarse"
else
  fail "coarsening a built database and its initial composition"
fi
expect_error "the coarsening factor along x is 3" coarsen "$db" -factor 3,1,1 -o "$work/x.h5"
expect_error "-time_factor 3: expected 1 or 2" coarsen "$db" -time_factor 3 -o "$work/x.h5"
expect_error "rcfd coarsen needs -o FILE" coarsen "$db" -factor 2,1,2
[ ! -e "$work/x.h5" ] && ok || fail "a refused coarsening left a file"
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
