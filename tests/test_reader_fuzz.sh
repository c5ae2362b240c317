#!/usr/bin/env bash
# A seeded fuzz pass over rcfd's readers (the options have test_option_fuzz): particle
# snapshots, snapshot times, Eulerian frames, CSV references, init files, path files and
# checkpoints, each made valid by rcfd itself, then damaged -- cut at a random byte, a
# random byte overwritten, a garbage line inserted -- and read again.  Every read must
# either succeed (exit 0: the damage left a valid input) or exit 1 with one line
# "rcfd CMD: error: ..." naming the damaged file; never a signal, a traceback or a hang
# (each call runs under timeout: a hang is a failure).
# usage: test_reader_fuzz.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR   (env FUZZ_SEED, FUZZ_TRIES)
set -u
rcfd=$1
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
RANDOM=${FUZZ_SEED:-20261202}
tries=${FUZZ_TRIES:-4}
write_two_particle_dumps
cd "$work" || exit 1

# damage IN OUT: OUT is IN cut, with one byte overwritten, or with a garbage line inserted.
garbage=("nan nan nan" "1e999,2" "-" "ITEM: ATOMS" "0,0,0,0,0,0,0,0" $'\x01\x02\xff' "#" "" "9999999999999999999999")
damage() {
  local in=$1 out=$2 size
  size=$(stat -c %s "$in")
  case $((RANDOM % 3)) in
  0) head -c $(((RANDOM * 32768 + RANDOM) % size)) "$in" >"$out" ;;
  1)
    cp "$in" "$out"
    printf "\\x$(printf %02x $((RANDOM % 256)))" |
      dd of="$out" bs=1 seek=$(((RANDOM * 32768 + RANDOM) % size)) conv=notrunc status=none
    ;;
  2)
    local lines at
    lines=$(wc -l <"$in")
    at=$((RANDOM % (lines + 1)))
    { head -n "$at" "$in"; printf '%s\n' "${garbage[RANDOM % ${#garbage[@]}]}"; tail -n +$((at + 1)) "$in"; } >"$out"
    ;;
  esac
}

# read_back LABEL FILE CMD ARGS...: succeeds, or fails with one line naming FILE.
read_back() {
  local label=$1 file=$2 rc lines
  shift 2
  timeout 30 "$rcfd" "$@" >/dev/null 2>err.txt
  rc=$?
  lines=$(grep -c . err.txt)
  if [ $rc -eq 124 ]; then
    fail "$label: rcfd $*: no answer in 30 s (a hang is a failure)"
  elif [ $rc -ge 128 ] || grep -q "PETSC ERROR\|terminate called\|Segmentation\|Aborted\|HDF5-DIAG" err.txt; then
    fail "$label: rcfd $*: exit $rc: $(head -3 err.txt)"
  elif [ $rc -ne 0 ] && { [ "$lines" -ne 1 ] || ! grep -q "^rcfd $1: error: " err.txt; }; then
    fail "$label: rcfd $*: exit $rc with $lines lines: $(head -3 err.txt)"
  elif [ $rc -ne 0 ] && ! grep -qF "$file" err.txt; then
    fail "$label: rcfd $*: the message does not name '$file': $(cat err.txt)"
  else
    ok
    [ $rc -eq 0 ] && accepted=$((accepted + 1))
  fi
}
accepted=0

# The valid inputs, made by rcfd: a small database and its Eulerian frames, a run's
# cog.csv, path.txt and checkpoint, and the particle database's init file.
"$rcfd" synth -synth_cells 4,2,8 -synth_frames 4 -synth_warm_up 0 -o s.h5 -quiet &&
  "$rcfd" export-eulerian s.h5 -o frames -quiet &&
  "$rcfd" build "${common[@]}" -o b.h5 -init_out init.h5 -quiet &&
  "$rcfd" run -db s.h5 -t_end 0.03 -checkpoint_every 0.02 -output_dir run -quiet -plot false -fields false ||
  { echo "FAIL: making the valid inputs"; exit 1; }
frames=(frames/*)
run=(run -db s.h5 -t_end 0.03 -output_dir out -quiet -plot false -fields false)

for ((k = 0; k < tries; ++k)); do
  # Particle snapshots (LAMMPS text) and their times.
  mkdir -p bad && rm -f bad/*
  cp dump/dump.*.txt bad/
  damage dump/dump.1.txt bad/dump.1.txt
  read_back "snapshot" "bad/dump.1.txt" build -dumps "bad/dump.*.txt" -times dump/times.txt -mesh_cells 2,1,2 -o x.h5
  damage dump/times.txt bad/times.txt
  read_back "times" "bad/times.txt" build -dumps "dump/dump.*.txt" -times bad/times.txt -mesh_cells 2,1,2 -o x.h5
  # One Eulerian frame of the set.
  rm -rf badframes && cp -r frames badframes
  f=${frames[RANDOM % ${#frames[@]}]}
  damage "$f" "bad${f}"
  read_back "Eulerian frame" "bad${f}" build -eulerian "badframes/*" -dt_rec 0.005 -o x.h5
  # A CSV reference.
  damage run/cog.csv bad/cog.csv
  read_back "reference CSV" "bad/cog.csv" compare -reference bad/cog.csv -rcfd run/cog.csv -score_window 0,0.03
  # A path file to replay.
  damage run/path.txt bad/path.txt
  read_back "path file" "bad/path.txt" "${run[@]}" -path_type recorded -path_file bad/path.txt
  # HDF5: the init file and the checkpoint.
  damage init.h5 bad/init.h5
  read_back "init file" "bad/init.h5" run -db b.h5 -init file -init_file bad/init.h5 -fractions_diameters 1e-3,2e-3 \
    -fractions_mass_shares 0.5,0.5 -t_end 0.2 -output_dir out -quiet -plot false -fields false
  damage run/checkpoint.h5 bad/checkpoint.h5
  read_back "checkpoint" "bad/checkpoint.h5" "${run[@]}" -restart bad/checkpoint.h5
  rm -rf out x.h5
done
echo "$passed passed ($accepted of them read as valid), $failures failed"
[ $failures -eq 0 ]
