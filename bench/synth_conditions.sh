#!/usr/bin/env bash
# The synthetic bed at several superficial gas velocities (rcfd synth -synth_superficial_velocity,
# docs/synthetic.md): one markdown table row per velocity with what the generator reports (mean bed
# height, eruptions per second, wrap mismatch), the database's bed dynamics Delta z_CoG (rcfd info),
# its recurrence (rcfd recurrence: closest pair at least K/10 apart; mean off-band entry), and a
# bi-wide run (the bubbling-bi-wide case, T_END s, replay): the small and large fractions' distance
# Delta z and the run's bed dynamics.
#
#   bench/synth_conditions.sh [U...]        default: 0.9 1.1 1.3; "default" is the bed without the option
#
# Environment: RCFD (default build/rcfd), T_END (5), WORK (/tmp/rcfd-synth-conditions, removed
# unless KEEP=1), SYNTH (extra rcfd synth options; default "-synth_nucleation steady", the stationary bed;
# SYNTH= gives the default Poisson bed).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
t_end=${T_END:-5}
work=${WORK:-/tmp/rcfd-synth-conditions}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mkdir -p "$work"
[ "${KEEP:-0}" = 1 ] || trap 'rm -rf "$work"' EXIT
[ $# -gt 0 ] || set -- 0.9 1.1 1.3

echo "| u_sup [m/s] | mean bed height [m] | eruptions [1/s] | wrap mismatch | Δz_CoG database [mm] | closest pair ≥ K/10 apart | mean R off-band | Δz bi-wide at ${t_end} s [mm] | Δz_CoG bi-wide run [mm] |"
echo "|---|---|---|---|---|---|---|---|---|"
for u in "$@"; do
  db=$work/bed-$u.h5
  knob=()
  [ "$u" = default ] || knob=(-synth_superficial_velocity "$u")
  # shellcheck disable=SC2086
  synth=$("$rcfd" synth -o "$db" "${knob[@]}" ${SYNTH-"-synth_nucleation steady"} | grep -v '^  frame')
  frames=$(echo "$synth" | sed -n 's/.*: \([0-9]*\) frames of.*/\1/p')
  dt=$(echo "$synth" | sed -n 's/.* every \([0-9.e-]*\) s;.*/\1/p')
  height=$(echo "$synth" | sed -n 's/.*mean bed height \([0-9.]*\) m.*/\1/p')
  erupted=$(echo "$synth" | sed -n 's/.*, \([0-9]*\) bubbles erupted.*/\1/p')
  wrap=$(echo "$synth" | sed -n 's/.*wrap mismatch \([0-9.]*\) %.*/\1/p')
  dzdb=$("$rcfd" info "$db" | sed -n 's/.*Delta z_CoG = mean |z_CoG - mean| = \([0-9.e-]*\) m.*/\1/p')
  closest=$("$rcfd" recurrence "$db" | sed -n 's/.*closest pair at least K\/10 apart: \([0-9.e-]*\).*/\1/p')
  offband=$(awk -F, -v K="$frames" '!/^#/ { i = NR - 2; for (j = 1; j <= NF; ++j) { d = i - (j - 1); if (d < 0) d = -d
      if (d >= K / 10) { s += $j; n++ } } } END { printf "%.3f", s / n }' "${db%.h5}-recurrence.csv")
  "$rcfd" run -options_file "$root/cases/bubbling-bi-wide/case.yaml" -db "$db" -t_end "$t_end" -bed_dynamics \
    -output_dir "$work/run-$u" -fields false -plot false -quiet >/dev/null
  dz=$(tail -n 1 "$work/run-$u/cog.csv" | cut -d, -f5)
  dzrun=$(awk -F, 'NR == 2 { print $3 }' "$work/run-$u/bed_dynamics.csv")
  awk -v u="$u" -v h="$height" -v e="$erupted" -v K="$frames" -v dt="$dt" -v w="$wrap" -v a="$dzdb" \
    -v c="$closest" -v o="$offband" -v z="$dz" -v r="$dzrun" 'BEGIN {
      printf "| %s | %s | %.1f | %s %% | %.2f | %s | %s | %.1f | %.2f |\n", u, h, e / (K * dt), w, 1e3 * a, c, o,
        1e3 * z, 1e3 * r }'
done
