#!/usr/bin/env bash
# One bit flipped in a small database, or in a checkpoint, at seeded positions of every class of its
# bytes (tests/h5_bytes: HDF5's superblock, its other records — object headers with the attributes
# dt_rec, the mesh box, the conditions, ..., chunk indexes, link heaps, free space — and the stored
# data of each kind of dataset, /mesh/* and every frame dataset): `rcfd run` (a restart for the
# checkpoint) either refuses with one line "rcfd run: error: ..." and exit status 1, or writes every
# output file byte-identical to the intact file's run; never a signal, never a different answer with
# exit 0.  Where the run is unchanged, `rcfd info` either refuses the same way or prints exactly what
# it prints for the intact file (a flip it does not catch is in bytes nothing reads).
# FUZZ_SEED (default 1) and FUZZ_PER_CLASS (default 2) choose the flips; FUZZ_WITHOUT_CHECKSUMS=1
# runs the same flips on files written as an rcfd before checksums did (the test hook
# RCFD_WRITE_WITHOUT_CHECKSUMS), to show what the checksums catch.
# usage: test_corruption_fuzz.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
bytes=$(dirname "$2")/h5_bytes
source "$4/tests/script_helpers.sh"
seed=${FUZZ_SEED:-1} per=${FUZZ_PER_CLASS:-2}
[ "${FUZZ_WITHOUT_CHECKSUMS:-0}" = 1 ] && export RCFD_WRITE_WITHOUT_CHECKSUMS=1
common=(-quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 11 -fractions_diameters
  1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -mixing_index)
refused=0 harmless=0 silent=0 crashed=0

# judge LABEL DIR_REF DIR_OUT STATUS ERR: counts the outcome of one damaged run; 0 if it changed nothing.
judge() {
  local label=$1 status=$4 f
  if [ "$status" -eq 0 ]; then
    for f in "$2"/*; do
      if ! cmp -s "$f" "$3/$(basename "$f")"; then
        silent=$((silent + 1))
        fail "$label: exit 0 but $(basename "$f") differs from the intact run's"
        return 1
      fi
    done
    harmless=$((harmless + 1))
    ok
    return 0
  fi
  if [ "$status" -eq 1 ] && [ "$(grep -c . "$5")" -eq 1 ] && grep -q "^rcfd [a-z]*: error: " "$5" &&
    ! grep -q "PETSC ERROR" "$5"; then
    refused=$((refused + 1))
    ok
  else
    crashed=$((crashed + 1))
    fail "$label: exit status $status and not one error line: $(head -c 600 "$5")"
  fi
  return 1
}

# The database: its intact run and view.
db=$work/db.h5
"$rcfd" synth -o "$work/intact.h5" -synth_cells 10,2,20 -synth_frames 60 -quiet || fail "synth"
cp "$work/intact.h5" "$db"
"$rcfd" run -db "$db" "${common[@]}" -t_end 0.5 -output_dir "$work/ref" >/dev/null 2>"$work/err" || fail "intact run: $(cat "$work/err")"
"$rcfd" info "$db" >"$work/ref-info.txt" 2>&1 || fail "intact info: $(cat "$work/ref-info.txt")"
while read -r class offset bit; do
  cp "$work/intact.h5" "$db" && "$bytes" "$db" flip "$offset" "$bit" || { fail "cannot flip $offset"; continue; }
  rm -rf "$work/out"
  "$rcfd" run -db "$db" "${common[@]}" -t_end 0.5 -output_dir "$work/out" >/dev/null 2>"$work/err"
  judge "database, $class, byte $offset bit $bit, run" "$work/ref" "$work/out" $? "$work/err" || continue
  "$rcfd" info "$db" >"$work/info.txt" 2>"$work/err"
  status=$?
  if [ $status -eq 0 ] && ! cmp -s "$work/info.txt" "$work/ref-info.txt"; then
    silent=$((silent + 1))
    fail "database, $class, byte $offset bit $bit: rcfd info exits 0 but prints another view: $(diff "$work/ref-info.txt" "$work/info.txt" | head -4)"
  elif [ $status -ne 0 ]; then
    judge "database, $class, byte $offset bit $bit, info" "" "" $status "$work/err"
  fi
done < <("$bytes" "$work/intact.h5" sample "$seed" "$per")

# The checkpoint of step 50 (t = 0.25 s) of a run stopped at 0.3 s, restarted to 0.5 s.
cp "$work/intact.h5" "$db"
"$rcfd" run -db "$db" "${common[@]}" -t_end 0.3 -checkpoint_every 0.25 -output_dir "$work/first" >/dev/null 2>&1 ||
  fail "first part"
while read -r class offset bit; do
  rm -rf "$work/second" && cp -r "$work/first" "$work/second" &&
    "$bytes" "$work/second/checkpoint.h5" flip "$offset" "$bit" || { fail "cannot flip $offset"; continue; }
  "$rcfd" run -db "$db" "${common[@]}" -t_end 0.5 -restart "$work/second/checkpoint.h5" \
    -output_dir "$work/second" >/dev/null 2>"$work/err"
  status=$?
  rm -f "$work/second/checkpoint.h5" # the comparison is of the run's own files
  judge "checkpoint, $class, byte $offset bit $bit, restart" "$work/ref" "$work/second" $status "$work/err"
done < <("$bytes" "$work/first/checkpoint.h5" sample "$seed" "$per")

[ $((refused + harmless + silent + crashed)) -gt 0 ] || fail "no flips were made"
echo "flips: $refused refused with one sentence, $harmless without effect, $silent a different answer with exit 0, $crashed crashed"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
