#!/usr/bin/env bash
# Checksums of cog.csv of the four cases, and of the frame path and its jumps (path.txt, jumps.csv),
# to show that a change which should not touch the arithmetic (a move of files, a new API around
# the same kernels) gives the same bits.
#
#   bench/case_checksums.sh [OUT]          writes OUT (default bench/results/case_checksums.txt)
#   bench/case_checksums.sh --check FILE   runs again and compares with FILE (exit 1 on a change)
#
# Each case runs on 1 rank (2 ranks add their own round-off order) for a shortened time, from a
# freshly made default database (build/case-checksums/), with fields and figures off.
# Environment: RCFD (default build/rcfd), REFERENCE (default ../shared/reference/dpm-bi-narrow),
# T_END (simulated seconds per bubbling case, default 2).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
ref=${REFERENCE:-$root/../shared/reference/dpm-bi-narrow}
t_end=${T_END:-2}
work=$root/build/case-checksums
check=""
out=$root/bench/results/case_checksums.txt
if [ "${1:-}" = "--check" ]; then
  check=${2:?"--check needs the file of recorded checksums"}
  out=$work/now.txt
elif [ -n "${1:-}" ]; then
  out=$1
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$work"

"$rcfd" synth -o "$work/default-bed.h5" -quiet
sums=()
# cog.csv as "SUM  case" (as recorded from the start), the path's files as "SUM  case/FILE".
record() {
  sums+=("$(sha256sum "$work/$1/cog.csv" | cut -d' ' -f1)  $1")
  for f in path.txt jumps.csv; do
    [ -e "$work/$1/$f" ] && sums+=("$(sha256sum "$work/$1/$f" | cut -d' ' -f1)  $1/$f")
  done
  return 0
}
for name in bubbling-bi-narrow bubbling-bi-wide bubbling-penta-narrow; do
  "$rcfd" run -options_file "$root/cases/$name/case.yaml" -db "$work/default-bed.h5" -t_end "$t_end" \
    -output_dir "$work/$name" -fields false -plot false -quiet
  record "$name"
done

input=(-dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60)
"$rcfd" build "${input[@]}" -window 0,200 -o "$work/dpm-db.h5" -init_out "$work/dpm-init.h5" -quiet
"$rcfd" run -options_file "$root/cases/dpm-bi-narrow/case.yaml" -db "$work/dpm-db.h5" \
  -init_file "$work/dpm-init.h5" -t_end 0.99 -output_dir "$work/dpm-bi-narrow" -plot false -quiet
record dpm-bi-narrow

printf '%s\n' "${sums[@]}" | tee "$out"
if [ -n "$check" ]; then
  if diff -u "$check" "$out"; then
    echo "same bits as $check"
  else
    echo "the cases' files differ from $check" >&2
    exit 1
  fi
fi
