#!/usr/bin/env bash
# Every registered test carries a CTest label (docs/testing.md: `ctest -L runs`, ...), so
# that a component's tests are all run by its label; only the fixtures that make the
# test data (make_*) have none.
# usage: test_labels.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR   (DATA_DIR is BUILD/test-data)
set -u
rcfd=$1 build=$(dirname "$3")
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

listed=$(cd "$build" && ctest -N) || { echo "FAIL: ctest -N in $build"; exit 1; }
total=$(grep -cE '^ *Test +#' <<<"$listed")
[ "$total" -gt 50 ] && ok || fail "ctest -N lists $total tests in $build; expected the suite"
unlabelled=$(cd "$build" && ctest -N -LE . | sed -nE 's/^ *Test +#[0-9]+: *//p' | grep -v '^make_')
if [ -n "$unlabelled" ]; then
  fail "tests without a label (add them to an rcfd_label(...) line of tests/CMakeLists.txt): $(echo $unlabelled)"
else
  ok
fi
echo "$passed passed, $failures failed ($total tests)"
[ $failures -eq 0 ]
