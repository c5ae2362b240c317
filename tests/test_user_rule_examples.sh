#!/usr/bin/env bash
# The path and switching rules of include/rcfd/path.hpp and switching.hpp as an outside project
# writes them: configure docs/examples/user-path-rule
# and docs/examples/user-switch-rule against the INSTALLED package (find_package(rcfd),
# rcfd::rcfd), build them, run each rule on small synthetic beds at 2 ranks, and check the frames
# and switches it made -- numbers only the user's rule and option determine.
# The package is installed once, into PREFIX, by the fixture installed_package.
# usage: test_user_rule_examples.sh RCFD BUILD_DIR SOURCE_DIR CMAKE CXX_COMPILER PREFIX
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rcfd=$1 build=$2 src=$3 cmake=$4 cxx=$5 prefix=$6
work=$build/test-data/user-rules
rm -rf "$work"
mkdir -p "$work"
source "$src/tests/script_helpers.sh"

build_example user-path-rule "$src" "$prefix" "$cmake" "$cxx"
build_example user-switch-rule "$src" "$prefix" "$cmake" "$cxx"

bed=(-synth_cells 6,2,12 -synth_frames 20 -quiet) # dt_rec 0.005 s
"$prefix/bin/rcfd" synth -o "$work/a.h5" "${bed[@]}"
"$prefix/bin/rcfd" synth -o "$work/b.h5" "${bed[@]}" -synth_seed 2
quiet=(-fields 0 -plot 0 -quiet)

# ---- the path rule: 20 steps through the 20 frames, 3 at a time.
run "path rule stride at 2 ranks" mpiexec -n 2 "$work/user-path-rule/user_path_rule" -db "$work/a.h5" \
  -t_end 0.1 -path_type stride -path_stride 3 "${quiet[@]}" -output_dir "$work/path" -run_view
grep -q "stride 3" "$work/out.txt" || fail "-run_view did not print the path rule: $(cat "$work/out.txt")"
same "frames of path.txt" "$(grep -v '^#' "$work/path/path.txt")" \
  "$(awk 'BEGIN { for (s = 0; s < 20; ++s) print (3 * s) % 20 }')" 0
# Every step goes on to another frame than the next: after each of the 20 a jump (the last one's
# into the frame a 21st step would use).
same "jumps.csv: from_frame to_frame" "$(awk -F, '$1 ~ /^[0-9]+$/ { print $3, $4 }' "$work/path/jumps.csv")" \
  "$(awk 'BEGIN { for (s = 0; s < 20; ++s) print (3 * s) % 20, (3 * s + 3) % 20 }')" 0
# Its own option, checked by its own setFromOptions.
if out=$("$work/user-path-rule/user_path_rule" -db "$work/a.h5" -t_end 0.1 -path_type stride \
  -path_stride 0 "${quiet[@]}" -output_dir "$work/path0" 2>&1); then
  fail "-path_stride 0 ran; expected a refusal"
else
  grep -qF -- "-path_stride must be at least 1, got 0" <<<"$out" && ok || fail "-path_stride 0: $out"
fi

# ---- the switching rule: 40 steps on the set a, b, the next database every 10 steps.
run "switching rule alternate at 2 ranks" mpiexec -n 2 "$work/user-switch-rule/user_switch_rule" \
  -db "$work/a.h5,$work/b.h5" -t_end 0.2 -db_switch_type alternate -db_switch_every 10 "${quiet[@]}" \
  -output_dir "$work/switch"
same "switches.csv" "$(grep -v '^#' "$work/switch/switches.csv")" "time_s,from,to,trigger,event
0.05,0,1,10,switch
0.1,1,0,20,switch
0.15,0,1,30,switch
0.2,1,0,40,switch"

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
