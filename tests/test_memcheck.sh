#!/usr/bin/env bash
# One small run under valgrind's memcheck: two fractions with drift, fields
# and a checkpoint on a tiny synthetic bed, a few steps.  Fails on an invalid
# read or write, a use of uninitialised memory, or a definite leak (PETSc's
# -malloc_dump does not see C++ allocations).  Open MPI's own allocations at
# MPI_Init are suppressed (Open MPI's suppression file plus
# tests/valgrind-mpi.supp).  Skipped (CTest code 77) without valgrind.
# usage: test_memcheck.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rcfd=$1 src=$4
command -v valgrind >/dev/null || { echo "valgrind is not installed: skipped"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$rcfd" synth -o "$work/tiny.h5" -synth_cells 6,2,12 -synth_frames 20 -quiet || exit 1
supp=(--suppressions="$src/tests/valgrind-mpi.supp")
[ -f /usr/share/openmpi/openmpi-valgrind.supp ] && supp+=(--suppressions=/usr/share/openmpi/openmpi-valgrind.supp)
valgrind --tool=memcheck --error-exitcode=99 --leak-check=full --show-leak-kinds=definite \
  --errors-for-leak-kinds=definite --num-callers=50 --log-file="$work/memcheck.log" "${supp[@]}" \
  "$rcfd" run -db "$work/tiny.h5" -t_end 0.05 -fractions_diameters 1e-3,3e-3 \
  -fractions_mass_shares 0.5,0.5 -drift_model B -drift_kd 5e3 -checkpoint_every 0.025 \
  -output_dir "$work/out" -quiet -plot 0 >"$work/run.txt" 2>&1
status=$?
if [ $status -ne 0 ]; then
  echo "FAIL: rcfd run under valgrind exited with $status (99: memcheck found errors)"
  cat "$work/run.txt"
  grep -v "^==[0-9]*== *$" "$work/memcheck.log" | grep -A40 -E "Invalid|uninitialised|definitely lost in" | head -150
  exit 1
fi
# The run did its work: 11 samples (t = 0 ... 0.05 s) and a checkpoint.
rows=$(($(wc -l <"$work/out/cog.csv") - 1))
[ "$rows" -eq 11 ] && [ -s "$work/out/checkpoint.h5" ] ||
  { echo "FAIL: expected 11 samples and a checkpoint, found $rows rows"; exit 1; }
grep -E "ERROR SUMMARY|definitely lost:" "$work/memcheck.log" | sed 's/^==[0-9]*== //'
echo "1 passed, 0 failed"
