#!/usr/bin/env bash
# Is a synthetic bed statistically stationary over its recorded span?  Issue 15's targets:
#   - mean bed height and Delta z_CoG of the first and second half of the span within 2 %;
#   - the frame-use histogram of a 60 s random path (today's jump rule, -path_type random) within
#     a factor 2 of uniform (largest over smallest of BINS equal bins of frames).
# With each halves' difference, whether it is within 2 of the standard errors rcfd synth prints
# (the scatter a stationary bed's own correlation makes expected over the span; how it shrinks
# with the span: bench/synth_stationarity_span.sh).
# Also prints the wrap mismatch (|alpha_K - alpha_0| over the solid, from rcfd synth's report).
#
#   bench/synth_stationarity.sh [SYNTH OPTIONS...]     e.g. -synth_superficial_velocity 1.3
#
# Environment: RCFD (default build/rcfd), T_END (60), PATH_SEEDS ("1 2 3"), BINS (4), WORK (a
# directory for the database and runs, default /tmp/rcfd-synth-stationarity; removed at the end
# unless KEEP=1).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
t_end=${T_END:-60}
bins=${BINS:-4}
work=${WORK:-/tmp/rcfd-synth-stationarity}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$work"
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT

start=$(date +%s.%N)
report=$("$rcfd" synth -o "$work/bed.h5" "$@" | grep -v '^  frame')
seconds=$(echo "$(date +%s.%N) - $start" | bc)
echo "rcfd synth $* ($(printf %.1f "$seconds") s)"
echo "$report" | sed 's/^/  /'
frames=$("$rcfd" info "$work/bed.h5" | awk '/frames:/ { print $2 }')

# Halves: pass when both differences are within 2 %; and whether a difference is within two
# of the standard errors rcfd synth prints with it (what a stationary bed shows over this span).
echo "$report" | awk '/^Halves/ {
    n = 0; line = $0
    while (match(line, /\([-+0-9.]+ %, \+\/- [0-9.e+-]+ %/)) {
      part = substr(line, RSTART + 1, RLENGTH - 1); line = substr(line, RSTART + RLENGTH)
      split(part, f, " "); d[++n] = f[1] + 0; e[n] = f[4] + 0 }
    if (n != 2) { print "  halves: could not read the line \"" $0 "\""; exit 1 }
    split("bed height,Delta z_CoG", name, ",")
    for (i = 1; i <= 2; ++i)
      printf "  halves: %s %+.1f %% (%s; %s 2 standard errors of %.2g %%)\n", name[i], d[i],
        (d[i] <= 2 && d[i] >= -2) ? "within 2 %" : "NOT within 2 %",
        (d[i] <= 2 * e[i] && d[i] >= -2 * e[i]) ? "within" : "beyond", e[i] }'

for seed in ${PATH_SEEDS:-1 2 3}; do
  "$rcfd" run -db "$work/bed.h5" -t_end "$t_end" -path_type random -path_seed "$seed" -fields 0 -plot 0 \
    -quiet -output_dir "$work/run$seed" >/dev/null
  awk -v K="$frames" -v B="$bins" -v seed="$seed" '!/^#/ { n[int($1 * B / K)]++; total++ }
    END { lo = total; hi = 0; line = ""
      for (b = 0; b < B; ++b) { lo = n[b] < lo ? n[b] : lo; hi = n[b] > hi ? n[b] : hi
        line = line sprintf(" %.0f%%", 100 * n[b] / total) }
      ratio = lo > 0 ? sprintf("%.2f", hi / lo) : "inf"
      printf "  random path seed %s: frame use per %d bins of frames:%s; max/min %s (%s)\n", seed, B, line, ratio,
        (lo > 0 && hi <= 2 * lo) ? "within a factor 2" : "NOT within a factor 2" }' "$work/run$seed/path.txt"
done
