#!/usr/bin/env bash
# rcfd build -vessel from-particles (docs/vessels.md): on hand-made dumps of particles turning and
# rising inside a cylinder, the vessel is exactly the box cells a particle centre visited in some
# snapshot (with -vessel_margin M, every cell closer than M to a centre), recorded in the database
# and reported by rcfd info; the frames move mass exactly; a run on it keeps its mass and gives
# the same answers on 1 and 2 ranks; a run on it and a database of another vessel is refused;
# misplaced options are refused with one sentence.
# usage: test_vessel_particles_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/vessel_script_setup.sh"

# Five snapshots of 200 particles (radius 1 and 1.5 mm) in a cylinder R = 4.6 cm about (5, 5) cm,
# turning by 0.5 rad and shuffled in height between snapshots; a box 10 x 4 cm of 1 cm cells.
mkdir -p "$work/dump"
for k in 0 1 2 3 4; do
  awk -v k=$k 'BEGIN {
    printf "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n200\nITEM: BOX BOUNDS ff ff ff\n0 0.1\n0 0.1\n0 0.04\n", 1000 * k
    print "ITEM: ATOMS id type x y z radius"
    for (p = 1; p <= 200; ++p) { r = 0.046 * sqrt((p * 37 % 200 + 0.5) / 200); a = p * 2.39996 + 0.5 * k
      z = 0.002 + 0.03 * ((p * 13 + 7 * k * (p % 3)) % 200) / 200
      printf "%d 1 %.9f %.9f %.9f %s\n", p, 0.05 + r * cos(a), 0.05 + r * sin(a), z, (p % 2 ? "0.0015" : "0.001") } }' \
    >"$work/dump/dump.$k.txt"
done
printf '# index time\n0 0.1\n1 0.2\n2 0.3\n3 0.4\n4 0.5\n' >"$work/dump/times.txt"
build=(-dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 10,10,4 -mesh_lo 0,0,0
  -mesh_hi 0.1,0.1,0.04)

# The cells the centres visited (margin m: every cell whose nearest point is closer than m), by hand.
visited() {
  awk -v m="$1" '/^ITEM: ATOMS/ { f = 1; next } /^ITEM/ { f = 0 } f { x[0] = $3; x[1] = $4; x[2] = $5
      for (a = 0; a < 3; ++a) { lo[a] = int((x[a] - m) / 0.01); hi[a] = int((x[a] + m) / 0.01)
        if (x[a] - m < 0) lo[a] = 0; if (hi[a] > n[a] - 1) hi[a] = n[a] - 1 }
      for (k = lo[2]; k <= hi[2]; ++k) for (j = lo[1]; j <= hi[1]; ++j) for (i = lo[0]; i <= hi[0]; ++i) {
        d2 = 0; c[0] = i; c[1] = j; c[2] = k
        for (a = 0; a < 3; ++a) { g = c[a] * 0.01 - x[a]; if (x[a] - c[a] * 0.01 - 0.01 > g) g = x[a] - c[a] * 0.01 - 0.01
          if (g > 0) d2 += g * g }
        if (m == 0 ? (i == int(x[0] / 0.01) && j == int(x[1] / 0.01) && k == int(x[2] / 0.01)) : d2 < m * m)
          print i + 10 * (j + 10 * k) } }
    BEGIN { n[0] = 10; n[1] = 10; n[2] = 4 }' \
    "$work"/dump/dump.*.txt | sort -n -u
}

"$rcfd" build "${build[@]}" -vessel from-particles -o "$work/fp.h5" > "$work/build.txt"
"$h5print" "$work/fp.h5" /mesh/box_cell > "$work/cells.txt"
visited 0 > "$work/expected.txt"
cells=$(wc -l < "$work/expected.txt")
cmp -s "$work/cells.txt" "$work/expected.txt" ||
  fail "the vessel from the particles is not the $cells cells they visited: $(diff "$work/cells.txt" "$work/expected.txt" | head -5)"
[ "$cells" -gt 150 ] && [ "$cells" -lt 400 ] || fail "the particles visited $cells of the 400 cells"
[ "$("$h5print" "$work/fp.h5" /mesh kind string)" = masked_box ] || fail "the vessel's mesh is not masked_box"
"$h5print" "$work/fp.h5" /mesh vessel string | grep -q "^particles(margin 0) $cells cells mask [0-9a-f]\{16\}$" ||
  fail "the vessel is not recorded: $("$h5print" "$work/fp.h5" /mesh vessel string)"
# Whole cells: every volume is the box cell's, 1 cm^3.
awk '{ if ($1 < 0.999999e-6 || $1 > 1.000001e-6) bad = 1 } END { exit bad }' <("$h5print" "$work/fp.h5" /mesh/cell_volumes) ||
  fail "a cell of the vessel from the particles is not whole"
# Faces open, whole (1 cm^2), exactly between two visited cells that touch in the box.
pairs=$(awk '{ v[$1] = 1 } END { for (c in v) { c += 0; if (c % 10 < 9 && ((c + 1) in v)) n++
    if (int(c / 10) % 10 < 9 && ((c + 10) in v)) n++; if ((c + 100) in v) n++ } print n + 0 }' "$work/expected.txt")
[ "$("$h5print" "$work/fp.h5" /mesh/face_owner | wc -l)" -eq "$pairs" ] || fail "the vessel has not the $pairs faces between visited cells"
awk '{ s += $1 } END { exit !(s > (1 - 1e-12) * p * 1e-4 && s < (1 + 1e-12) * p * 1e-4) }' p="$pairs" \
  <("$h5print" "$work/fp.h5" /mesh/face_area) || fail "the faces between visited cells are not whole"
grep -q "Vessel from the particles (margin 0 m): $cells of the box's 400 cells" "$work/build.txt" ||
  { cat "$work/build.txt"; fail "rcfd build does not report the vessel"; }
grep -q "outside the mesh: 0 particle-snapshots" "$work/build.txt" ||
  { cat "$work/build.txt"; fail "particles were left outside their own vessel"; }
# Mass moved exactly by every frame (to rounding: 1e-12 of the particles' mass).
sed -n 's/.*max |T m_k - m_k+1| = \([^ ]*\) kg.*/\1/p' "$work/build.txt" |
  awk -v m="$(sed -n 's/.*particles 200 (\([^ ]*\) kg).*/\1/p' "$work/build.txt")" '{ r = $1 / m } END { exit !(NR == 1 && m > 0 && r < 1e-12) }' ||
  { cat "$work/build.txt"; fail "the frames do not move mass exactly"; }
"$rcfd" info -db "$work/fp.h5" > "$work/info.txt"
grep -q "mesh: vessel particles(margin 0) $cells cells" "$work/info.txt" || { cat "$work/info.txt"; fail "rcfd info does not report the vessel"; }

# A run on it: mass kept, 1 rank == 2 ranks.
run=(-db "$work/fp.h5" -t_end 0.6 -quiet -fields 0 -plot 0 -fractions_diameters 2e-3,3e-3 -fractions_mass_shares 0.5,0.5
  -init layered -monitor_digits 17 -halves -profiles)
run_on_ranks "the vessel from the particles" "${run[@]}"

# With a margin of 4 mm: every cell closer than 4 mm to a centre, a superset of the cells visited.
"$rcfd" build "${build[@]}" -vessel from-particles -vessel_margin 0.004 -o "$work/fp4.h5" -quiet \
  -particle_volume overlap > "$work/build4.txt"
"$h5print" "$work/fp4.h5" /mesh/box_cell > "$work/cells4.txt"
visited 0.004 > "$work/expected4.txt"
cmp -s "$work/cells4.txt" "$work/expected4.txt" ||
  fail "the vessel with a 4 mm margin is not the cells within 4 mm: $(diff "$work/cells4.txt" "$work/expected4.txt" | head -5)"
[ -z "$(awk 'NR == FNR { a[$1]; next } !($1 in a)' "$work/cells4.txt" "$work/expected.txt")" ] || fail "the margin lost a visited cell"
[ "$(wc -l < "$work/cells4.txt")" -gt "$cells" ] || fail "the margin added no cell"

# Databases of two vessels in one run are refused, naming both.
"$rcfd" build "${build[@]}" -vessel cylinder -o "$work/cyl.h5" -quiet
if "$rcfd" run -db "$work/fp.h5,$work/cyl.h5" -t_end 0.2 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 \
  -fractions_mass_shares 1 -output_dir "$work/two" > "$work/two.txt" 2>&1; then
  fail "a run on databases of two vessels was not refused"
fi
grep -q "are of different vessels (particles(margin 0) $cells cells" "$work/two.txt" || { cat "$work/two.txt"; fail "the refusal does not name the vessels"; }
if "$rcfd" run -db "$work/fp.h5,$work/fp4.h5" -t_end 0.2 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 \
  -fractions_mass_shares 1 -output_dir "$work/two4" > "$work/two4.txt" 2>&1; then
  fail "a run on databases of two vessels from particles was not refused"
fi

# Misplaced options: one sentence each.
if "$rcfd" build "${build[@]}" -vessel cylinder -vessel_margin 0.01 -o "$work/bad.h5" > "$work/bad.txt" 2>&1; then
  fail "-vessel_margin with an analytic vessel was not refused"
fi
grep -q -- "-vessel_margin belongs to -vessel from-particles" "$work/bad.txt" || { cat "$work/bad.txt"; fail "no sentence for -vessel_margin"; }
if "$rcfd" build "${build[@]}" -vessel from-particles -vessel_margin -1 -o "$work/bad.h5" > "$work/bad.txt" 2>&1; then
  fail "a negative margin was not refused"
fi
grep -q -- "-vessel_margin" "$work/bad.txt" || { cat "$work/bad.txt"; fail "no sentence for a negative margin"; }
if "$rcfd" synth -o "$work/bad.h5" -synth_cells 4,4,4 -synth_frames 3 -quiet -vessel from-particles > "$work/bad.txt" 2>&1; then
  fail "rcfd synth -vessel from-particles was not refused"
fi
grep -q -- "-vessel from-particles takes the vessel from particle dumps" "$work/bad.txt" || { cat "$work/bad.txt"; fail "no sentence for synth -vessel from-particles"; }
echo "vessel from particles: $cells cells (margin 4 mm: $(wc -l < "$work/cells4.txt")), runs and refusals ok"
