#!/usr/bin/env bash
# A real full file system: a tmpfs of 320 kB mounted for the test (skipped,
# exit code 77, where mounting is not permitted).  rcfd synth into it fails
# with one sentence and leaves nothing; a run whose fields fill it stops on
# every rank with one sentence naming the file, keeps every file it finished
# (each readable) and leaves no temporary.
# usage: test_full_disk.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rcfd=$1 data=$3
h5print=$(dirname "$2")/h5_print
work=$(mktemp -d)
disk=$work/disk
mkdir -p "$disk"
if ! mount -t tmpfs -o size=320k tmpfs "$disk" 2>/dev/null; then
  echo "SKIP: mount -t tmpfs is not permitted here (run as root to test a full file system)"
  rmdir "$disk" "$work"
  exit 77
fi
trap 'umount "$disk"; rm -rf "$work"' EXIT
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

one_sentence() { # one_sentence LABEL RC OUTPUT: rc 1 and one line of rcfd's naming a file on the disk
  if [ "$2" -ne 1 ]; then
    fail "$1: exit code $2, expected 1 (124: hung, >128: crashed): $3"
  elif [ "$(grep -c "^rcfd [a-z]*: error: .*'$disk/[^']*': No space left on device" <<<"$3")" -ne 1 ] ||
    grep -qiE "PETSC ERROR|segmentation|signal|HDF5-DIAG" <<<"$3"; then
    fail "$1: expected one line naming a file on the full disk, got: $3"
  else
    ok
  fi
}

out=$(timeout 120 "$rcfd" synth -o "$disk/s.h5" -synth_cells 10,2,20 -synth_frames 60 2>&1)
one_sentence "synth" $? "$out"
[ -z "$(ls -A "$disk")" ] && ok || fail "synth left $(ls -A "$disk")"

for np in 1 2; do
  rm -rf "${disk:?}"/*
  out=$(timeout 120 mpiexec -n $np "$rcfd" run -db "$data/small.h5" -quiet -plot 0 -t_end 2 -fields_every 0.05 \
    -output_dir "$disk/run" 2>&1)
  one_sentence "run -n $np" $? "$out"
  left=$(find "$disk" -name '*.tmp')
  [ -z "$left" ] && ok || fail "run -n $np left $left"
  n=0
  for f in "$disk"/run/fields_*.h5; do
    "$h5print" "$f" /alpha_s >/dev/null 2>&1 && n=$((n + 1)) || fail "run -n $np: '$f' cannot be read"
  done
  [ "$n" -ge 2 ] && ok || fail "run -n $np: only $n field files before the disk was full; make the disk larger"
  # FAILED (tested in test_write_failures.sh) needs a page the full disk may not have left.
done

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
