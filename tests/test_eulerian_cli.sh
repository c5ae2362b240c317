#!/usr/bin/env bash
# rcfd build -eulerian and rcfd export-eulerian:
#  1. a hand-made uniform field (Us = (0, 0, u), u dt_rec = half a cell) gives
#     the hand-computed shift: half of each cell stays, half moves up, the top
#     layer keeps everything; exporting that database gives Us back;
#  2. round trip of a small synthetic database (exact shifts from parcels):
#     export its frames, trace them back, and check the traced database
#     loads, is column-stochastic, is mass-consistent below the scaling
#     tolerance, stays within measured bounds of the exact shifts, and
#     replays to a Delta z(t) within measured bounds (docs/validation.md);
#  3. bad frame files: one error line naming the file and the line.
# usage: test_eulerian_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
bin=$(dirname "$2")
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

# below "label" value bound: value is a number and value < bound.
below() {
  if [[ "$2" =~ ^-?[0-9.]+([eE][-+]?[0-9]+)?$ ]] && awk -v v="$2" -v b="$3" 'BEGIN { exit !(v + 0 < b + 0) }'; then
    ok
  else
    fail "$1: '$2' is not a number below $3"
  fi
}

# ---- 1. uniform field on 2 x 1 x 4 cells of 1 cm, alpha_s = 0.4, u = 0.5 m/s,
# dt_rec = 0.01 s: u dt_rec = 5 mm = half a cell.  Cell (i, k) = i + 2 k.
# T(k, k) = 1/2 and T(k+1, k) = 1/2 for k < 3, T(3, 3) = 1; the second frame's
# alpha_s is T alpha_0 (0.2, 0.4, 0.4, 0.6 by layer), so scaling has nothing to do.
mkdir -p "$work/uniform"
frame() { # frame FILE "alpha_s per layer" Usz
  local a
  read -r -a a <<<"$2"
  for k in 0 1 2 3; do
    for i in 0 1; do
      echo "0.0${i}5 0.005 0.0${k}5 $(awk -v s="${a[$k]}" 'BEGIN { print 1 - s }') 0 0 0 0 0 $3"
    done
  done >"$1"
}
frame "$work/uniform/frame_0.txt" "0.4 0.4 0.4 0.4" 0.5
frame "$work/uniform/frame_1.txt" "0.2 0.4 0.4 0.6" 0.5
# One cell across y: its extent must be given.
uni=(-eulerian "$work/uniform/frame_*.txt" -dt_rec 0.01 -mesh_lo 0,0,0 -mesh_hi 0.02,0.01,0.04 -quiet)
if run "uniform build" "$rcfd" build "${uni[@]}" -scaling_support 0 -o "$work/uniform.h5"; then
  same "uniform row_ptr" "$("$bin/h5_print" "$work/uniform.h5" /frames/000000/shift_row_ptr)" \
    "0 1 2 4 6 8 10 12 14"
  same "uniform columns" "$("$bin/h5_print" "$work/uniform.h5" /frames/000000/shift_col)" \
    "0 1 0 2 1 3 2 4 3 5 4 6 5 7"
  same "uniform shares" "$("$bin/h5_print" "$work/uniform.h5" /frames/000000/shift_val)" \
    "0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 0.5 1 0.5 1"
  same "uniform alpha_s" "$("$bin/h5_print" "$work/uniform.h5" /frames/000000/alpha_s)" \
    "0.4 0.4 0.4 0.4 0.4 0.4 0.4 0.4"
  same "uniform mesh" "$("$bin/h5_print" "$work/uniform.h5" /mesh box_length)" "0.02 0.01 0.04"
  # Exported back, the database's velocity is the field's: u below the top, 0 at the top.
  if run "uniform export" "$rcfd" export-eulerian "$work/uniform.h5" -o "$work/uexport" -quiet; then
    same "exported Usz" "$(awk '{ print $10 }' "$work/uexport/frame_000000.txt")" \
      "0.5 0.5 0.5 0.5 0.5 0.5 0 0"
    same "exported alpha" "$(awk '{ print $4 }' "$work/uexport/frame_000000.txt")" \
      "0.6 0.6 0.6 0.6 0.6 0.6 0.6 0.6"
  fi
fi
# ---- 2. round trip of a small synthetic database.
exact=$work/small.h5 traced=$work/traced.h5
run "synth" "$rcfd" synth -synth_cells 10,4,30 -synth_length 0.05,0.02,0.15 -synth_bed_height 0.06 \
  -synth_frames 20 -o "$exact" -quiet
run "export" "$rcfd" export-eulerian "$exact" -o "$work/frames" -quiet
same "exported files" "$(ls "$work/frames" | wc -l)" "20"
run "traced build" "$rcfd" build -eulerian "$work/frames/frame_*.txt" -dt_rec 0.005 -o "$traced" -quiet
if run "info" "$rcfd" info "$traced"; then
  # rcfd info loads the database: column sums are checked there (1e-9) and
  # the largest error before rescaling is printed.
  below "column sums" "$(grep 'column sum' "$work/out.txt" | awk '{ print $NF }')" 1e-12
  below "info mass consistency" "$(grep -F 'mass consistency |' "$work/out.txt" | awk '{ print $(NF - 3) }')" 1e-6
fi
# Per frame: traced mismatch, after scaling, iterations, change of the total.
"$bin/h5_print" "$traced" /extra/eulerian_residuals | paste - - - - >"$work/residuals.txt"
same "traced frames" "$(wc -l <"$work/residuals.txt")" "19"
below "largest residual after scaling (tolerance 1e-6)" "$(awk '$2 > m { m = $2 } END { print m + 0 }' "$work/residuals.txt")" 1e-6
below "scaling reduces the mismatch" "$(awk '$2 >= $1 / 1000 { n++ } END { print n + 0 }' "$work/residuals.txt")" 1
# Traced against exact (db_compare: mass, moved, tv, residual, alpha; see its header).
if "$bin/db_compare" "$exact" "$traced" >"$work/compare.txt" 2>&1; then
  ok
  read -r _ mass moved tv residual alpha < <(grep '^max' "$work/compare.txt")
  read -r _ mmass mmoved mtv _ _ < <(grep '^mean' "$work/compare.txt")
  below "|T_traced m - T_exact m| / |m|, largest" "$mass" 1e-6
  below "alpha_s carried through ASCII" "$alpha" 1e-15
  below "mass sent elsewhere than exact, mean (measured 0.119)" "$mtv" 0.17
  below "mass sent elsewhere than exact, largest (measured 0.127)" "$tv" 0.20
  below "the exact shifts move more than that (measured 0.186)" "$mtv" "$mmoved"
else
  fail "db_compare: $(cat "$work/compare.txt")"
fi
# Replay both with two fractions and drift model B for 1 s (the exact
# database cut to the traced one's 19 frames, so that both wrap alike).
runopts=(-fractions_diameters 1.95e-3,2.82e-3 -fractions_mass_shares 0.5,0.5 -drift_model B
  -drift_kd 5e3 -t_end 1 -fields false -plot false -quiet)
if run "run exact" "$rcfd" run -db "$exact" -db_frames 0,18 "${runopts[@]}" -output_dir "$work/run-exact" &&
  run "run traced" "$rcfd" run -db "$traced" "${runopts[@]}" -output_dir "$work/run-traced" &&
  run "compare" "$rcfd" compare -reference "$work/run-exact/cog.csv" -rcfd "$work/run-traced/cog.csv" \
    -score_window 0.5,1; then
  read -r _ meandz seg rms rel _ < <(tail -1 "$work/out.txt")
  below "Delta_seg of the traced replay (measured 17.7 %)" "${seg#-}" 25
  below "RMS / peak of Delta z (measured 0.112)" "$rel" 0.16
  below "bulk mismatch at the end of the traced replay" \
    "$(tail -1 "$work/run-traced/cog.csv" | awk -F, '{ print $NF }')" 1e-4
fi

# ---- 3. bad input: one line naming the file and the line (every message of
# the reader is checked in test_eulerian_frames).
bad=$work/bad
mkdir -p "$bad"
cp "$work/uniform/frame_0.txt" "$bad/frame_0.txt"
badcase() { # badcase "expected" "sed program": frame_1 = the uniform frame_1 edited by sed
  sed "$2" "$work/uniform/frame_1.txt" >"$bad/frame_1.txt"
  expect_error "$1" build -eulerian "$bad/frame_*.txt" -dt_rec 0.01 -mesh_lo 0,0,0 \
    -mesh_hi 0.02,0.01,0.04 -o "$work/bad.h5"
}
badcase "Eulerian frame '$bad/frame_1.txt', line 3: expected 10 numbers (x y z alpha Ux Uy Uz Usx Usy Usz), found 9" \
  '3s/ 0.5$//'
badcase "Eulerian frame '$bad/frame_1.txt' has 7 cells but the mesh 2 x 1 x 4 has 8: 1 missing, the first is mesh cell (1, 0, 1)" \
  '4d'
if [ -e "$work/bad.h5" ] || [ -e "$work/bad.h5.tmp" ]; then fail "a refused build left a file behind"; else ok; fi
expect_error "no Eulerian frame file matches '$bad/nothing_*.txt'" build -eulerian "$bad/nothing_*.txt" -dt_rec 0.01
expect_error "$work/missing.h5" export-eulerian "$work/missing.h5" -o "$work/x"

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
