#!/usr/bin/env bash
# rcfd coarsen on a small synthetic database: the coarse databases (space,
# time, both) load and stay mass-consistent to round-off, factor 1 gives the
# same shifts, a run on the coarse database conserves its fractions, the output
# keeps the input's weight precision unless -weights asks for another, and bad
# factors and precisions are refused naming the option.
# usage: test_coarsen_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
dbcompare=$(dirname "$2")/db_compare
h5print=$(dirname "$2")/h5_print
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
conserves() { # conserves DB NAME: a run on DB keeps both fractions' masses to 1e-12
  run "run on $2" "$rcfd" run -db "$1" -t_end 0.3 -quiet -plot false -fields false -output_dir "$work/out-$2" \
    -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 || return
  awk -F, 'NR == 2 { a = $6; b = $7 } END { d1 = ($6 - a) / a; d2 = ($7 - b) / b
    exit !(d1 < 1e-12 && d1 > -1e-12 && d2 < 1e-12 && d2 > -1e-12) }' "$work/out-$2/cog.csv" && ok ||
    fail "masses changed on $2"
}
conserves "$work/c.h5" coarse
# Precision: the output keeps the input's (the bits of a quantised input, full precision of a full
# one) unless -weights asks for B bits or full.
precision() { "$rcfd" info "$1" | grep -o "weights quantised to 2^-[0-9]*\|full-precision weights"; }
column_error() { "$rcfd" info "$1" | sed -n 's/.*largest |column sum - 1| before rescaling: //p'; }
hash() { "$h5print" "$1" / content_hash string; }
expect_precision() { # expect_precision FILE "what rcfd info says" LABEL
  local got
  got=$(precision "$1")
  [ "$got" = "$2" ] && ok || fail "$3: expected '$2', rcfd info says '$got'"
}
expect_precision "$work/c.h5" "full-precision weights" "a full-precision input coarsened"
"$rcfd" coarsen "$db" -factor 1,1,1 -weights 16 -o "$work/q16.h5" -quiet
expect_precision "$work/q16.h5" "weights quantised to 2^-16" "-weights 16"
# Factor 1 on a quantised input re-quantises weights that are already multiples of 2^-16 with
# columns summing to 1: exact, so the same frames (the same identity) and the same bits.
"$rcfd" coarsen "$work/q16.h5" -factor 1,1,1 -o "$work/q16-same.h5" -quiet
expect_precision "$work/q16-same.h5" "weights quantised to 2^-16" "factor 1 on a quantised input"
[ -n "$(hash "$work/q16.h5")" ] && [ "$(hash "$work/q16-same.h5")" = "$(hash "$work/q16.h5")" ] && ok ||
  fail "factor 1 on a quantised input changed the frames: $(hash "$work/q16.h5") -> $(hash "$work/q16-same.h5")"
# Coarsened in space and in time, a quantised input's frames are quantised again: every column
# sums to exactly 1 and a run conserves both fractions.
for args in "-factor 2,1,2" "-time_factor 2"; do
  # shellcheck disable=SC2086
  "$rcfd" coarsen "$work/q16.h5" $args -o "$work/qc.h5" -quiet
  expect_precision "$work/qc.h5" "weights quantised to 2^-16" "coarsen $args of a quantised input"
  r=$(column_error "$work/qc.h5")
  awk -v r="$r" 'BEGIN { exit !(r != "" && r < 1e-12) }' && ok || fail "coarsen $args of q16: column sums off by '$r'"
done
conserves "$work/qc.h5" coarse-q16
# Asked for: full precision (full, or 0 as before), or other bits.
for full in full 0; do
  "$rcfd" coarsen "$work/q16.h5" -factor 1,1,1 -weights $full -o "$work/q16-full.h5" -quiet
  expect_precision "$work/q16-full.h5" "full-precision weights" "-weights $full on a quantised input"
done
[ "$(hash "$work/q16-full.h5")" = "$(hash "$work/q16.h5")" ] && ok || fail "-weights full changed the frames"
"$rcfd" coarsen "$work/q16.h5" -factor 2,1,2 -weights 12 -o "$work/q12.h5" -quiet
expect_precision "$work/q12.h5" "weights quantised to 2^-12" "-weights 12 on a 16-bit input"
# An initial composition from rcfd build -init_out, coarsened with its database: the one coarse
# cell holds the two particles' masses.
write_two_particle_dumps
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
for bad in half 17 -1; do
  expect_error "-weights '$bad': expected the bits of the quantised weights, 1 to 16, full, or input" \
    coarsen "$db" -weights "$bad" -o "$work/x.h5"
done
[ ! -e "$work/x.h5" ] && ok || fail "a refused coarsening left a file"
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
