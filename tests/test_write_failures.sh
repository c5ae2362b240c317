#!/usr/bin/env bash
# A write that fails leaves no file under its final name that is not
# complete, no temporary behind, and ends every rank with one sentence that
# names the file -- no crash, no hang.  Failures are injected with the test
# hook RCFD_FAIL_WRITE (src/base/atomic_file.hpp): the process may not grow a
# file past RCFD_FAIL_WRITE_BYTES while it writes a file whose path contains
# the text, so HDF5 and stdio see real write errors (EFBIG) as on a full disk.
# Also: a failed run says so in OUTPUT_DIR/FAILED and keeps cog.csv, and a
# run restarted into its own directory continues the field series.
# usage: test_write_failures.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 data=$3
h5print=$(dirname "$2")/h5_print
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

# failed_cleanly LABEL RC OUTPUT FILE: rc 1 (not a signal, not a timeout),
# exactly one line from rcfd, naming FILE, and no PETSc dump or crash report.
failed_cleanly() {
  local label=$1 rc=$2 out=$3 file=$4
  local lines
  lines=$(grep -c "^rcfd [a-z]*: error: " <<<"$out")
  if [ "$rc" -ne 1 ]; then
    fail "$label: exit code $rc, expected 1 (124: hung, >128: crashed): $out"
  elif [ "$lines" -ne 1 ] || ! grep -q "^rcfd [a-z]*: error: .*'$file'" <<<"$out"; then
    fail "$label: expected one line naming '$file', got: $out"
  elif grep -qiE "PETSC ERROR|segmentation|signal|HDF5-DIAG" <<<"$out"; then
    fail "$label: a crash or a library dump: $out"
  else
    ok
  fi
}

no_temporaries() { # no_temporaries LABEL DIR
  local left
  left=$(find "$2" -name '*.tmp')
  if [ -n "$left" ]; then fail "$1: temporaries left behind: $left"; else ok; fi
}

absent() { # absent LABEL FILE
  if [ -e "$2" ]; then fail "$1: '$2' exists under its final name"; else ok; fi
}

# ---- synth and build: the database is complete or not there, and no "Wrote".
for bytes in 0 100000; do
  out=$(RCFD_FAIL_WRITE=s.h5 RCFD_FAIL_WRITE_BYTES=$bytes timeout 120 "$rcfd" synth -o "$work/s.h5" \
    -synth_cells 10,2,20 -synth_frames 60 2>&1)
  failed_cleanly "synth, writes fail after $bytes bytes" $? "$out" "$work/s.h5"
  grep -q "^Wrote" <<<"$out" && fail "synth printed 'Wrote' after a failed write: $out"
  absent "synth after $bytes bytes" "$work/s.h5"
  no_temporaries "synth after $bytes bytes" "$work"
done
write_two_particle_dumps
out=$(RCFD_FAIL_WRITE=b.h5 timeout 120 "$rcfd" build "${common[@]}" -o "$work/b.h5" 2>&1)
failed_cleanly "build" $? "$out" "$work/b.h5"
grep -q "^Wrote" <<<"$out" && fail "build printed 'Wrote' after a failed write: $out"
absent "build" "$work/b.h5"
out=$(RCFD_FAIL_WRITE=init.h5 timeout 120 "$rcfd" build "${common[@]}" -o "$work/b.h5" -init_out "$work/init.h5" 2>&1)
failed_cleanly "build -init_out" $? "$out" "$work/init.h5"
absent "build -init_out" "$work/init.h5"
no_temporaries "build" "$work"

# ---- run, at 1 and 2 ranks: a field file, the checkpoint, cog.csv.
opts=(-db "$data/small.h5" -quiet -plot 0 -t_end 2 -fields_every 0.25 -checkpoint_every 0.5)
for np in 1 2; do
  for target in fields_000002.h5 checkpoint.h5 cog.csv; do
    dir=$work/run$np-${target%%.*}
    out=$(RCFD_FAIL_WRITE=$target timeout 120 mpiexec -n $np "$rcfd" run "${opts[@]}" -output_dir "$dir" 2>&1)
    failed_cleanly "run -n $np, $target" $? "$out" "$dir/$target"
    absent "run -n $np, $target" "$dir/$target"
    no_temporaries "run -n $np, $target" "$dir"
    if grep -q "rcfd run failed at step [0-9]* of 400 (t = [0-9.]* s): .*'$dir/$target'" "$dir/FAILED" 2>/dev/null; then
      ok
    else
      fail "run -n $np, $target: no FAILED naming the step and the file: $(cat "$dir/FAILED" 2>&1)"
    fi
    for f in "$dir"/fields_*.h5 "$dir"/checkpoint.h5; do # what is there is complete
      [ -e "$f" ] && { "$h5print" "$f" /masses >/dev/null 2>&1 || "$h5print" "$f" /alpha_s >/dev/null 2>&1 ||
        fail "run -n $np, $target: '$f' cannot be read"; }
    done
  done
  # The field file of t = 0.5 s failed: cog.csv keeps the rows up to then
  # (t = 0 .. 0.5 s in steps of 0.005 s), the same as a complete run's.
  dir=$work/run$np-fields_000002
  if [ "$(wc -l <"$dir/cog.csv" 2>/dev/null)" = 102 ] && [ "$(tail -1 "$dir/cog.csv" | cut -d, -f1)" = 0.5 ]; then
    ok
  else
    fail "run -n $np: cog.csv of the failed run does not end at t = 0.5 s: $(tail -1 "$dir/cog.csv" 2>&1)"
  fi
done
# A successful run into the same directory removes the failure marker.
"$rcfd" run "${opts[@]}" -output_dir "$work/run1-fields_000002" >/dev/null 2>&1 || fail "a clean rerun failed"
absent "a clean rerun" "$work/run1-fields_000002/FAILED"
ref=$work/run1-fields_000002 # an uninterrupted run

# ---- a restart into the same directory continues the field series.
times() { grep -o '<Time Value="[^"]*"' "$1" | tr '\n' ' '; }
for np in 1 2; do
  dir=$work/restart$np
  mpiexec -n $np "$rcfd" run "${opts[@]}" -t_end 1.1 -output_dir "$dir" >/dev/null 2>&1 || fail "first leg failed"
  mpiexec -n $np "$rcfd" run "${opts[@]}" -restart "$dir/checkpoint.h5" -output_dir "$dir" >/dev/null 2>&1 ||
    fail "restart failed"
  if [ -n "$(times "$ref/fields.xmf")" ] && [ "$(times "$dir/fields.xmf")" = "$(times "$ref/fields.xmf")" ]; then
    ok
  else
    fail "restart -n $np: XDMF times '$(times "$dir/fields.xmf")', uninterrupted '$(times "$ref/fields.xmf")'"
  fi
  for k in 0 1 2 3 4 5 6 7 8; do
    same "restart -n $np, alpha_s of fields_00000$k" "$("$h5print" "$dir/fields_00000$k.h5" /alpha_s 2>&1)" \
      "$("$h5print" "$ref/fields_00000$k.h5" /alpha_s 2>&1)" 1e-12
  done
done

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
