#!/usr/bin/env bash
# Every input file must be a regular file: a FIFO given as an input (which would wait
# for a writer for ever), a character device such as /dev/zero (which never ends) and a
# directory are refused with one line naming the file, before it is opened.  Every
# reader is tried: databases, init files, checkpoints, options files (YAML and plain),
# particle snapshots, snapshot lists, times, Eulerian frames, references, run files,
# path files.  Each call runs under `timeout`: a hang is a failure.
# usage: test_input_files.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 db=$3/small.h5
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
write_two_particle_dumps
fifo=$work/pipe
mkfifo "$fifo" "$work/pipe.yaml" || { echo "FAIL: mkfifo"; exit 1; }

# refused KIND PATH [mpiexec -n N] CMD ARGS...: rcfd exits non-zero within 20 s with one line
# "input file 'PATH' is KIND, not a regular file" (and no other line of its own).
refused() {
  local kind=$1 path=$2 out rc
  shift 2
  local launcher=()
  [ "$1" = mpiexec ] && { launcher=("$1" "$2" "$3"); shift 3; }
  out=$(timeout 20 "${launcher[@]}" "$rcfd" "$@" 2>&1 >/dev/null)
  rc=$?
  local expected="input file '$path' is $kind, not a regular file"
  if [ $rc -eq 124 ]; then
    fail "rcfd $*: no answer in 20 s (it waits on '$path'); expected: $expected"
  elif [ $rc -eq 0 ]; then
    fail "rcfd $* succeeded; expected: $expected"
  elif ! grep -qF -- "$expected" <<<"$out"; then
    fail "rcfd $*: expected '$expected', got: $out"
  elif [ "$(grep -c '^rcfd' <<<"$out")" -ne 1 ] || grep -q "PETSC ERROR" <<<"$out" ||
    { [ ${#launcher[@]} -eq 0 ] && [ "$(grep -c . <<<"$out")" -ne 1 ]; }; then # mpiexec adds its own lines
    fail "rcfd $*: expected one line, got: $out"
  else
    ok
  fi
}
pipe="a FIFO (named pipe)"
run=(run -t_end 0.02 -output_dir "$work/out" -quiet -plot false -fields false)

# Databases, init files, checkpoints (HDF5), at 1 and 2 ranks; a device and a directory.
refused "$pipe" "$fifo" "${run[@]}" -db "$fifo"
refused "$pipe" "$fifo" mpiexec -n 2 "${run[@]}" -db "$fifo"
refused "a character device" /dev/zero "${run[@]}" -db /dev/zero
refused "a directory" "$work" "${run[@]}" -db "$work"
refused "$pipe" "$fifo" "${run[@]}" -db "$db,$fifo" -db_switch_schedule 0:1.1
refused "$pipe" "$fifo" info "$fifo"
refused "$pipe" "$fifo" coarsen "$fifo" -factor 2,1,2 -o "$work/c.h5"
refused "$pipe" "$fifo" "${run[@]}" -db "$db" -init file -init_file "$fifo"
refused "$pipe" "$fifo" mpiexec -n 2 "${run[@]}" -db "$db" -restart "$fifo"
# Options files, before PETSc reads them.
refused "$pipe" "$work/pipe.yaml" run -options_file "$work/pipe.yaml"
refused "$pipe" "$fifo" run -options_file "$fifo"
refused "a directory" "$work" run -options_file "$work"
# Text inputs: a path to replay, particle snapshots (found by a pattern, listed), times, frames.
refused "$pipe" "$fifo" "${run[@]}" -db "$db" -path_type recorded -path_file "$fifo"
printf '%s\n' "$work/dump/dump.0.txt" "$fifo" >"$work/list.txt"
refused "$pipe" "$fifo" build -dump_list "$work/list.txt" -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/b.h5"
refused "$pipe" "$fifo" build -dump_list "$fifo" -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/b.h5"
mkdir "$work/pipes" && mkfifo "$work/pipes/dump.0.txt" "$work/pipes/dump.1.txt"
refused "$pipe" "$work/pipes/dump.0.txt" build -dumps "$work/pipes/dump.*.txt" -dump_dt 0.1 \
  -mesh_cells 2,1,2 -o "$work/b.h5"
refused "$pipe" "$work/pipes/dump.0.txt" reference -dumps "$work/pipes/dump.*.txt" -dump_dt 0.1 \
  -mesh_cells 2,1,2 -o "$work/ref"
refused "$pipe" "$fifo" build "${common[@]/$work\/dump\/times.txt/$fifo}" -o "$work/b.h5"
mkfifo "$work/pipes/frame_0.txt" "$work/pipes/frame_1.txt"
refused "$pipe" "$work/pipes/frame_0.txt" build -eulerian "$work/pipes/frame_*.txt" -dt_rec 0.01 \
  -o "$work/e.h5"
# CSV files: references, runs, ensembles' members.
printf 'time_s,delta_z_m\n0,0\n1,0.001\n' >"$work/cog.csv"
refused "$pipe" "$fifo" compare -reference "$fifo" -rcfd "$work/cog.csv"
refused "$pipe" "$fifo" compare -reference "$work/cog.csv" -rcfd "$fifo"
refused "$pipe" "$fifo" calibrate -reference "$fifo" -db "$db" -output_dir "$work/cal"

# Nothing is refused that is a regular file reached through a symbolic link.
ln -s "$db" "$work/link.h5"
if timeout 60 "$rcfd" "${run[@]}" -db "$work/link.h5" >/dev/null 2>"$work/err.txt"; then ok; else
  fail "a database through a symbolic link: $(cat "$work/err.txt")"
fi

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
