#!/usr/bin/env bash
# The three situations of the paper's Fig. 7 on the default database, from any directory:
#   cases/granulator/run.sh [OUTPUT_DIR]      (default: rcfd-output/granulator)
# Environment: RCFD (default build/rcfd), DB (default build/default-bed.h5, made by rcfd synth if
# missing), NP (MPI ranks, default 2).  Runs case.yaml three times:
#   still/      shift,drift,carry                      no growth, no through-flow
#   growth/     + growth                               m_g = 1 kg/s, c = 0.01
#   granulator/ + growth, feed, discharge               and m_f = 0.2 kg/s in and out
#   spray-dry/  the granulator with liquid sprayed and dried (spray-dry.yaml, docs/scalars.md)
# and draws each run's figures (-plot), the halves of the first three side by side (Fig. 7), and
# moisture and temperature against size and height (spray-dry/scalar_profiles.png).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
rcfd=${RCFD:-$root/build/rcfd}
db=${DB:-$root/build/default-bed.h5}
out=${1:-$root/rcfd-output/granulator}
np=${NP:-2}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# build/ is absent in a checkout used with an installed rcfd (RCFD=...).
[ -s "$db" ] || { mkdir -p "$(dirname "$db")" && "$rcfd" synth -o "$db" -quiet; }
runs=(mpiexec -n "$np" "$rcfd" run -options_file "$root/cases/granulator/case.yaml" -db "$db")
growth=(-growth_rate 1 -growth_transfer_fraction 0.01)
flow=(-feed_rate 0.2 -discharge_rate 0.2 -discharge_sample_interval 1)
echo "== no growth, no through-flow"
"${runs[@]}" -pipeline shift,drift,carry -output_dir "$out/still"
echo "== growth only"
"${runs[@]}" -pipeline shift,drift,carry,growth "${growth[@]}" -growth_view -output_dir "$out/growth"
echo "== growth with through-flow"
"${runs[@]}" -pipeline shift,drift,carry,growth,feed,discharge "${growth[@]}" "${flow[@]}" -growth_view \
  -feed_view -discharge_view -output_dir "$out/granulator"
echo "== growth with through-flow, spray and drying"
"${runs[@]}" -options_file "$root/cases/granulator/spray-dry.yaml" -pipeline shift,drift,carry,growth,feed,discharge \
  "${growth[@]}" "${flow[@]}" -output_dir "$out/spray-dry"
python=${RCFD_PYTHON:-/usr/bin/python3}
if "$python" -c "import matplotlib" 2>/dev/null; then
  "$python" "$root/src/cli/figures/granulation_halves.py" "$out"/{still,growth,granulator}/halves.csv \
    --labels "no growth, no through-flow;growth only;growth with through-flow" -o "$out/fig7-halves.png" \
    --title "bottom and top halves, mean over 50-60 s"
  "$python" "$root/src/cli/figures/scalar_profiles.py" "$out/spray-dry/scalar_profiles.csv" \
    --scalars moisture,temperature --product "$out/spray-dry/steady_state.csv" -o "$out/spray-dry/scalar_profiles.png" \
    --title "spray and dry, plug-flow gas: mean over 50-60 s"
fi
echo "Wrote $out/{still,growth,granulator,spray-dry}/ (halves, cog, product, mass_account; scalars) and $out/fig7-halves.png"
