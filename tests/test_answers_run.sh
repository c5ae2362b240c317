#!/usr/bin/env bash
# The answers in whole runs on the small synthetic database:
# - a run restarted from a checkpoint in the middle of the profiles' and
#   halves' window writes the same profiles, halves, bottom layer, mixing and
#   bed dynamics files, bit for bit, as one uninterrupted run (1 and 2 ranks);
# - 1 and 2 ranks give the same files within round-off;
# - the de-fluidization warning is printed once, at the first row where u_mf
#   reached u_sup, and flagged in bottom.csv from there;
# - operating conditions come from the case, the database or the default, and say so;
# - bad options are refused with one sentence.
# usage: test_answers_run.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 compare=$2 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
db=$data/small.h5
answers=(-profiles -profiles_window 0.2,0.6 -halves -halves_window 0.2,0.6 -bottom_layer -mixing_index
  -bed_dynamics -zones low -zone_low_layers 0,2)
common=(-db "$db" -quiet -fields 0 -plot 0 -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436
  "${answers[@]}" -observables_every 2)
files="profiles halves bottom mixing bed_dynamics"

# Restart in the middle of the window, along a path with jumps.
stitched=(-path_type random -path_seed 5)
for np in 1 2; do
  run "full run np$np" mpiexec -n $np "$rcfd" run "${common[@]}" "${stitched[@]}" -t_end 0.8 -output_dir "$work/full$np" &&
    run "first half np$np" mpiexec -n $np "$rcfd" run "${common[@]}" "${stitched[@]}" -t_end 0.4 -checkpoint_every 0.4 \
      -output_dir "$work/first$np" &&
    run "restart np$np" mpiexec -n $np "$rcfd" run "${common[@]}" "${stitched[@]}" -t_end 0.8 \
      -restart "$work/first$np/checkpoint.h5" -output_dir "$work/second$np" || continue
  for f in $files; do
    if cmp -s "$work/full$np/$f.csv" "$work/second$np/$f.csv"; then ok; else fail "np$np: restarted $f.csv differs"; fi
  done
  # The window really was cut: the first half alone averaged fewer samples.
  if grep -q "mean over 41 samples" "$work/full$np/profiles.csv" &&
    grep -q "mean over 21 samples" "$work/first$np/profiles.csv"; then ok; else
    fail "np$np: window sample counts: $(head -1 "$work/full$np/profiles.csv") / $(head -1 "$work/first$np/profiles.csv")"
  fi
done

# A restart that asks for a windowed answer the checkpoint did not keep is refused.
plain=(-db "$db" -quiet -fields 0 -plot 0)
"$rcfd" run "${plain[@]}" -t_end 0.4 -checkpoint_every 0.4 -output_dir "$work/plain"
expect_error "holds no state of the monitor profiles.csv: ask for the same answers as the run that wrote the checkpoint" \
  run "${plain[@]}" -t_end 0.8 -profiles -restart "$work/plain/checkpoint.h5" -output_dir "$work/other"

# 1 and 2 ranks, replayed.
for np in 1 2; do
  run "replay np$np" mpiexec -n $np "$rcfd" run "${common[@]}" -t_end 0.5 -init layered -output_dir "$work/np$np"
done
for f in $files; do
  if "$compare" "$work/np1/$f.csv" "$work/np2/$f.csv" 1e-10 1e-14 >/dev/null; then ok; else
    fail "1 and 2 ranks differ in $f.csv: $("$compare" "$work/np1/$f.csv" "$work/np2/$f.csv" 1e-10 1e-14 2>&1)"
  fi
done

# The warning: the mixed bed's bottom layer coarsens under drift; u_sup set between its start and end u_mf.
mpiexec -n 2 "$rcfd" run "${common[@]}" -t_end 1 -superficial_velocity 0.86 -output_dir "$work/warn" \
  >"$work/warn.txt" 2>&1 || fail "warning run: $(cat "$work/warn.txt")"
lines=$(grep -c "WARNING: de-fluidization" "$work/warn.txt")
[ "$lines" = 1 ] && ok || fail "the warning was printed $lines times: $(cat "$work/warn.txt")"
first=$(awk -F, 'NR > 1 && $5 == 1 { print $1; exit }' "$work/warn/bottom.csv")
before=$(awk -F, 'NR > 1 && $5 == 1 { print prev; exit } NR > 1 { prev = $3 " < " $4 }' "$work/warn/bottom.csv")
grep -q "WARNING: de-fluidization at t = $first s" "$work/warn.txt" && ok ||
  fail "warning time: $(grep WARNING "$work/warn.txt"), first flagged row at '$first'"
awk -F, -v f="$first" 'NR > 1 && $1 < f && ($3 >= $4 || $5 != 0) { bad = 1 } END { exit bad }' "$work/warn/bottom.csv" &&
  [ -n "$first" ] && ok || fail "rows before $first s are flagged or have u_mf >= u_sup ($before)"
# Saxena-Vogel gives a larger u_mf at these sizes: the warning comes earlier.
mpiexec -n 1 "$rcfd" run "${common[@]}" -t_end 1 -superficial_velocity 0.86 -umf_correlation saxena-vogel \
  -output_dir "$work/warn-sv" >"$work/warn-sv.txt" 2>&1
sv=$(awk -F, 'NR > 1 && $5 == 1 { print $1; exit }' "$work/warn-sv/bottom.csv")
awk -v a="$sv" -v b="$first" 'BEGIN { exit !(a < b) }' && ok || fail "saxena-vogel warned at '$sv', wen-yu at '$first'"

# Where the conditions came from.
"$rcfd" synth -o "$work/recorded.h5" -synth_cells 4,2,8 -synth_frames 3 -quiet -superficial_velocity 1.25 -gas_density 1.1
"$rcfd" run -db "$work/recorded.h5" -fields 0 -plot 0 -bottom_layer -gas_kinematic_viscosity 1.5e-5 \
  -output_dir "$work/cond" >"$work/cond.txt" 2>&1
grep -q "u_sup = 1.25 m/s (database), gas density 1.1 kg/m^3 (database), gas kinematic viscosity 1.5e-05 m^2/s (case)" \
  "$work/cond.txt" && ok || fail "conditions: $(cat "$work/cond.txt")"
"$rcfd" run -db "$db" -fields 0 -plot 0 -bottom_layer -t_end 0.01 -output_dir "$work/cond2" >"$work/cond2.txt" 2>&1
grep -q "u_sup = 1.1 m/s (default), gas density 1.189 kg/m^3 (default)" "$work/cond2.txt" && ok ||
  fail "default conditions: $(cat "$work/cond2.txt")"
awk -F, 'NR == 2 { exit !($4 == 1.1) }' "$work/cond2/bottom.csv" && ok || fail "u_sup column: $(head -2 "$work/cond2/bottom.csv")"

# The figures, where python3 has matplotlib: PNG files for each answer.
python=${RCFD_PYTHON:-/usr/bin/python3}
if "$python" -c 'import matplotlib, numpy' 2>/dev/null; then
  "$rcfd" run -db "$db" -fields 0 -quiet -t_end 0.3 "${answers[@]}" -snapshots_times 0,0.3 -plot 1 \
    -output_dir "$work/plots" -plot_reference "$work/np1" >"$work/plots.txt" 2>&1 || fail "figures: $(cat "$work/plots.txt")"
  for png in profiles halves bottom snapshots; do
    if [ "$(od -An -tx1 -N8 "$work/plots/$png.png" 2>/dev/null | tr -d ' \n')" = 89504e470d0a1a0a ]; then ok; else
      fail "no $png.png: $(cat "$work/plots.txt")"
    fi
  done
fi

# Bad options.
base=(run -db "$db" -fields 0 -plot 0 -quiet -t_end 0.1 -output_dir "$work/bad")
expect_error "-profiles_window takes two times t0,t1 in seconds with 0 <= t0 <= t1" "${base[@]}" -profiles -profiles_window 0.3,0.1
expect_error "The -halves window 5,6 s begins after the run's end at 0.1 s (-t_end)" "${base[@]}" -halves -halves_window 5,6
expect_error "-halves_split takes median or a height in metres, not 'middle'" "${base[@]}" -halves -halves_split middle
expect_error "-halves_split 9 m is outside the layer centres" "${base[@]}" -halves -halves_split 9
expect_error "the minimum fluidization correlation 'ergun' is not known; use one of wen-yu, richardson" "${base[@]}" -bottom_layer -umf_correlation ergun
expect_error "-superficial_velocity must be a positive number, got -1" "${base[@]}" -bottom_layer -superficial_velocity -1
expect_error "-observables_every must be at least 1 step, got 0" "${base[@]}" -mixing_index -observables_every 0
expect_error "-snapshots_times: 3 s is after the run's end at 0.1 s (-t_end)" "${base[@]}" -snapshots_times 0,3
expect_error "u_mf needs a particle density (1440 kg/m^3) above the gas density (2000 kg/m^3, -gas_density)" "${base[@]}" -bottom_layer -gas_density 2000

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
