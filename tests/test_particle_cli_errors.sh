#!/usr/bin/env bash
# Bad particle input to rcfd build / reference / compare gets one line that
# names the file (or option) and what was expected: no traceback, no file left.
# usage: test_particle_cli_errors.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
write_two_particle_dumps

# ---- bad input: one line naming the file.
cp "$work/dump/dump.0.txt" "$work/a.txt"
printf '%s\n' "$work/a.txt" "$work/missing.txt" >"$work/list.txt"
expect_error "cannot open particle snapshot '$work/missing.txt'" build -dump_list "$work/list.txt" \
  -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/x.h5"
sed 's/ radius$//; s/ 0.0005$//; s/ 0.001$//' "$work/dump/dump.1.txt" >"$work/noradius.txt"
printf '%s\n' "$work/a.txt" "$work/noradius.txt" >"$work/list2.txt"
expect_error "particle snapshot '$work/noradius.txt', line 9: expected a column 'radius'" build \
  -dump_list "$work/list2.txt" -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/x.h5"
expect_error "particle snapshot '$work/noradius.txt', line 9: expected a column 'radius'" reference \
  -dump_list "$work/list2.txt" -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/xref"
expect_error "no particle snapshot file matches '$work/nothing.*'" build -dumps "$work/nothing.*" \
  -dump_dt 0.1 -mesh_cells 2,1,2
printf '0 0.1\n1 0.2\n' >"$work/times2.txt"
expect_error "-times '$work/times2.txt' lists 2 times but" build -dumps "$work/dump/dump.*.txt" \
  -times "$work/times2.txt" -mesh_cells 2,1,2
printf '0 0.1\n1 0.2\n2 0.35\n' >"$work/times3.txt"
expect_error "not equally spaced" build -dumps "$work/dump/dump.*.txt" -times "$work/times3.txt" \
  -mesh_cells 2,1,2 -o "$work/x.h5"
expect_error "Give the snapshot times with -times FILE" build -dumps "$work/dump/dump.*.txt" \
  -mesh_cells 2,1,2
# 1 mm cells and a 2 mm particle: counted by centre, alpha_s passes 1 and the
# build is refused without leaving the database or the -init_out file behind.
expect_error "alpha_s reaches" build "${common[@]/2,1,2/20,10,20}" \
  -o "$work/x.h5" -init_out "$work/x-init.h5"
[ ! -e "$work/x.h5" ] && [ ! -e "$work/x.h5.tmp" ] && [ ! -e "$work/x-init.h5" ] && ok ||
  fail "a refused build left a file"
# Counted by overlap the same build holds: the 2 mm particle sits
# on a corner of eight cells (x, y, z = 5, 5, 6 mm), an eighth in each:
# alpha_s = (pi/6 8e-9 / 8) / 1e-9 = pi/6.
if "$rcfd" build "${common[@]/2,1,2/20,10,20}" -particle_volume overlap -o "$work/x.h5" \
  -init_out "$work/x-init.h5" \
  >"$work/out.txt" 2>&1; then
  grep -q "alpha_s: max 0.5236, 0 cell-snapshots" "$work/out.txt" && ok ||
    fail "overlap build: $(grep alpha_s: "$work/out.txt")"
else
  fail "overlap build with cells smaller than the particles: $(cat "$work/out.txt")"
fi
expect_error "-particle_volume" build "${common[@]}" -particle_volume middle -o "$work/x.h5"
expect_error "Unknown option -frame_strid" build "${common[@]}" -frame_strid 2
expect_error "-vertical_axis w is not known" reference "${common[@]}" -vertical_axis w
expect_error "cannot open the reference file '$work/none.csv'" compare \
  -reference "$work/none.csv" -rcfd "$work/none.csv"

# Sizes too large to hold: one sentence, not std::bad_alloc.
sed 's/^2$/1000000000000000/' "$work/dump/dump.0.txt" >"$work/huge.txt"
printf '%s\n' "$work/huge.txt" "$work/a.txt" >"$work/list3.txt"
expect_error "particle snapshot '$work/huge.txt', line 12: expected 1000000000000000 atom lines" build \
  -dump_list "$work/list3.txt" -dump_dt 0.1 -mesh_cells 2,1,2 -o "$work/x.h5"
expect_error "-mesh_cells (2000 x 2000 x 2000) asks for 8e+09 cells, more than the 2147483647" build \
  -dump_list "$work/list.txt" -dump_dt 0.1 -mesh_cells 2000,2000,2000 -o "$work/x.h5"
expect_error "-mesh_cell_size (" build -dumps "$work/dump/dump.*.txt" -dump_dt 0.1 -mesh_cell_size 1e-9 \
  -o "$work/x.h5"
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
