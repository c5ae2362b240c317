#!/usr/bin/env bash
# A seeded fuzz pass over the options of `rcfd run`, `build`, `synth` and `markov`, taken
# from their -help (so options added later are covered): each invocation sets
# one to three options to hostile values (NaN, inf, empty, negative, huge,
# text, lists) and must either succeed or exit non-zero with exactly one line
# "rcfd CMD: error: ..." -- never a signal, a traceback or a hang.
# usage: test_option_fuzz.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR   (env FUZZ_SEED, FUZZ_RUNS)
set -u
rcfd=$1 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
write_two_particle_dumps
RANDOM=${FUZZ_SEED:-20261129}
runs=${FUZZ_RUNS:-25}
values=(nan inf -inf "" -1 0 1 2 -5 1e300 -1e300 1e-300 0.5 abc "1,2,3" "0,0" 7 1e9 true false "-")

options_of() { # the command's own options, from its -help
  "$rcfd" "$@" -help 2>&1 | awk -v cmd="rcfd $1" '
    index($0, cmd) == 1 { on = 1; next }
    on && /PetscOptionsGetViewer/ { next }
    on && match($0, /^  -[a-z0-9_]+/) { print substr($0, 4, RLENGTH - 3) }' | sort -u |
    grep -vxE 'help|restart|db|o|dumps|dump_list|times|eulerian|quiet|init_file|path_file|live' || true
}
# (-live names a file another program writes: a run waits for it to appear, saying so, by design;
# the live tests cover it.)

declare -A base
base[run]="-db $data/small.h5 -t_end 0.02 -output_dir $work/out -quiet -plot false -fields false"
base[synth]="-synth_cells 4,2,8 -synth_frames 3 -synth_warm_up 0 -o $work/s.h5 -quiet"
ls "$work"/dump/dump.*.txt >"$work/dumps.txt"
base[build]="-dump_list $work/dumps.txt -dump_dt 0.1 -mesh_cells 2,1,2 -o $work/b.h5 -quiet"
base[markov]="$data/small.h5 -o $work/out -quiet -plot 0 -zones low -zone_low_layers 0,4 -markov_mix_horizon 2 -markov_passage_horizon 1
  -fractions_diameters 1e-3,3e-3 -fractions_mass_shares 0.5,0.5 -drift_model B -drift_kd 5e4"

cd "$work" || exit 1
for cmd in run synth build markov; do
  # shellcheck disable=SC2086
  mapfile -t opts < <(options_of $cmd ${base[$cmd]})
  [ ${#opts[@]} -gt 5 ] || { fail "$cmd: only ${#opts[@]} options found in -help"; continue; }
  for ((k = 0; k < runs; ++k)); do
    args=()
    for ((j = 0; j <= RANDOM % 3; ++j)); do
      args+=("-${opts[RANDOM % ${#opts[@]}]}" "${values[RANDOM % ${#values[@]}]}")
    done
    # shellcheck disable=SC2086
    timeout 20 "$rcfd" $cmd ${base[$cmd]} "${args[@]}" >/dev/null 2>"$work/err.txt"
    rc=$?
    lines=$(grep -c . "$work/err.txt")
    # A run given a huge -t_end is a long run, not a hang: it has written rows of cog.csv (the small
    # database's 60 frames take well under a second). No row in 20 s is a hang, and a failure.
    if [ $rc -eq 124 ] && [ "$cmd" = run ] && [ "$(grep -vs '^#' "$work/out/cog.csv" | grep -c .)" -gt 10 ]; then
      ok
    elif [ $rc -eq 124 ]; then
      fail "rcfd $cmd ${args[*]}: no answer in 20 s (a hang is a failure)"
    elif [ $rc -ge 128 ] || grep -q "PETSC ERROR\|terminate called\|Segmentation\|Aborted" "$work/err.txt"; then
      fail "rcfd $cmd ${args[*]}: exit $rc: $(head -3 "$work/err.txt")"
    elif [ $rc -ne 0 ] && { [ "$lines" -ne 1 ] || ! grep -q "^rcfd $cmd: error: " "$work/err.txt"; }; then
      fail "rcfd $cmd ${args[*]}: exit $rc with $lines lines: $(head -3 "$work/err.txt")"
    else
      ok
    fi
    rm -rf "$work/out" "$work/s.h5" "$work/b.h5"
  done
done
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
