#!/usr/bin/env bash
# Plugins as an outside project makes them: build docs/examples/plugin against the INSTALLED package
# (find_package(rcfd), rcfd::plugin), and load it into the installed program
# with -plugin (and $RCFD_PLUGINS).  Its operator "attrition", size law
# "linear" and monitor "fines" then work in `rcfd run` on
# cases/bubbling-bi-narrow at 1 and 2 ranks: every fraction's mass is
# accounted (mass_account.csv), the bed's total is kept to 1e-12, fines grow,
# 1 rank equals 2 ranks to 1e-12, and a run restarted from its checkpoint
# writes the same files byte for byte.  `rcfd -help` and `rcfd run -help` list what the
# plugin added; `rcfd calibrate` fits the plugin's law; a plugin built for another
# rcfd version, a missing file and a name clash are refused with one sentence.
# The package is installed once, into PREFIX, by the fixture installed_package.
# usage: test_plugin_example.sh RCFD BUILD_DIR SOURCE_DIR CMAKE CXX_COMPILER DATA_DIR PREFIX
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
build=$2 src=$3 cmake=$4 cxx=$5 data=$6 prefix=$7
work=$build/test-data/plugin
rm -rf "$work"
mkdir -p "$work"
source "$src/tests/script_helpers.sh"

rcfd=$prefix/bin/rcfd
[ -e "$prefix/include/rcfd/plugin.hpp" ] && ok || fail "cmake --install did not install rcfd/plugin.hpp"

# Built against the installed package only.
"$cmake" -S "$src/docs/examples/plugin" -B "$work/example" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
grep -q "$prefix/lib/cmake/rcfd" "$work/example/CMakeCache.txt" || fail "the plugin did not find the installed rcfd"
"$cmake" --build "$work/example" >"$work/example.log" 2>&1 || { cat "$work/example.log"; exit 1; }
plugin=$work/example/librcfd_attrition.so
[ -f "$plugin" ] && ok || fail "no $plugin"

# rcfd run -help lists the plugin's additions under their points.
"$rcfd" run -help -plugin "$plugin" >"$work/help.txt" 2>&1 || fail "rcfd run -help -plugin failed: $(tail -3 "$work/help.txt")"
for line in "  attrition: plugin: each fraction" "  linear: plugin: u = kd (d32 - d)/d32" "  fines: plugin: fines.csv" \
  "  stride: plugin: frames 0, s, 2s" \
  "  drift: fractional drift" "  replay: the recorded frames"; do
  grep -qF -- "$line" "$work/help.txt" && ok || fail "rcfd run -help -plugin lists no '$line'"
done

# So does the program's own help, with the plugin from the environment.
RCFD_PLUGINS=$plugin "$rcfd" -help >"$work/top-help.txt" 2>&1 || fail "rcfd -help with RCFD_PLUGINS failed"
for line in "usage: rcfd <command>" "operators (-pipeline):" "  attrition: plugin:" "size laws (-drift_size_law):" \
  "  linear: plugin:" "monitors (-monitors):" "  fines: plugin:"; do
  grep -qF -- "$line" "$work/top-help.txt" && ok || fail "rcfd -help (RCFD_PLUGINS) lists no '$line'"
done

case_run=(-options_file "$src/cases/bubbling-bi-narrow/case.yaml" -db "$data/default.h5" -quiet -fields 0 -plot 0
  -monitor_digits 17 -path_type random -path_seed 3 -pipeline shift,drift,attrition,carry -attrition_rate 0.2
  -drift_size_law linear -drift_kd 0.01 -monitors fines -fines_every 5)
for np in 1 2; do
  run "full run, $np rank(s)" mpiexec -n $np "$rcfd" run -plugin "$plugin" "${case_run[@]}" -t_end 1 \
    -output_dir "$work/full$np" -attrition_view ascii:"$work/view$np.txt"
  grep -q "attrition: rate 0.2 1/s" "$work/view$np.txt" && ok || fail "-attrition_view printed no rate"
  # Stopped at 0.75 s with its checkpoint at 0.5 s, restarted to 1 s (the plugin from the environment).
  run "first part, $np rank(s)" mpiexec -n $np "$rcfd" run -plugin "$plugin" "${case_run[@]}" -t_end 0.75 \
    -checkpoint_every 0.5 -output_dir "$work/first$np"
  RCFD_PLUGINS=$plugin run "restart, $np rank(s)" mpiexec -n $np -x RCFD_PLUGINS "$rcfd" run "${case_run[@]}" -t_end 1 \
    -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np"
  for f in cog.csv fines.csv mass_account.csv path.txt; do
    cmp -s "$work/full$np/$f" "$work/second$np/$f" && ok || fail "restart, $np rank(s): $f differs from the full run's"
  done
done
for f in cog.csv fines.csv; do
  same "1 rank = 2 ranks: $f" "$(tr , ' ' <"$work/full1/$f")" "$(tr , ' ' <"$work/full2/$f")" 1e-12
done
# The bed's total mass is kept; the finest fraction gains what attrition grinds.
totals=$(awk -F, 'NR == 1 { for (c = 1; c <= NF; ++c) if ($c ~ /^mass_/) cols[++n] = c; next }
  { s = 0; for (k = 1; k <= n; ++k) s += $cols[k]; printf "%.17g\n", s }' "$work/full2/cog.csv")
first=$(head -n 1 <<<"$totals")
same "total mass over the run" "$totals" "$(sed "s/.*/$first/" <<<"$totals")" 1e-12
awk -F, 'NR == 2 { a = $2 } END { exit !($2 > a * 1.01) }' "$work/full2/fines.csv" && ok ||
  fail "fines did not grow: $(sed -n '2p;$p' "$work/full2/fines.csv")"
[ "$(grep -c . "$work/full2/fines.csv")" -ge 40 ] && ok || fail "fines.csv holds too few rows (-fines_every 5)"

# The plugin's path rule: the run steps frames 0, 7, 14, ... (path.txt), its view printed by -path_view.
run "stride path" "$rcfd" run -plugin "$plugin" -db "$data/small.h5" -quiet -fields 0 -plot 0 -t_end 0.1 \
  -path_type stride -path_stride 7 -output_dir "$work/stride" -path_view ascii:"$work/path-view.txt" \
  -monitors fines -fines_view ascii:"$work/fines-view.txt"
same "frames of the stride path" "$(grep -v '^#' "$work/stride/path.txt" | head -n 10)" "0 7 14 21 28 35 42 49 56 3"
grep -q "stride: every 7 frames" "$work/path-view.txt" && ok || fail "-path_view printed no stride: $(cat "$work/path-view.txt")"
grep -q "monitor fines" "$work/fines-view.txt" && ok || fail "-fines_view printed nothing"

# A built-in registered monitor by name: sampled every -NAME_every steps, viewed by -NAME_view; the
# same file asked for twice is refused.
run "-monitors mixing_index" "$rcfd" run -db "$data/small.h5" -quiet -fields 0 -plot 0 -t_end 0.1 \
  -monitors mixing_index -mixing_index_every 2 -mixing_index_view ascii:"$work/mixing-view.txt" -output_dir "$work/mixing"
same "rows of mixing.csv (20 steps, every 2nd, and the start)" "$(grep -c . "$work/mixing/mixing.csv")" 12 0
grep -q "monitor mixing_index" "$work/mixing-view.txt" && ok || fail "-mixing_index_view printed nothing"
expect_error "-monitors mixing_index and -mixing_index both ask for mixing.csv; give one of them" \
  run -db "$data/small.h5" -monitors mixing_index -mixing_index
expect_error "-monitors: unknown monitor 'fines'; known monitors: markov, mixing_index" run -db "$data/small.h5" -monitors fines

# rcfd calibrate: the plugin's operator in the pipeline, its law fitted.
run "calibrate with the plugin" "$rcfd" calibrate -plugin "$plugin" -db "$data/small.h5" \
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -fields 0 \
  -reference "$work/full1/cog.csv" -score_window 0.1,0.3 -pipeline shift,drift,attrition,carry -attrition_rate 0.2 \
  -calibrate_models linear -calibrate_kd_range 1e-3,1e-1 -calibrate_scan 3 -output_dir "$work/calibrate"
grep -q "^model linear: best k_d" "$work/out.txt" && ok || fail "calibrate fitted no linear law: $(tail -5 "$work/out.txt")"
# The plugin's path rule reaches calibrate too, batched replays included.
run "calibrate on the plugin's path" "$rcfd" calibrate -plugin "$plugin" -db "$data/small.h5" \
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -fields 0 -path_type stride \
  -path_stride 3 -reference "$work/full1/cog.csv" -score_window 0.1,0.3 -pipeline shift,drift,carry \
  -calibrate_models linear -calibrate_kd_range 1e-3,1e-1 -calibrate_scan 3 -calibrate_batch true \
  -output_dir "$work/calibrate-stride"
grep -q "^model linear: best k_d" "$work/out.txt" && grep -Eq "[1-9][0-9]* of [0-9]+ in [1-9][0-9]* batched" "$work/out.txt" &&
  ok || fail "calibrate on the plugin's path rule, batched: $(tail -3 "$work/out.txt")"
grep -q "stride: every 3 frames" "$work/calibrate-stride/path.txt" && ok ||
  fail "the calibration did not step the plugin's path: $(head -1 "$work/calibrate-stride/path.txt")"

# Refusals, one sentence each.
cat >"$work/other.cpp" <<'CPP'
#include <rcfd/plugin.hpp>
extern "C" __attribute__((visibility("default"))) const char rcfd_plugin_version[] = "0.0.1";
extern "C" PetscErrorCode rcfd_plugin_register(rcfd::Registries *) { return 0; }
CPP
cat >"$work/clash.cpp" <<'CPP'
#include <rcfd/plugin.hpp>
#include <memory>
RCFD_PLUGIN_VERSION_SYMBOL
extern "C" PetscErrorCode rcfd_plugin_register(rcfd::Registries *r) {
  return r->operators.add("drift", [] { return std::unique_ptr<rcfd::Operator>(); }, "a second drift");
}
CPP
flags=$(grep -E "^CXX_FLAGS|^CXX_INCLUDES|^CXX_DEFINES" "$work/example/CMakeFiles/rcfd_attrition.dir/flags.make" | cut -d= -f2- | tr '\n' ' ')
for name in other clash; do
  # shellcheck disable=SC2086
  "$cxx" -std=c++17 -shared -fPIC $flags "$work/$name.cpp" -o "$work/lib$name.so" || fail "cannot build lib$name.so"
done
expect_error "-plugin $work/libother.so was built against rcfd 0.0.1, not this rcfd 0.3.0; rebuild it against this version" \
  run -plugin "$work/libother.so" -db "$data/small.h5"
expect_error "-plugin $work/libclash.so: its registration failed: Cannot register the operator 'drift': the name is taken" \
  run -plugin "$work/libclash.so" -db "$data/small.h5"
expect_error "-plugin $work/nothere.so cannot be opened" run -plugin "$work/nothere.so" -db "$data/small.h5"
expect_error "-pipeline: unknown operator 'attrition'; known operators: carry, discharge, dispersion, drift, feed" \
  run -db "$data/small.h5" -pipeline shift,attrition

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
