#!/usr/bin/env bash
# Tiny cut cells merged in the program (-vessel_merge_below, docs/vessels.md): a threshold of 0
# writes today's database (the same content hash); the synthetic bed in a cylinder and under a
# cone and a build from particle dumps on merged meshes record the threshold and the merged box
# cells, keep the vessel's volume (to 1e-13), leave no cell below it (none is isolated here), move mass
# exactly; runs keep every fraction's mass to 1e-12 with 1 rank == 2 ranks, a restart repeats
# byte for byte; databases of two thresholds are refused in one run; build -eulerian refuses it.
# usage: test_vessel_merge_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/vessel_script_setup.sh"
bed=(-synth_cells 12,12,24 -synth_length 0.12,0.12,0.24 -synth_bed_height 0.08 -synth_frames 30 -quiet)
cone=(-vessel body,bottom -vessel_body_cylinder 0.06,0.06,0.06,0.04,0.24 -vessel_bottom_cone 0.06,0.06,0,0.02,0.04,0.06)
hash() { "$h5print" "$1" / content_hash string; }
# The smallest cell's share of a box cell (0.12 / 12 = 1 cm cells of 1 cm height: 1e-6 m^3).
smallest() { "$h5print" "$1" /mesh/cell_volumes | awk 'NR == 1 || $1 < s { s = $1 } END { printf "%.4f", s / 1e-6 }'; }
volume() { "$h5print" "$1" /mesh/cell_volumes | awk '{ s += $1 } END { printf "%.17g", s }'; }

# A threshold of 0: the same database as without the option.
"$rcfd" synth -o "$work/cyl.h5" "${bed[@]}" -vessel cylinder
"$rcfd" synth -o "$work/cyl0.h5" "${bed[@]}" -vessel cylinder -vessel_merge_below 0
[ "$(hash "$work/cyl.h5")" = "$(hash "$work/cyl0.h5")" ] || fail "-vessel_merge_below 0 changed the cylinder's database"

for S in 0.1 0.25; do
  for v in cyl cone; do
    if [ $v = cyl ]; then shape=(-vessel cylinder); else shape=("${cone[@]}"); fi
    [ -e "$work/$v.h5" ] || "$rcfd" synth -o "$work/$v.h5" "${bed[@]}" "${shape[@]}"
    db=$work/$v-$S.h5
    "$rcfd" synth -o "$db" "${bed[@]}" "${shape[@]}" -vessel_merge_below $S
    "$h5print" "$db" /mesh vessel string | grep -q " samples 8 merge $S\$" ||
      fail "the $v's threshold $S is not recorded: $("$h5print" "$db" /mesh vessel string)"
    plain=$("$h5print" "$work/$v.h5" /mesh/cell_volumes | wc -l)
    cells=$("$h5print" "$db" /mesh/cell_volumes | wc -l)
    merged=$("$h5print" "$db" /mesh/merged_box_cell | wc -l)
    [ $((cells + merged)) -eq "$plain" ] && [ "$merged" -gt 0 ] ||
      fail "the $v at $S: $cells cells and $merged merged box cells of $plain"
    awk -v s="$(smallest "$db")" -v S=$S 'BEGIN { exit !(s >= S) }' || fail "the $v at $S keeps a cell of share $(smallest "$db")"
    awk -v a="$(volume "$work/$v.h5")" -v b="$(volume "$db")" 'BEGIN { exit !(a > 0 && (a - b) ^ 2 <= (1e-13 * a) ^ 2) }' ||
      fail "merging changed the $v's volume: $(volume "$work/$v.h5") -> $(volume "$db")"
    "$rcfd" info -db "$db" > "$work/info.txt"
    awk '/mass consistency/ { v = $(NF - 3) + 0; found = 1; exit !(v < 1e-12) } END { if (!found) exit 1 }' \
      "$work/info.txt" || { grep 'mass consistency' "$work/info.txt"; fail "the $v's shifts at $S are not exact"; }
    echo "$v at S = $S: $plain -> $cells cells, smallest share $(smallest "$work/$v.h5") -> $(smallest "$db")"
  done
done

# Runs on the merged cone: masses, no negative cell, 1 rank == 2 ranks, restart byte for byte.
run=(-db "$work/cone-0.25.h5" -t_end 0.6 -quiet -fields_every 0.3 -plot false -profiles -halves -bottom_layer
  -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -init layered -monitor_digits 17)
run_on_ranks "the merged cone" "${run[@]}"
for f in halves.csv bottom.csv profiles.csv; do
  cmp -s "$work/np1/$f" "$work/np2/$f" || fail "the merged cone's $f differs between 1 and 2 ranks"
done
restart=(-db "$work/cyl-0.25.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 3
  -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -bottom_layer)
restart_repeats "the merged cylinder" "${restart[@]}"
# The stitched run jumps, so the column carry runs over the merged cells: each stands in one column once.
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^mass_/) m[i] = 1; if ($i == "min_cell_mass_kg") low = i }; next }
  NR == 2 { for (i in m) first[i] = $i }
  { for (i in m) if (($i - first[i]) > 1e-12 * first[i] || (first[i] - $i) > 1e-12 * first[i]) { print "mass " $i " vs " first[i]; bad = 1 }
    if ($low < 0) { print "negative cell mass " $low; bad = 1 } }
  END { exit bad }' "$work/full/cog.csv" || fail "the stitched run on the merged cylinder lost mass or made a negative cell"
awk 'NR > 2 && $1 != prev + 1 { j++ } { prev = $1 } END { exit !(j >= 3) }' "$work/full/path.txt" ||
  fail "the stitched path on the merged cylinder did not jump"

# Databases of two thresholds in one run: refused as of two vessels.
if "$rcfd" run -db "$work/cyl.h5,$work/cyl-0.1.h5" -db_switch_schedule 0:1.1 -t_end 0.1 -quiet -output_dir "$work/two" \
  > "$work/two.txt" 2>&1; then fail "a run on databases of two merge thresholds was not refused"; fi
grep -q "are of different vessels (+cylinder(0.06,0.06,0.06) samples 8 and +cylinder(0.06,0.06,0.06) samples 8 merge 0.1)" \
  "$work/two.txt" || { cat "$work/two.txt"; fail "the refusal does not name the thresholds"; }

# rcfd build from particle dumps on a merged cylinder (half the particles at the wall, in the cells
# merged): each particle's mass in the merged cell of its box cell; mass moved exactly, -init_out of frame 0's mass, a run keeps it on 1 and 2 ranks.
mkdir -p "$work/dump"
for k in 0 1 2; do
  awk -v k=$k 'BEGIN {
    printf "ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n400\nITEM: BOX BOUNDS ff ff ff\n0 0.1\n0 0.1\n0 0.04\n", 1000 * k
    print "ITEM: ATOMS id type x y z radius"
    for (p = 1; p <= 400; ++p) { r = 0.046 * sqrt((p * 37 % 400 + 0.5) / 400); a = p * 2.39996 + 0.4 * k
      if (p % 2 == 0) r = 0.0455 + 0.0014 * ((p * 7) % 100) / 100 # half at the wall, in the small cut cells
      printf "%d 1 %.9f %.9f %.9f 0.0015\n", p, 0.05 + r * cos(a), 0.05 + r * sin(a), 0.003 + 0.034 * ((p * 13) % 400) / 400 } }' \
    >"$work/dump/dump.$k.txt"
done
printf '# index time\n0 0.1\n1 0.2\n2 0.3\n' >"$work/dump/times.txt"
for S in 0 0.25; do
  "$rcfd" build -dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 10,10,4 -vessel cylinder \
    -vessel_radius 0.047 -vessel_merge_below $S -o "$work/built-$S.h5" -init_out "$work/init-$S.h5" -quiet
done
"$h5print" "$work/built-0.25.h5" /mesh vessel string | grep -q '^+cylinder(0.05,0.05,0.047) samples 8 merge 0.25$' ||
  fail "rcfd build did not record the threshold: $("$h5print" "$work/built-0.25.h5" /mesh vessel string)"
[ "$("$h5print" "$work/built-0.25.h5" /mesh/merged_box_cell | wc -l)" -gt 0 ] || fail "rcfd build merged no cell"
"$rcfd" info -db "$work/built-0.25.h5" > "$work/built.txt"
sum() { "$h5print" "$1" /masses | awk '{ for (i = 1; i <= NF; ++i) s += $i } END { printf "%.15e", s }'; }
awk -v a="$(sum "$work/init-0.h5")" -v b="$(sum "$work/init-0.25.h5")" 'BEGIN { exit !(a > 0 && (a - b) ^ 2 <= (1e-12 * a) ^ 2) }' ||
  fail "the merged build's -init_out holds $(sum "$work/init-0.25.h5") kg, not $(sum "$work/init-0.h5")"
run=(-db "$work/built-0.25.h5" -t_end 0.4 -quiet -fields 0 -plot false -halves -fractions_diameters 3e-3
  -fractions_mass_shares 1 -init file -init_file "$work/init-0.25.h5" -monitor_digits 17)
run_on_ranks "the merged build" "${run[@]}"

# build -eulerian: refused with one sentence.
if "$rcfd" build -eulerian "$work/none_*.txt" -dt_rec 0.01 -vessel cylinder -vessel_merge_below 0.1 -o "$work/e.h5" \
  > "$work/e.txt" 2>&1; then fail "build -eulerian took -vessel_merge_below"; fi
grep -q "vessel_merge_below is not supported by rcfd build -eulerian" "$work/e.txt" || { cat "$work/e.txt"; fail "the refusal does not say why"; }
echo "vessel merge cli: passed"
