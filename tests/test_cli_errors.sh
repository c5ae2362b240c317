#!/usr/bin/env bash
# Bad input gets one sentence naming the file or option and what was
# expected: no traceback, no crash, a non-zero exit code.
# usage: test_cli_errors.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

db=$data/default.h5
expect_error "unknown command 'rnu'" rnu
expect_error "No database given: pass -db FILE" run
expect_error "cannot open file '$work/none.h5': it does not exist" run -db "$work/none.h5"
echo "plain text" >"$work/text.h5"
expect_error "file '$work/text.h5' is not an HDF5 file" run -db "$work/text.h5"
expect_error "Unknown option -t_edn" run -db "$db" -t_edn 1
expect_error "-fractions_diameters: diameter 2 is -0.002" run -db "$db" \
  -fractions_diameters 1e-3,-2e-3 -fractions_mass_shares 0.5,0.5
expect_error "-fractions_mass_shares sum to 0.9" run -db "$db" \
  -fractions_diameters 1e-3,2e-3 -fractions_mass_shares 0.5,0.4
expect_error "-fractions_mass_shares has 1 values but -fractions_diameters has 2" run -db "$db" \
  -fractions_diameters 1e-3,2e-3 -fractions_mass_shares 1
many_d=$(seq -s, 1 65 | sed 's/[0-9]\+/1e-3/g') many_w=$(seq -s, 1 65 | sed 's/[0-9]\+/0.015384615384615385/g')
expect_error "-fractions_diameters has 65 diameters; rcfd handles at most 64 fractions" run -db "$db" \
  -fractions_diameters "$many_d" -fractions_mass_shares "$many_w"
expect_error "-pipeline: unknown operator 'shfit'" run -db "$db" -pipeline shfit
expect_error "-init sideways is not known" run -db "$db" -init sideways
expect_error "-init file needs -init_file FILE" run -db "$db" -init file
expect_error "-db_frames 5:2 is outside" run -db "$db" -db_frames 5,2
expect_error "Unknown option -bogus" info "$db" -bogus
expect_error "cannot open file 'nope.h5'" info nope.h5

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
