#!/usr/bin/env bash
# What quantised shift weights (rcfd coarsen -weights B) do to the answer: for B = 8, 12, 16, the
# mass consistency T_k a_k = a_k+1 (rcfd info), the largest relative change of a fraction's mass,
# and the difference of Delta z(t) and of the fractions' z_CoG from the full-precision run, on the
# default bed (penta, 5 s, drift as the case default) and, if its reference is there, on
# dpm-bi-narrow (B-kd9.4e3 of cases/dpm-bi-narrow/run.sh, with its Eq. 7 score against CFD-DEM).
# usage: bench/quantised_weights.sh [BUILD_DIR]   (env: CASES, default "default dpm-bi-narrow")  Prints a table and writes bench/results/quantised_weights.md
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
rcfd=$build/rcfd
work=${WORK:-/tmp/rcfd-quantised}
ref=${REFERENCE:-../shared/reference/dpm-bi-narrow}
mkdir -p "$work" bench/results
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
penta=(-fractions_diameters 1.783e-3,1.998e-3,2.284e-3,2.855e-3,3.426e-3 -fractions_mass_shares 0.100,0.205,0.445,0.150,0.100)
[ -s "$work/default.h5" ] || "$rcfd" synth -o "$work/default.h5" -quiet
# diff FULL QUANT: largest |Delta z| difference / peak Delta z, largest z_CoG difference (m), largest mass change
diffs() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
def rows(p):
    with open(p) as f: return list(csv.DictReader(f))
a, b = rows(sys.argv[1]), rows(sys.argv[2])
dz = max(abs(float(x['delta_z_m']) - float(y['delta_z_m'])) for x, y in zip(a, b))
peak = max(float(x['delta_z_m']) for x in a)
cogs = [k for k in a[0] if k.startswith('z_cog_d')]
cog = max(abs(float(x[k]) - float(y[k])) for x, y in zip(a, b) for k in cogs)
masses = [k for k in b[0] if k.startswith('mass_')]
m = max(abs(float(b[-1][k]) - float(b[0][k])) / float(b[0][k]) for k in masses)
print(f"{dz / peak:.2e} | {cog:.2e} | {m:.1e}")
PY
}
{
  echo "# quantised shift weights, $(date -u +%Y-%m-%dT%H:%MZ)"
  echo
  echo "| database | weights | compact frames MB | max rel. mass consistency residual | max |ΔΔz| / peak Δz | max |Δz_CoG,i| m | largest rel. mass change |"
  echo "|---|---|---|---|---|---|---|"
  cases=(${CASES:-default dpm-bi-narrow})
  [ -d "$ref/dump" ] || cases=("${cases[@]/dpm-bi-narrow/}")
  for c in "${cases[@]}"; do
    if [ $c = default ]; then
      db=$work/default.h5 opts=("${penta[@]}" -t_end 5)
    else
      if [ ! -s "$work/dpm.h5" ]; then
        "$rcfd" build -dumps "$ref/dump/dump.*.gz" -times "$ref/dump/times.txt" -mesh_cells 16,2,60 \
          -o "$work/dpm.h5" -init_out "$work/dpm-init.h5" -quiet
      fi
      db=$work/dpm.h5 opts=(-options_file cases/dpm-bi-narrow/case.yaml -init_file "$work/dpm-init.h5" -drift_kd 9.4e3)
    fi
    for bits in 0 16 12 8; do
      q=$db
      if [ $bits != 0 ]; then
        q=$work/$c-q$bits.h5
        [ -s "$q" ] || "$rcfd" coarsen "$db" -weights $bits -o "$q" -quiet
      fi
      info=$("$rcfd" info "$q")
      mb=$(sed -n 's/.*compact frames: \([0-9.]*\) MB.*/\1/p' <<<"$info")
      res=$(sed -n 's/.*largest \([0-9.e+-]*\) over.*/\1/p' <<<"$info")
      "$rcfd" run "${opts[@]}" -db "$q" -fields 0 -plot 0 -quiet -output_dir "$work/$c-run-q$bits" >/dev/null
      if [ $bits = 0 ]; then row="— | — | —"; else row=$(diffs "$work/$c-run-q0/cog.csv" "$work/$c-run-q$bits/cog.csv"); fi
      echo "| $c | $([ $bits = 0 ] && echo double || echo "2^-$bits") | $mb | $res | $row |"
    done
  done
} | tee "bench/results/quantised_weights${CASES:+-${CASES// /-}}.md"
