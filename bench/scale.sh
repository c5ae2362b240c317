#!/usr/bin/env bash
# Memory, load time and step time of a large synthetic bed with compact frames, at 1 and 2 ranks.
# usage: bench/scale.sh [BUILD_DIR] [CELLS nx,ny,nz] [FRAMES]   (default 100,25,400 and 100: about
# 1 M cells of 5 mm, settled bed 40 % of the height).  Prints a table and writes
# bench/results/scale-<cells>.md.  The database goes to $WORK (default /tmp/rcfd-scale).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
cells=${2:-100,25,400}
frames=${3:-100}
work=${WORK:-/tmp/rcfd-scale}
rcfd=$build/rcfd
mkdir -p "$work" bench/results
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
IFS=, read -r nx ny nz <<<"$cells"
length=$(awk -v x=$nx -v y=$ny -v z=$nz 'BEGIN { printf "%g,%g,%g", x * 0.005, y * 0.005, z * 0.005 }')
bed=$(awk -v z=$nz 'BEGIN { printf "%g", 0.4 * z * 0.005 }')
db=$work/bed-${nx}x${ny}x${nz}-$frames.h5
if [ ! -s "$db" ]; then
  t0=$(date +%s.%N)
  "$rcfd" synth -o "$db" -synth_cells "$cells" -synth_length "$length" -synth_bed_height "$bed" \
    -synth_frames "$frames" -quiet
  echo "synth: $(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.0f", b - a }') s, $(du -m "$db" | cut -f1) MB file" >&2
fi
out=bench/results/scale-${nx}x${ny}x${nz}.md
{
  echo "# scale, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load average $(cut -d' ' -f1 /proc/loadavg)"
  echo
  echo "Synthetic bed $nx x $ny x $nz cells of 5 mm, $frames frames; rcfd run -pipeline shift, 2 fractions, 100 steps."
  echo
  echo "| ranks | cells | peak MB/rank | compact frames MB (rank 0) | ghost cells (rank 0) | load s (wall) | step ms (wall) |"
  echo "|---|---|---|---|---|---|---|"
  for np in 1 2; do
    t0=$(date +%s.%N)
    log=$(mpiexec -n $np "$rcfd" run -db "$db" -t_end 0.5 -pipeline shift -fields 0 -plot 0 -monitor_every 100 \
      -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -shift_view -output_dir "$work/run$np" \
      -progress_interval 1000)
    t1=$(date +%s.%N)
    wall=$(sed -n 's/.* in \([0-9.e+-]*\) s wall.*/\1/p' <<<"$log")
    steps=$(sed -n 's/^Done: \([0-9]*\) steps.*/\1/p' <<<"$log")
    mem=$(sed -n 's/.*peak memory \([0-9]*\) MB.*/\1/p' <<<"$log")
    mb=$(sed -n 's/.*compact frames \([0-9.]*\) MB.*/\1/p' <<<"$log" | head -1)
    ghosts=$(sed -n 's/.*, \([0-9]*\) ghost cells.*/\1/p' <<<"$log" | head -1)
    load=$(awk -v a="$t0" -v b="$t1" -v w="$wall" 'BEGIN { printf "%.1f", b - a - w }')
    step=$(awk -v w="$wall" -v s="$steps" 'BEGIN { printf "%.2f", 1e3 * w / s }')
    echo "| $np | $((nx * ny * nz)) | $mem | $mb | $ghosts | $load | $step |"
  done
} | tee "$out"
echo "written to $out"
