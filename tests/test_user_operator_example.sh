#!/usr/bin/env bash
# The library as an outside project sees it: configure docs/examples/user-operator against the
# INSTALLED package (find_package(rcfd), rcfd::rcfd), build it, run its user
# operator "decay" (-pipeline shift,decay -decay_rate k) on a small synthetic
# bed, and check that every fraction's mass in cog.csv is exactly exp(-k t)
# of its initial value -- a number only the user's option determines.
# The package is installed once, into PREFIX, by the fixture installed_package
# (tests/install_package.sh).
# usage: test_user_operator_example.sh RCFD BUILD_DIR SOURCE_DIR CMAKE CXX_COMPILER PREFIX
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rcfd=$1 build=$2 src=$3 cmake=$4 cxx=$5 prefix=$6
work=$build/test-data/user-operator
rm -rf "$work"
mkdir -p "$work"
source "$src/tests/script_helpers.sh"

# Configured against the installed package only: the source tree is not on
# any path the example sees.
build_example user-operator "$src" "$prefix" "$cmake" "$cxx"

"$prefix/bin/rcfd" synth -o "$work/bed.h5" -synth_cells 6,2,12 -synth_frames 20 -quiet
rate=0.5
run "decay at 2 ranks" mpiexec -n 2 "$work/user-operator/user_operator" -db "$work/bed.h5" -t_end 1 \
  -pipeline shift,decay -decay_rate $rate -monitor_digits 17 -fields 0 -plot 0 -quiet \
  -output_dir "$work/out" -decay_view
grep -q "decay: rate 0.5 1/s" "$work/out.txt" || fail "-decay_view did not print the operator"

# Every row t and every mass column: m(t) / m(0) = exp(-rate t).
csv=$work/out/cog.csv
ratios=$(awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c ~ /^mass_/) cols[++n] = c; next }
  NR == 2 { for (k = 1; k <= n; ++k) m0[k] = $cols[k] }
  { for (k = 1; k <= n; ++k) printf "%.17g\n", $cols[k] / m0[k] }' "$csv")
expected=$(awk -F, -v k=$rate 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c ~ /^mass_/) ++n; next }
  { for (i = 1; i <= n; ++i) printf "%.17g\n", exp(-k * $1) }' "$csv")
[ "$(grep -c . <<<"$ratios")" -ge 20 ] || fail "cog.csv holds too few samples: $(cat "$csv")"
same "mass / initial mass = exp(-$rate t)" "$ratios" "$expected" 1e-12
last=$(tail -n 1 <<<"$ratios")
same "mass left after 1 s" "$last" 0.60653065971263342 1e-12

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
