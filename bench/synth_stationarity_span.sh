#!/usr/bin/env bash
# Is a synthetic bed stationary, and how long a span meets issue 15's 2 % for the halves?
# Generates long per-frame series of the bed (rcfd synth -synth_series_only: the bed without
# its shifts, about 12 ms of CPU a frame), then bench/synth_stationarity_span.py measures the
# integrated autocorrelation time of the bed height and z_CoG, cuts the series into spans of
# increasing length and prints, per span, the rms of the halves' differences against the
# standard error expected from the autocorrelation and the one rcfd synth prints, and the span
# at which 2 % is expected.  See docs/synthetic.md, "Stationarity over the recorded span".
#
#   bench/synth_stationarity_span.sh [SYNTH OPTIONS...]     e.g. -synth_nucleation steady
#
# Environment: RCFD (default build/rcfd), FRAMES (frames per seed, 24000 = 120 s), SEEDS ("1 2"),
# SPANS (span lengths in frames, "150,300,600,1200,2400,4800,9600"), LABEL (name of the result,
# default from the options), OUT (bench/results/synth_stationarity_span-LABEL.md), WORK (directory
# for the series LABEL-seedS.csv, default /tmp/rcfd-synth-span; kept, so a second call with the same
# options reuses a series of at least FRAMES frames, all of it, unless FRESH=1).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
frames=${FRAMES:-24000}
label=${LABEL:-$(echo "${*:-default}" | tr -s ' ' '_' | tr -d '-')}
out=${OUT:-$root/bench/results/synth_stationarity_span-$label.md}
work=${WORK:-/tmp/rcfd-synth-span}
mkdir -p "$work" "$(dirname "$out")"

series=()
for seed in ${SEEDS:-1 2}; do
  file="$work/$label-seed$seed.csv"
  if [ "${FRESH:-0}" = 1 ] || [ ! -s "$file" ] || [ "$(($(wc -l <"$file") - 1))" -lt "$frames" ]; then
    start=$(date +%s)
    "$rcfd" synth "$@" -synth_seed "$seed" -synth_frames "$frames" -synth_series "$file" -synth_series_only -quiet
    echo "rcfd synth $* -synth_seed $seed -synth_frames $frames: $(($(date +%s) - start)) s" >&2
  fi
  series+=("$file")
done

{
  echo "# bench/synth_stationarity_span.sh $* (FRAMES=$frames SEEDS=\"${SEEDS:-1 2}\"), $(date -u +%Y-%m-%d)"
  echo
} > "$out.tmp"
python3 "$root/bench/synth_stationarity_span.py" --spans "${SPANS:-150,300,600,1200,2400,4800,9600}" \
  --markdown "$out.body" "${series[@]}"
cat "$out.body" >> "$out.tmp" && rm -f "$out.body" && mv "$out.tmp" "$out"
echo "Wrote $out" >&2
