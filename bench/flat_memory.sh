#!/usr/bin/env bash
# Memory and file sizes against run length: stitched runs of 200, 2,000 and
# 20,000 s (40,000 to 4,000,000 steps) on a small database (10 x 2 x 20
# cells, 60 frames) with -pipeline shift,carry, a row of cog.csv every 100
# steps and four checkpoints per run.  Peak memory (the run's "peak memory"
# line, largest rank) and the checkpoint's size must not grow with the run's
# length; cog.csv and path.txt grow, as files of rows do.  With OLD_RCFD=path
# the same runs of another rcfd binary are measured as well (the table in
# docs/performance.md compares the rcfd before the time series left memory).
# Prints a table and writes it to bench/results/flat_memory.md (about 2 min).
# usage: bench/flat_memory.sh [BUILD_DIR] [TIMES...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
times=("$@")
[ ${#times[@]} -gt 0 ] || times=(200 2000 20000)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/rcfd" synth -o "$work/small.h5" -synth_cells 10,2,20 -synth_frames 60 -quiet
mkdir -p bench/results
out=bench/results/flat_memory.md
binaries=("$build/rcfd")
[ -n "${OLD_RCFD:-}" ] && binaries+=("$OLD_RCFD")
{
  echo "# memory and file sizes against run length, $(date -u +%Y-%m-%dT%H:%MZ), 1 rank"
  echo
  echo "| rcfd | simulated [s] | steps | wall [s] | peak memory [MB] | checkpoint.h5 [kB] | cog.csv [kB] | path.txt [kB] |"
  echo "|---|---|---|---|---|---|---|---|"
} >"$out"
for rcfd in "${binaries[@]}"; do
  for t in "${times[@]}"; do
    dir="$work/run-$t"
    rm -rf "$dir"
    start=$(date +%s.%N)
    log=$("$rcfd" run -db "$work/small.h5" -pipeline shift,carry -path_type random -path_seed 5 \
      -t_end "$t" -monitor_every 100 -checkpoint_every "$(awk -v t="$t" 'BEGIN { print t / 4 }')" -fields 0 \
      -plot 0 -progress_interval 1e9 -output_dir "$dir" 2>&1)
    end=$(date +%s.%N)
    peak=$(sed -n 's/.*peak memory \([0-9.]*\) MB.*/\1/p' <<<"$log")
    steps=$(sed -n 's/^Done: \([0-9]*\) steps.*/\1/p' <<<"$log")
    kb() { awk -v b="$(stat -c %s "$1")" 'BEGIN { printf "%.1f", b / 1024 }'; }
    printf '| %s | %s | %s | %.1f | %s | %s | %s | %s |\n' "$rcfd" "$t" "$steps" \
      "$(awk -v a="$start" -v b="$end" 'BEGIN { print b - a }')" "$peak" "$(kb "$dir/checkpoint.h5")" \
      "$(kb "$dir/cog.csv")" "$(kb "$dir/path.txt")" | tee -a "$out"
  done
done
echo "written to $out"
