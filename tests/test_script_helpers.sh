#!/usr/bin/env bash
# The shell tests' own helpers: same() compares numbers within a tolerance and words as
# they are, and fails on NaN and infinity.  Under
# Debian's mawk "nan" - 0.5 is a NaN that no comparison catches, so a NaN written
# where a number was expected passed every same() before; now it fails unless
# asked for with --nan, and then only against "nan".
# usage: test_script_helpers.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

passes() { # passes same-args...: same() counts one pass and no failure
  local out
  out=$(failures=0 passed=0; same "$@" >/dev/null; echo "$passed $failures")
  [ "$out" = "1 0" ] && ok || fail "same $*: expected a pass, got passed/failed $out"
}
fails() { # fails same-args...: same() counts one failure
  local out
  out=$(failures=0 passed=0; same "$@" >/dev/null; echo "$passed $failures")
  [ "$out" = "0 1" ] && ok || fail "same $*: expected a failure, got passed/failed $out"
}

for awk_name in awk mawk gawk; do
  command -v $awk_name >/dev/null || continue
  awk() { command $awk_name "$@"; }
  passes "equal" "1 2.5 -3e-4" "1 2.5 -3e-4"
  passes "within 1e-12 of 2" "1 2.000000000001" "1 2"
  passes "blanks and lines around" "  0.5
-1.25e+3 " "0.5 -1.25e3"
  passes "tolerance" "1.01" "1" 0.02
  fails "beyond the tolerance" "1 2.1" "1 2"
  fails "count" "1 2" "1 2 3"
  fails "nan against a number" "nan" "0.5"
  fails "a number against nan" "0.5" "nan"
  fails "NaN in a row" "0.1 NaN 0.3" "0.1 0.2 0.3"
  fails "nan against nan without --nan" "nan" "nan"
  fails "inf" "inf" "inf"
  fails "a word against a number" "abc" "0"
  passes "the same words" "time_s,delta_z_m run" "time_s,delta_z_m run"
  fails "other words" "run ens" "run run"
  fails "a number glued to a word" "1,,2" "1 0 2"
  fails "-inf" "-inf" "-inf"
  passes --nan "nan where nan is expected" "0.1 nan" "0.1 nan"
  fails --nan "nan against a number, with --nan" "nan 0.5" "0.5 0.5"
  fails --nan "a number against nan, with --nan" "0.5" "nan"
  unset -f awk
done

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
