#!/usr/bin/env bash
# Databases and checkpoints that check themselves (docs/database-format.md, "Checksums"): a new
# database says "verified" in rcfd info; one written as an rcfd before checksums did (the test hook
# RCFD_WRITE_WITHOUT_CHECKSUMS) still loads, with a note that it cannot be verified, and gives the same
# run byte for byte; rcfd coarsen -factor 1,1,1 adds the checksums (same identity, same run); a
# damaged chunk of a frame is one sentence naming the file, the frame and the dataset at 1 and 2
# ranks; a checkpoint without checksums restarts byte for byte and a damaged one is refused naming
# the part.
# usage: test_checksums.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
tools=$(dirname "$2")
source "$4/tests/script_helpers.sh"
common=(-quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 11 -fractions_diameters
  1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -mixing_index)
small=(-synth_cells 10,2,20 -synth_frames 60 -quiet)
files=(cog.csv mixing.csv path.txt jumps.csv)
same_files() { # same_files LABEL DIR_A DIR_B
  local f
  for f in "${files[@]}"; do
    if cmp -s "$2/$f" "$3/$f"; then ok; else fail "$1: $3/$f differs from $2/$f"; fi
  done
}

run "synth" "$rcfd" synth -o "$work/new.h5" "${small[@]}"
run "synth without checksums" env RCFD_WRITE_WITHOUT_CHECKSUMS=1 "$rcfd" synth -o "$work/old.h5" "${small[@]}"
[ "$("$tools/h5_print" "$work/new.h5" / checksums string)" = fletcher32 ] && ok || fail "new.h5 has no checksums attribute"
"$tools/h5_print" "$work/old.h5" / checksums string >/dev/null 2>&1 && fail "old.h5 has a checksums attribute" || ok
grep -q "^  integrity: verified (308 datasets" <<<"$("$rcfd" info "$work/new.h5")" && ok ||
  fail "rcfd info new.h5 should say verified: $("$rcfd" info "$work/new.h5" 2>&1 | grep integrity)"
info=$("$rcfd" info "$work/old.h5" 2>&1)
grep -q "^  integrity: cannot be verified: the file has no checksums" <<<"$info" &&
  grep -q "^Note: database '$work/old.h5' has no checksums" <<<"$info" && ok || fail "rcfd info old.h5: $info"

# The same frames, with and without checksums, and rewritten: the same runs, byte for byte.
run "run new" "$rcfd" run -db "$work/new.h5" "${common[@]}" -t_end 0.5 -output_dir "$work/new"
run "run old" "$rcfd" run -db "$work/old.h5" "${common[@]}" -t_end 0.5 -output_dir "$work/old"
same_files "without checksums" "$work/new" "$work/old"
run "coarsen adds checksums" "$rcfd" coarsen "$work/old.h5" -factor 1,1,1 -o "$work/rewritten.h5" -quiet
grep -q "^  integrity: verified" <<<"$("$rcfd" info "$work/rewritten.h5")" && ok || fail "rewritten.h5 not verified"
[ "$("$tools/h5_print" "$work/rewritten.h5" / content_hash string)" = "$("$tools/h5_print" "$work/old.h5" / content_hash string)" ] &&
  ok || fail "rcfd coarsen -factor 1,1,1 changed the identity"
run "run rewritten" "$rcfd" run -db "$work/rewritten.h5" "${common[@]}" -t_end 0.5 -output_dir "$work/rewritten"
same_files "rewritten by coarsen" "$work/new" "$work/rewritten"

# A damaged chunk of frame 7's alpha_s: one sentence at 1 and 2 ranks (flip a bit in the middle of
# the dataset's stored data, found by tests/h5_bytes' listing of frame datasets).
cp "$work/new.h5" "$work/damaged.h5"
where=$("$tools/h5_bytes" "$work/new.h5" locate /frames/000007/alpha_s)
"$tools/h5_bytes" "$work/damaged.h5" flip $((where + 100)) 3
sentence="error: database '$work/damaged.h5', frame 7: dataset alpha_s is damaged (its bytes do not match their checksum"
expect_error "$sentence" run -db "$work/damaged.h5" "${common[@]}" -t_end 0.5 -output_dir "$work/refused"
expect_error "$sentence" info "$work/damaged.h5"
out=$(mpiexec -n 2 "$rcfd" run -db "$work/damaged.h5" "${common[@]}" -t_end 0.5 -output_dir "$work/refused" 2>&1)
[ $? -ne 0 ] && [ "$(grep -c "$sentence" <<<"$out")" -eq 1 ] && ! grep -q "PETSC ERROR" <<<"$out" && ok ||
  fail "2 ranks, damaged alpha_s: $out"
[ ! -e "$work/refused/cog.csv" ] && ok || fail "a refused run wrote $work/refused/cog.csv"

# Checkpoints: one without checksums restarts byte for byte; a damaged /masses is refused.
for kind in old new; do
  hook=0
  [ $kind = old ] && hook=1
  run "first part, $kind checkpoint" env RCFD_WRITE_WITHOUT_CHECKSUMS=$hook "$rcfd" run -db "$work/new.h5" "${common[@]}" \
    -t_end 0.3 -checkpoint_every 0.25 -output_dir "$work/first-$kind" || continue
  run "restart from the $kind checkpoint" "$rcfd" run -db "$work/new.h5" "${common[@]}" -t_end 0.5 \
    -restart "$work/first-$kind/checkpoint.h5" -output_dir "$work/first-$kind" &&
    same_files "restart from the $kind checkpoint" "$work/new" "$work/first-$kind"
done
"$tools/h5_print" "$work/first-old/checkpoint.h5" / checksums string >/dev/null 2>&1 && fail "old checkpoint has checksums" || ok
cp "$work/first-new/checkpoint.h5" "$work/damaged-checkpoint.h5"
"$tools/h5_bytes" "$work/damaged-checkpoint.h5" flip $(($("$tools/h5_bytes" "$work/damaged-checkpoint.h5" locate /masses) + 8)) 0
expect_error "error: HDF5 file '$work/damaged-checkpoint.h5': '/masses' is damaged (its bytes do not match their checksum" \
  run -db "$work/new.h5" "${common[@]}" -t_end 0.5 -restart "$work/damaged-checkpoint.h5" -output_dir "$work/refused"
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
