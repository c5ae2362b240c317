#!/usr/bin/env bash
# rcfd synth at an operating point (docs/synthetic.md):
# - -synth_superficial_velocity is recorded in the database's metadata (format 2), as a note
#   naming the point, and a run takes it as the database's condition;
# - at the default bed's own point (1.1 m/s) the file's contents are the default bed's, bit for bit;
#   at another point they differ;
# - U <= U_mf, negative values and a disagreeing -superficial_velocity are refused with a sentence
#   naming the option;
# - -synth_series writes the per-frame series, the same without the database (-synth_series_only).
# usage: test_synth_conditions.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
h5print=$(dirname "$2")/h5_print
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
small=(-synth_cells 10,2,20 -synth_frames 10 -quiet)

run "synth at 1.3 m/s" "$rcfd" synth -o "$work/u13.h5" "${small[@]}" -synth_superficial_velocity 1.3
"$rcfd" info "$work/u13.h5" >"$work/info.txt" 2>&1
grep -q "recorded at: u_sup 1.3 m/s" "$work/info.txt" && ok || fail "u_sup not recorded: $(cat "$work/info.txt")"
grep -q "source: .*at u_sup = 1.3 m/s" "$work/info.txt" && ok || fail "source: $(grep source "$work/info.txt")"
note=$("$h5print" "$work/u13.h5" /metadata synth_operating_point string 2>&1)
grep -q "u_sup = 1.3 m/s, u_mf = 0.8381 m/s (Wen & Yu (1966) at d32 = 2.026 mm); excess gas 1.764" <<<"$note" && ok ||
  fail "note synth_operating_point: $note"
"$rcfd" run -db "$work/u13.h5" -fields 0 -plot 0 -bottom_layer -t_end 0.01 -output_dir "$work/run" >"$work/run.txt" 2>&1
grep -q "u_sup = 1.3 m/s (database)" "$work/run.txt" && ok || fail "the run's condition: $(cat "$work/run.txt")"

# The default bed's own point: the same frames; another point: other frames.
run "synth default" "$rcfd" synth -o "$work/default.h5" "${small[@]}"
run "synth at 1.1 m/s" "$rcfd" synth -o "$work/u11.h5" "${small[@]}" -synth_superficial_velocity 1.1
hash() { "$h5print" "$1" / content_hash string 2>&1; }
[ "$(hash "$work/u11.h5")" = "$(hash "$work/default.h5")" ] && ok ||
  fail "1.1 m/s is not the default bed: $(hash "$work/u11.h5") vs $(hash "$work/default.h5")"
[ "$(hash "$work/u13.h5")" != "$(hash "$work/default.h5")" ] && ok || fail "1.3 m/s gave the default bed's frames"

base=(synth -o "$work/bad.h5" "${small[@]}")
expect_error "-synth_superficial_velocity 0.8 m/s must exceed the minimum fluidization velocity 0.838124 m/s" \
  "${base[@]}" -synth_superficial_velocity 0.8
expect_error "-synth_superficial_velocity 1. m/s must exceed the minimum fluidization velocity 1.2 m/s (-synth_min_fluidization_velocity)" \
  "${base[@]}" -synth_superficial_velocity 1 -synth_min_fluidization_velocity 1.2
expect_error "-synth_superficial_velocity -1: expected a positive number" "${base[@]}" -synth_superficial_velocity -1
expect_error "-synth_min_fluidization_velocity 0: expected a positive number" "${base[@]}" -synth_min_fluidization_velocity 0
expect_error "-superficial_velocity 1.2 m/s and -synth_superficial_velocity 1.3 m/s disagree" \
  "${base[@]}" -synth_superficial_velocity 1.3 -superficial_velocity 1.2
[ ! -e "$work/bad.h5" ] && ok || fail "a refused synth wrote $work/bad.h5"

# The per-frame series: the same with and without the database (-synth_series_only skips the
# shifts, not the bed's motion), one row per frame, no database written; the halves come with
# their standard errors.
series=(-synth_cells 10,2,20 -synth_frames 12)
"$rcfd" synth -o "$work/with.h5" "${series[@]}" -synth_series "$work/with.csv" >"$work/synth.txt" 2>&1
"$rcfd" synth -o "$work/none.h5" "${series[@]}" -synth_series "$work/only.csv" -synth_series_only -quiet
cmp -s "$work/with.csv" "$work/only.csv" && ok || fail "the series differ with and without the database"
[ "$(head -1 "$work/only.csv")" = "frame,t_s,bed_height_m,z_cog_m" ] && [ "$(wc -l <"$work/only.csv")" = 13 ] && ok ||
  fail "series file: $(head -2 "$work/only.csv")"
[ ! -e "$work/none.h5" ] && ok || fail "-synth_series_only wrote a database"
grep -Eq "^Halves of the span: mean bed height .* m \([-+][0-9.]+ %, \+/- [0-9.e+-]+ % expected from the span\), Delta z_CoG .* mm \([-+][0-9.]+ %, \+/- [0-9.e+-]+ % expected from the span\)$" \
  "$work/synth.txt" && ok || fail "halves line: $(grep Halves "$work/synth.txt")"
expect_error "-synth_series_only needs -synth_series FILE" "${base[@]}" -synth_series_only

echo "$passed passed, $failures failed"
[ "$failures" = 0 ]
