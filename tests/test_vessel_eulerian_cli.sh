#!/usr/bin/env bash
# rcfd build -eulerian -vessel ... (docs/vessels.md): frames given on the box, the database on the
# vessel's cells.  Hand-made frames of a bed turning about the axis of a cylinder (R = 4.7 cm in a
# 10 x 10 x 4 cm box of 1 cm cells; solid in the cells centred within 4.4 cm, some of them cut by the
# wall): the database holds the cylinder's cells with the frames' alpha_s, its shifts are
# mass-consistent on the cells' inside volumes (T (V a_0) = V a_1), a run on it keeps its mass and
# gives the same answers on 1 and 2 ranks; tracers bounce off the vessel's wall; a frame with solid
# outside the vessel is refused with one sentence naming the file and the cell.
# usage: test_vessel_eulerian_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/vessel_script_setup.sh"

# frame FILE ALPHA_S OUTSIDE_ALPHA_S: x y z alpha Ux Uy Uz Usx Usy Usz per box cell; solid turning at
# 5 rad/s (a quarter cell per dt_rec at the rim) where the centre is within 4.4 cm of the axis.
frame() {
  awk -v as="$2" -v out="$3" 'BEGIN { for (k = 0; k < 4; ++k) for (j = 0; j < 10; ++j) for (i = 0; i < 10; ++i) {
      x = 0.005 + 0.01 * i; y = 0.005 + 0.01 * j; z = 0.005 + 0.01 * k; dx = x - 0.05; dy = y - 0.05
      if (dx * dx + dy * dy < 0.044 * 0.044) printf "%g %g %g %.17g 0 0 0 %.17g %.17g 0\n", x, y, z, 1 - as, -5 * dy, 5 * dx
      else printf "%g %g %g %.17g 0 0 0 0 0 0\n", x, y, z, 1 - ((i == 0 && j == 0 && k == 1) ? out : 0) } }' >"$1"
}
mkdir -p "$work/good" "$work/bad"
frame "$work/good/frame_0.txt" 0.4 0
frame "$work/good/frame_1.txt" 0.4 0
frame "$work/good/frame_2.txt" 0.4 0
vessel=(-vessel cylinder -vessel_axis 0.05,0.05 -vessel_radius 0.047 -mesh_lo 0,0,0 -mesh_hi 0.1,0.1,0.04)
"$rcfd" build -eulerian "$work/good/frame_*.txt" -dt_rec 0.01 "${vessel[@]}" -o "$work/cyl.h5" -quiet \
  -scaling_tolerance 1e-10
[ "$("$h5print" "$work/cyl.h5" /mesh kind string)" = masked_box ] || fail "the Eulerian database's mesh is not masked_box"
"$h5print" "$work/cyl.h5" /mesh vessel string | grep -q '^+cylinder(0.05,0.05,0.047) samples 8$' ||
  fail "the vessel is not recorded: $("$h5print" "$work/cyl.h5" /mesh vessel string)"
"$h5print" "$work/cyl.h5" /mesh/cell_volumes > "$work/vol.txt"
cells=$(wc -l < "$work/vol.txt")
[ "$cells" -lt 400 ] && [ "$cells" -gt 250 ] || fail "the cylinder has $cells of the box's 400 cells"
"$h5print" "$work/cyl.h5" /frames/000000/alpha_s > "$work/a0.txt"
"$h5print" "$work/cyl.h5" /frames/000001/alpha_s > "$work/a1.txt"
[ "$(wc -l < "$work/a0.txt")" -eq "$cells" ] || fail "alpha_s is not one value per cell of the vessel"
# Cut cells hold solid: the test is about their inside volumes.
cut=$(paste "$work/vol.txt" "$work/a0.txt" | awk '$1 < 0.999e-6 && $2 > 0 { n++ } END { print n + 0 }')
[ "$cut" -ge 8 ] || fail "only $cut cut cells hold solid"
awk '$1 != 0 && $1 != 0.4 { bad = 1 } END { exit bad }' "$work/a0.txt" || fail "alpha_s is not the frames' (0.4 or 0)"
# T (V a_0) = V a_1 on the inside volumes, to the scaling tolerance.
for f in row_ptr col val; do "$h5print" "$work/cyl.h5" /frames/000000/shift_$f | tr ' ' '\n' | grep . > "$work/$f.txt"; done
awk 'FILENAME == ARGV[1] { v[FNR - 1] = $1; next } FILENAME == ARGV[2] { a0[FNR - 1] = $1; next }
  FILENAME == ARGV[3] { a1[FNR - 1] = $1; next } FILENAME == ARGV[4] { rp[FNR - 1] = $1; n = FNR - 1; next }
  FILENAME == ARGV[5] { col[FNR - 1] = $1; next } { val[FNR - 1] = $1 }
  END { for (r = 0; r < n; ++r) { s = 0; for (e = rp[r]; e < rp[r + 1]; ++e) s += val[e] * v[col[e]] * a0[col[e]]
          d = s - v[r] * a1[r]; err += d < 0 ? -d : d; tot += v[r] * a1[r] }
        printf "T (V a_0) - V a_1: %.3g of the mass\n", err / tot; exit !(err / tot < 1e-8 && n == '"$cells"') }' \
  "$work/vol.txt" "$work/a0.txt" "$work/a1.txt" "$work/row_ptr.txt" "$work/col.txt" "$work/val.txt" ||
  fail "the shift is not mass-consistent on the inside volumes"

# Tracers bounce off the vessel's wall: solid in every cell of the cylinder (cut cells too) turning at
# 5 rad/s, each tracer with its cell's velocity, so that those near the wall step across it. Mirrored
# back in, none ends outside to be moved to the nearest cell with solid (153 of 5632 were before, and
# 1135 of 45,056 at 64 per cell), and the traced shift misses its target by less (0.0176 against
# 0.0338 at 64 tracers per cell).
"$h5print" "$work/cyl.h5" /mesh/box_cell > "$work/inside.txt"
mkdir -p "$work/full"
for k in 0 1 2; do
  awk 'FILENAME == ARGV[1] { inside[$1] = 1; next }
    END { for (k = 0; k < 4; ++k) for (j = 0; j < 10; ++j) for (i = 0; i < 10; ++i) {
      x = 0.005 + 0.01 * i; y = 0.005 + 0.01 * j; z = 0.005 + 0.01 * k
      if ((i + 10 * j + 100 * k) in inside) printf "%g %g %g 0.6 0 0 0 %.17g %.17g 0\n", x, y, z, -5 * (y - 0.05), 5 * (x - 0.05)
      else printf "%g %g %g 1 0 0 0 0 0 0\n", x, y, z } }' "$work/inside.txt" >"$work/full/frame_$k.txt"
done
for n in 8 64; do
  "$rcfd" build -eulerian "$work/full/frame_*.txt" -dt_rec 0.01 "${vessel[@]}" -o "$work/full$n.h5" -tracers_per_cell $n \
    > "$work/full$n.txt"
  grep -q 'tracers moved out of cells empty at t_k+1 0,' "$work/full$n.txt" ||
    { grep tracing "$work/full$n.txt"; fail "tracers crossed the vessel's wall ($n per cell)"; }
done
"$h5print" "$work/full64.h5" /extra/eulerian_residuals | awk 'NR == 1 { exit !($1 < 0.025) }' ||
  fail "the traced shift misses its target by $("$h5print" "$work/full64.h5" /extra/eulerian_residuals | head -1) (0.0176 expected)"

# A run on it: mass kept, 1 rank == 2 ranks.
run=(-db "$work/cyl.h5" -t_end 0.1 -quiet -fields 0 -plot 0 -fractions_diameters 2e-3,3e-3 -fractions_mass_shares 0.5,0.5
  -init layered -monitor_digits 17 -halves)
run_on_ranks "the Eulerian cylinder" "${run[@]}"

# Solid in a box cell outside the cylinder: refused, naming the file and the cell.
frame "$work/bad/frame_0.txt" 0.4 0
frame "$work/bad/frame_1.txt" 0.4 0.3
if "$rcfd" build -eulerian "$work/bad/frame_*.txt" -dt_rec 0.01 "${vessel[@]}" -o "$work/bad.h5" > "$work/bad.txt" 2>&1; then
  fail "a frame with solid outside the vessel was built"
fi
grep -q "Eulerian frame '$work/bad/frame_1.txt' has solid (alpha_s = 0.3) in mesh cell (0, 0, 1) centred at (0.005, 0.005, 0.015), which lies outside the vessel" "$work/bad.txt" ||
  { cat "$work/bad.txt"; fail "the refusal does not name the file and the cell"; }
[ ! -e "$work/bad.h5" ] || fail "a refused build left a database"
echo "Eulerian frames in a cylinder: $cells cells, $cut cut cells with solid; run and refusal ok"
