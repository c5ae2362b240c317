#!/usr/bin/env bash
# Operators through the program, on a small synthetic bed: plain -drift_view
# prints to stdout, -drift_view ascii:FILE writes FILE instead, -carry_type
# level is chosen from the command line (and -carry_view reports its sweeps),
# and a binary viewer or an unknown carry kind is refused with one sentence.
# usage: test_operators_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

db=$work/small.h5
run "synth" "$rcfd" synth -o "$db" -synth_cells 10,2,20 -synth_frames 60 -quiet
common=(run -db "$db" -fields false -plot false -quiet -output_dir "$work/out")

# Inventory 1.95 / 2.82 mm (d32 2.329 mm), model B, k_d 5e3: u = -k_d (d - d32)|d - d32|.
velocities="fraction 0 (d = 1.95 mm): u_d = +0.0007167 m/s
fraction 1 (d = 2.82 mm): u_d = -0.001207 m/s"
if run "-drift_view" "$rcfd" "${common[@]}" -drift_view; then
  grep -q "^drift: model B" "$work/out.txt" && ok || fail "-drift_view printed no drift view: $(cat "$work/out.txt")"
  same "-drift_view velocities" "$(grep -o 'u_d = [-+0-9.e]*' "$work/out.txt" | cut -d' ' -f3)" "0.0007167 -0.001207"
fi
if run "-drift_view ascii:FILE" "$rcfd" "${common[@]}" -drift_view "ascii:$work/drift.txt"; then
  grep -q "drift: model" "$work/out.txt" && fail "-drift_view ascii:FILE also printed to stdout" || ok
  grep -qF "$(head -1 <<<"$velocities")" "$work/drift.txt" && grep -qF "$(tail -1 <<<"$velocities")" "$work/drift.txt" &&
    ok || fail "drift.txt lacks the velocities: $(cat "$work/drift.txt" 2>&1)"
fi
if run "-carry_type level" "$rcfd" "${common[@]}" -path_type random -carry_type level -carry_sweeps 7 \
  -carry_view "ascii:$work/carry.txt"; then
  line=$(cat "$work/carry.txt")
  applications=$(sed -n 's/.* \([0-9]*\) applications$/\1/p' <<<"$line")
  sweeps=$(sed -n 's/.*per step; \([0-9]*\) sweeps in.*/\1/p' <<<"$line")
  if [[ "$line" == "carry: 7 levelling sweeps per jump, 0 per step;"* ]] && [ "${applications:-0}" -gt 0 ] &&
    [ "$sweeps" -eq $((7 * applications)) ]; then ok; else fail "-carry_view: $line"; fi
fi
expect_error "-drift_view prints text: give it no value (stdout) or ascii:FILE" \
  "${common[@]}" -drift_view "binary:$work/drift.bin"
expect_error "-carry_type bogus is not a known carry kind; known kinds: column, level, remap" \
  "${common[@]}" -carry_type bogus

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
