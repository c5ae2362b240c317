#!/usr/bin/env bash
# No public header throws (docs/extending.md, "Errors are PetscErrorCodes"): no `throw` in the code
# of include/rcfd/*.hpp (comments may say that nothing throws), so that user code needs no
# try/catch around rcfd and every failure is a PetscErrorCode with its sentence.
# usage: test_public_headers_throw_nothing.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
source_dir=$4
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
cd "$source_dir" || exit 1
headers=$(ls include/rcfd/*.hpp | wc -l)
[ "$headers" -ge 20 ] && ok || fail "found only $headers public headers in include/rcfd"
# The code of each line: what comes before a // comment (block comments are not used there).
thrown=$(awk '{ code = $0; sub(/\/\/.*/, "", code) } code ~ /(^|[^A-Za-z_])throw([^A-Za-z_]|$)/ {
  print FILENAME ":" FNR ": " $0 }' include/rcfd/*.hpp)
[ -z "$thrown" ] && ok || fail "a public header throws: $thrown"
grep -q "No function of a public header throws" docs/extending.md && ok ||
  fail "docs/extending.md no longer says that no function of a public header throws"
echo "$passed passed, $failures failed ($headers headers)"
[ $failures -eq 0 ]
