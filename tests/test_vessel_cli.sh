#!/usr/bin/env bash
# Vessels in the program (docs/vessels.md): -vessel box is today's database bit
# for bit; the synthetic bed in a cylinder makes a database of the cylinder's
# cells that rcfd info reports, on which a run keeps every fraction's mass,
# never turns a cell negative, gives the same answers on 1 and 2 ranks and
# writes field files of the cylinder's cells only; a set of databases of two
# vessels is refused; bad vessel options are refused with one sentence.
# usage: test_vessel_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/vessel_script_setup.sh"
bed=(-synth_cells 12,12,24 -synth_length 0.12,0.12,0.24 -synth_bed_height 0.08 -synth_frames 30 -quiet)

# The whole box, named or as a shape holding the box: the same frames, the same content hash.
"$rcfd" synth -o "$work/box.h5" "${bed[@]}"
"$rcfd" synth -o "$work/box2.h5" "${bed[@]}" -vessel box
"$rcfd" synth -o "$work/box3.h5" "${bed[@]}" -vessel all -vessel_all_box -1,1,-1,1,-1,1
hash() { "$h5print" "$1" / content_hash string; }
[ "$(hash "$work/box.h5")" = "$(hash "$work/box2.h5")" ] || fail "-vessel box changed the database"
[ "$(hash "$work/box.h5")" = "$(hash "$work/box3.h5")" ] || fail "a box shape holding the box changed the database"
[ "$("$h5print" "$work/box2.h5" /mesh kind string)" = box ] || fail "-vessel box did not write a box mesh"

# The bed in the inscribed cylinder: fewer cells, recorded, reported.
"$rcfd" synth -o "$work/cyl.h5" "${bed[@]}" -vessel cylinder
[ "$("$h5print" "$work/cyl.h5" /mesh kind string)" = masked_box ] || fail "the cylinder's mesh is not masked_box"
"$h5print" "$work/cyl.h5" /mesh vessel string | grep -q '^+cylinder(0.06,0.06,0.06) samples 8$' ||
  fail "the cylinder is not recorded: $("$h5print" "$work/cyl.h5" /mesh vessel string)"
cells=$("$h5print" "$work/cyl.h5" /mesh/cell_volumes | wc -l)
[ "$cells" -lt 3456 ] && [ "$cells" -gt 2500 ] || fail "the cylinder has $cells of the box's 3456 cells"
"$rcfd" info -db "$work/cyl.h5" > "$work/info.txt"
grep -q 'mesh: vessel +cylinder(0.06,0.06,0.06)' "$work/info.txt" || { cat "$work/info.txt"; fail "rcfd info does not report the vessel"; }
grep -q "$cells cells inside" "$work/info.txt" || fail "rcfd info does not report the inside cells"

# A run on the cylinder: masses kept, none negative, 1 rank == 2 ranks, fields of the cylinder's cells.
run=(-db "$work/cyl.h5" -t_end 0.6 -quiet -fields_every 0.3 -plot false -profiles -halves -bottom_layer
  -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -init layered -monitor_digits 17)
mpiexec -n 1 "$rcfd" run "${run[@]}" -output_dir "$work/np1"
mpiexec -n 2 "$rcfd" run "${run[@]}" -output_dir "$work/np2"
"$compare" "$work/np1/cog.csv" "$work/np2/cog.csv" 1e-12 1e-15 bulk_mismatch=1e-12
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^mass_/) m[i] = 1; if ($i == "min_cell_mass_kg") low = i }; next }
  NR == 2 { for (i in m) first[i] = $i }
  { for (i in m) if (($i - first[i]) > 1e-12 * first[i] || (first[i] - $i) > 1e-12 * first[i]) { print "mass " $i " vs " first[i]; bad = 1 }
    if ($low < 0) { print "negative cell mass " $low; bad = 1 } }
  END { exit bad }' "$work/np1/cog.csv" || fail "the run on the cylinder lost mass or made a negative cell"
# Answers on real volumes: the settled bottom layer holds the bed's packing (0.55), not
# 0.55 x 79 % as it would over the box's volumes.
awk -F, '/^[0-9]/ { print $NF; exit }' "$work/np1/profiles.csv" |
  awk '{ exit !($1 > 0.52 && $1 < 0.56) }' || fail "the bottom layer's alpha_s is not the packing: $(sed -n 3p "$work/np1/profiles.csv")"
"$compare" "$work/np1/halves.csv" "$work/np2/halves.csv" 1e-12 1e-15
grep -q 'TopologyType="Hexahedron" NumberOfElements="'"$cells"'"' "$work/np2/fields.xmf" ||
  fail "the field index does not list the cylinder's $cells cells"
[ "$("$h5print" "$work/np2/fields_000001.h5" /alpha_s | wc -l)" -eq "$cells" ] || fail "a field file is not of the cylinder's cells"
[ "$("$h5print" "$work/np2/fields_mesh.h5" /cells | wc -l)" -eq $((8 * cells)) ] || fail "fields_mesh.h5 has not 8 corners per cell"
awk '$1 <= 0 || $1 > 1 { bad = 1 } $1 < 1 { cut++ } END { exit bad || !cut }' <("$h5print" "$work/np2/fields_mesh.h5" /inside_share) ||
  fail "fields_mesh.h5's inside_share is not in (0, 1] with cut cells below 1"

# rcfd coarsen on the cylinder: the same vessel and volume on 6 x 6 x 12 coarse cells, a run on it
# keeps its mass.
"$rcfd" coarsen -db "$work/cyl.h5" -factor 2,2,2 -o "$work/coarse.h5" -quiet
"$rcfd" info -db "$work/coarse.h5" > "$work/coarse.txt"
volume() { grep -o 'inside ([0-9.]* % of the box.s), [0-9.e+-]* m^3' "$1" | awk '{ print $(NF - 1) }'; }
grep -q 'mesh: vessel +cylinder(0.06,0.06,0.06) samples 8' "$work/coarse.txt" &&
  grep -q 'cut from the box 6 x 6 x 12 cells' "$work/coarse.txt" || { cat "$work/coarse.txt"; fail "the coarse cylinder"; }
[ "$(volume "$work/coarse.txt")" = "$(volume "$work/info.txt")" ] && [ -n "$(volume "$work/info.txt")" ] ||
  fail "coarsening changed the cylinder's volume: $(volume "$work/info.txt") -> $(volume "$work/coarse.txt")"
mpiexec -n 2 "$rcfd" run -db "$work/coarse.h5" -t_end 0.3 -quiet -fields 0 -plot 0 -fractions_diameters 1.5e-3,3e-3 \
  -fractions_mass_shares 0.5,0.5 -init layered -monitor_digits 17 -output_dir "$work/coarserun"
awk -F, 'NR == 2 { a = $6; b = $7 } NR > 2 && (($6 - a) ^ 2 > (1e-12 * a) ^ 2 || ($7 - b) ^ 2 > (1e-12 * b) ^ 2) { bad = 1 }
  END { exit bad }' "$work/coarserun/cog.csv" || fail "the run on the coarse cylinder lost mass"

# A stitched run on the cylinder restarted from its checkpoint: the same series, byte for byte,
# on 2 ranks (the carry jumps between frames, so the column carry over the cylinder's columns runs).
restart=(-db "$work/cyl.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 3
  -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -bottom_layer)
restart_repeats "the cylinder" "${restart[@]}"
awk 'NR > 2 && $1 != prev + 1 { j++ } { prev = $1 } END { exit !(j >= 3) }' "$work/full/path.txt" ||
  fail "the stitched path on the cylinder did not jump"

# Databases of two vessels in one run: refused, naming both.
if "$rcfd" run -db "$work/cyl.h5,$work/box.h5" -db_switch_schedule 0:1.1 -t_end 0.1 -quiet -output_dir "$work/two" > "$work/two.txt" 2>&1; then
  fail "a run on databases of two vessels was not refused"
fi
grep -q "are of different vessels (+cylinder(0.06,0.06,0.06) samples 8 and box)" "$work/two.txt" || { cat "$work/two.txt"; fail "the refusal does not name the vessel"; }

# rcfd build from particle dumps in a cylinder: a cloud turning about the axis, three snapshots;
# the database is on the cylinder's cells and a run on it keeps its mass.
mkdir -p "$work/dump"
for k in 0 1 2; do
  awk -v k=$k 'BEGIN {
    printf "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n60\nITEM: BOX BOUNDS ff ff ff\n0 0.1\n0 0.1\n0 0.04\n", 1000 * k
    print "ITEM: ATOMS id type x y z radius"
    for (p = 1; p <= 60; ++p) { r = 0.045 * sqrt((p * 37 % 60 + 0.5) / 60); a = p * 2.39996 + 0.4 * k
      printf "%d 1 %.9f %.9f %.9f 0.0015\n", p, 0.05 + r * cos(a), 0.05 + r * sin(a), 0.003 + 0.034 * ((p * 13) % 60) / 60 } }' \
    >"$work/dump/dump.$k.txt"
done
printf '# index time\n0 0.1\n1 0.2\n2 0.3\n' >"$work/dump/times.txt"
"$rcfd" build -dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 10,10,4 -vessel cylinder \
  -o "$work/built.h5" -quiet
"$h5print" "$work/built.h5" /mesh vessel string | grep -q '^+cylinder(0.05,0.05,0.05) samples 8$' ||
  fail "rcfd build did not record the cylinder: $("$h5print" "$work/built.h5" /mesh vessel string)"
built=$("$h5print" "$work/built.h5" /mesh/cell_volumes | wc -l)
[ "$built" -lt 400 ] && [ "$built" -gt 300 ] || fail "the built cylinder has $built of the box's 400 cells"
mpiexec -n 2 "$rcfd" run -db "$work/built.h5" -t_end 0.4 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 \
  -fractions_mass_shares 1 -monitor_digits 17 -output_dir "$work/builtrun" -drift_model measured -snapshots_times 0.2
awk -F, 'NR == 2 { m = $5 } NR > 2 && ($5 - m > 1e-12 * m || m - $5 > 1e-12 * m) { bad = 1 } END { exit bad }' \
  "$work/builtrun/cog.csv" || fail "the run on the built cylinder lost mass"
# The mid-plane snapshot holds the plane's cells of the cylinder (10 across, 4 layers; its row lies inside).
[ "$(grep -c '^[0-9]' "$work/builtrun/snapshot_0.2000s.csv")" -eq 40 ] || fail "the snapshot is not the cylinder's mid-plane"

# The same cloud in a cone standing on a plinth (from 1 cm up): the box's lowest cell layer has no
# cell of the vessel, so the profiles start at the cone's first layer and the bottom layer is its.
"$rcfd" build -dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 10,10,4 -vessel cone \
  -vessel_cone_cone 0.05,0.05,0.01,0.02,0.04,0.05 -o "$work/cone.h5" -quiet -init_out "$work/cone-init.h5"
"$rcfd" run -db "$work/cone.h5" -t_end 0.2 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 -fractions_mass_shares 1 \
  -profiles -bottom_layer -output_dir "$work/conerun"
[ "$(awk -F, '/^[0-9]/ { print $1; exit }' "$work/conerun/profiles.csv")" = 0.015 ] ||
  fail "the cone's profiles do not start at its first layer: $(sed -n 3p "$work/conerun/profiles.csv")"
[ "$(grep -c '^[0-9]' "$work/conerun/profiles.csv")" -eq 3 ] || fail "the cone's profiles have not its 3 layers"
# -init_out counts the particles frame 0 counts: the same mass as the start from frame 0's alpha_s.
"$rcfd" run -db "$work/cone.h5" -t_end 0.1 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 -fractions_mass_shares 1 \
  -init file -init_file "$work/cone-init.h5" -monitor_digits 17 -output_dir "$work/coneinit"
"$rcfd" run -db "$work/cone.h5" -t_end 0.1 -quiet -fields 0 -plot 0 -fractions_diameters 3e-3 -fractions_mass_shares 1 \
  -monitor_digits 17 -output_dir "$work/conemixed"
awk -F, -v b="$(sed -n 2p "$work/conemixed/cog.csv" | cut -d, -f5)" 'NR == 2 { exit !($5 - b < 1e-12 * b && b - $5 < 1e-12 * b) }' \
  "$work/coneinit/cog.csv" || fail "the cone's -init_out holds another mass than its frame 0"
grep -q '^0,' "$work/conerun/bottom.csv" && ! grep -q nan "$work/conerun/bottom.csv" ||
  fail "the cone's bottom layer is empty: $(sed -n 2p "$work/conerun/bottom.csv")"

# Under the overlap rule the parts of a sphere beyond a cut cell's wall go to its centre's cell:
# the cone's small rim cells are not crowded (alpha_s reached 34 in one before).
"$rcfd" build -dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 10,10,4 -vessel cone \
  -vessel_cone_cone 0.05,0.05,0.01,0.02,0.04,0.05 -particle_volume overlap -o "$work/cone-overlap.h5" -quiet ||
  fail "the cone under the overlap rule was not built"

# A broken vessel mesh is refused with a sentence naming the file and what is wrong.
h5edit=$(dirname "$compare")/h5_edit
cp "$work/cyl.h5" "$work/short.h5"
"$h5edit" "$work/short.h5" keep /mesh/cell_volumes 100
if "$rcfd" info -db "$work/short.h5" > "$work/short.txt" 2>&1; then fail "a vessel mesh with too few volumes was read"; fi
grep -q "short.h5': /mesh cell_centres and cell_volumes must have one row per cell of box_cell ($cells)" "$work/short.txt" ||
  { cat "$work/short.txt"; fail "the short vessel mesh's refusal does not say what is wrong"; }

# Bad vessel options: one sentence each.
refused() { # expected text, then options
  local text=$1; shift
  if "$rcfd" synth -o "$work/bad.h5" "${bed[@]}" "$@" > "$work/bad.txt" 2>&1; then fail "synth $* was not refused"; fi
  grep -q -- "$text" "$work/bad.txt" || { cat "$work/bad.txt"; fail "synth $*: no '$text'"; }
}
refused "has no shape" -vessel body
refused "needs a positive radius" -vessel body -vessel_body_cylinder 0.06,0.06,-1
refused "belong to -vessel cylinder" -vessel box -vessel_radius 0.05
refused "above the settled bed" -vessel body -vessel_body_cylinder 0.06,0.06,0.06,0,0.1
echo "vessel cli: passed"
