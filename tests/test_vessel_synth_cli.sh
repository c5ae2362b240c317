#!/usr/bin/env bash
# The synthetic bed under a conical bottom and in a box minus tubes, in the program
# (docs/vessels.md): rcfd synth writes databases of the vessels' cells that rcfd info reports,
# with exact shifts; a run on each keeps every fraction's mass to 1e-12 with no cell negative,
# writes fields of the vessel's cells only and gives the same bytes on 1 and 2 ranks; a stitched
# run on the cone restarted from its checkpoint repeats the uninterrupted one byte for byte; a
# bed too high for its vessel is refused with one sentence.
# usage: test_vessel_synth_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
source "$(dirname "${BASH_SOURCE[0]}")/vessel_script_setup.sh"

cone=(-synth_cells 12,12,24 -synth_length 0.12,0.12,0.24 -synth_bed_height 0.08 -synth_frames 30 -quiet
  -vessel body,bottom -vessel_body_cylinder 0.06,0.06,0.06,0.04,0.24 -vessel_bottom_cone 0.06,0.06,0,0.02,0.04,0.06)
tubes=(-synth_cells 20,4,40 -synth_length 0.1,0.02,0.2 -synth_bed_height 0.1 -synth_frames 30 -quiet
  -synth_max_diameter 0.02 -vessel bed -vessel_bed_box 0,0.1,0,0.02,0,0.2 -vessel_minus a,b,c
  -vessel_a_tube_y 0.03,0.04,0.008 -vessel_b_tube_y 0.07,0.04,0.008 -vessel_c_tube_y 0.05,0.07,0.008)
"$rcfd" synth -o "$work/cone.h5" "${cone[@]}"
"$rcfd" synth -o "$work/tubes.h5" "${tubes[@]}"

for bed in cone tubes; do
  db=$work/$bed.h5
  [ "$("$h5print" "$db" /mesh kind string)" = masked_box ] || fail "the $bed's mesh is not masked_box"
  cells=$("$h5print" "$db" /mesh/cell_volumes | wc -l)
  "$rcfd" info -db "$db" > "$work/$bed-info.txt"
  grep -q "$cells cells inside" "$work/$bed-info.txt" || { cat "$work/$bed-info.txt"; fail "rcfd info does not report the $bed"; }
  # T_k moves V alpha_k onto V alpha_k+1 (rcfd info's mass consistency, a relative L1).
  awk '/mass consistency/ { v = $(NF - 3) + 0; found = 1; exit !(v < 1e-12) } END { if (!found) exit 1 }' \
    "$work/$bed-info.txt" || { grep 'mass consistency' "$work/$bed-info.txt"; fail "the $bed's shifts are not exact"; }

  # A run: masses kept, none negative, fields of the vessel's cells, 1 rank == 2 ranks: cog.csv to
  # 1e-12 (its sums over cells, like the state, differ in the last bits with the ranks' order of
  # addition: 2e-15 in alpha_s here, as on the cylinder), the answers' files byte for byte.
  run=(-db "$db" -t_end 0.6 -quiet -fields_every 0.3 -plot false -profiles -halves -bottom_layer
    -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -init layered -monitor_digits 17)
  run_on_ranks "the $bed" "${run[@]}"
  mv "$work/np1" "$work/$bed-np1"
  mv "$work/np2" "$work/$bed-np2"
  for f in halves.csv bottom.csv profiles.csv; do
    cmp -s "$work/$bed-np1/$f" "$work/$bed-np2/$f" || fail "the $bed's $f differs between 1 and 2 ranks"
  done
  grep -q 'TopologyType="Hexahedron" NumberOfElements="'"$cells"'"' "$work/$bed-np2/fields.xmf" ||
    fail "the $bed's field index does not list its $cells cells"
  [ "$("$h5print" "$work/$bed-np2/fields_000001.h5" /alpha_s | wc -l)" -eq "$cells" ] || fail "a field file is not of the $bed's cells"
done
# The cone's bottom layer is the cone's lowest (4 cm across): the bed fills it at about the packing.
awk -F, '/^[0-9]/ { print $1, $NF; exit }' "$work/cone-np1/profiles.csv" |
  awk '{ exit !($1 == 0.005 && $2 > 0.45 && $2 < 0.56) }' ||
  fail "the cone's bottom layer is not filled: $(sed -n 3p "$work/cone-np1/profiles.csv")"

# A stitched run on the cone restarted from its checkpoint: the same series, byte for byte, on 2 ranks.
restart=(-db "$work/cone.h5" -quiet -fields 0 -plot 0 -monitor_digits 17 -path_type random -path_seed 3
  -fractions_diameters 1.5e-3,3e-3 -fractions_mass_shares 0.5,0.5 -bottom_layer)
restart_repeats "the cone" "${restart[@]}"

# A bed too high for its vessel (a column capped at 10 cm holding 8 cm of bed): one sentence, no file.
if "$rcfd" synth -o "$work/bad.h5" "${cone[@]:0:8}" -vessel body -vessel_body_cylinder 0.06,0.06,0.06,0,0.1 \
  > "$work/bad.txt" 2>&1; then fail "a bed too high for its vessel was not refused"; fi
grep -q "bedHeight must leave at least 30 % of the vessel's volume above the settled bed" "$work/bad.txt" ||
  { cat "$work/bad.txt"; fail "the refusal does not say what is wrong"; }
[ ! -e "$work/bad.h5" ] || fail "a refused synth left a file"
echo "vessel synth cli: passed"
