#!/usr/bin/env bash
# Forecasts on a database set switch and blend within their horizon (docs/live.md, "Forecasts"): on
# two small beds recorded at 1.1 and 1.3 m/s (a and b), a live run holding its u_sup forecasts at
# t = 0, one member 0.1 s ahead, under a what-if whose u_sup changes at 0.05 s (with the schedule rule
# a drop from 1.3 to 1.1 m/s: a switch from b to a; with the blend rule a rise from 1.1 to 1.2 m/s:
# the two blended at 0.5).  A live run that follows the same u_sup over the same frames (the member's
# stitched path, recorded) ends with the member's delta z to 1e-12 (relative), its bottom d32 and
# u_mf/u_sup to bottom.csv's 10 digits; the forecasting run's own files are those of the run without
# forecasts; with scalars (spray, plug-flow gas) the member's bottom moisture is the followed run's
# too; a forecast that holds 1.3 m/s stays on b (another delta z); 2 ranks write 1 rank's forecast.csv.
# usage: test_forecast_switching.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 compare=$2
source "$4/tests/script_helpers.sh"
write_two_velocity_beds
common=(-fields 0 -plot 0 -quiet -bottom_layer -live_poll 0.02 -monitor_digits 17
  -fractions_diameters 1.5e-3,3.5e-3 -fractions_mass_shares 0.5,0.5)
two=(-db "$work/a.h5,$work/b.h5" "${common[@]}")
forecast=(-forecast_every 1 -forecast_horizon 0.1 -forecast_members 1 -forecast_digits 17)

# The member's frames: its path is the random path of seed 1 (-forecast_seed) on the run's first
# database; the live run it is compared with starts on the forecasting run's frame 0 (replay) and
# then takes them.
for db in a b; do
  "$rcfd" run -db "$work/$db.h5" "${common[@]}" -path_type random -path_seed 1 -t_end 0.1 -output_dir "$work/q-$db"
  { echo "# the forecast member's frames"; echo 0; grep -v '^#' "$work/q-$db/path.txt"; } >"$work/member-path-$db.txt"
done

# case: name, rule, the live file's held u_sup, the what-if's from 0.05 s, the database held on, extra options.
check_case() {
  local name=$1 rule=$2 held=$3 u=$4 db=$5
  shift 5
  printf 'time_s,u_sup\n0,%s\n0.2,%s\n' "$held" "$held" >"$work/held-$name.csv"
  printf 'time_s,u_sup\n0,%s\n0.05,%s\n' "$held" "$u" >"$work/whatif-$name.csv"
  printf 'time_s,u_sup\n0,%s\n0.05,%s\n0.1,%s\n' "$held" "$u" "$u" >"$work/follow-$name.csv"
  "$rcfd" run "${two[@]}" "$@" -db_switch_type $rule -live "$work/held-$name.csv" -live_end 0.2 -output_dir "$work/plain-$name"
  "$rcfd" run "${two[@]}" "$@" -db_switch_type $rule -live "$work/held-$name.csv" -live_end 0.2 "${forecast[@]}" \
    -forecast_schedule "$work/whatif-$name.csv" -output_dir "$work/fc-$name"
  "$rcfd" run "${two[@]}" "$@" -db_switch_type $rule -live "$work/follow-$name.csv" -live_end 0.1 -path_type recorded \
    -path_file "$work/member-path-$db.txt" -output_dir "$work/follow-$name"
  grep -q "^0.05,[01],[01][,+]" "$work/follow-$name/switches.csv" && ok ||
    fail "$name: the followed run did not switch at 0.05 s: $(cat "$work/follow-$name/switches.csv")"
  local row d32 umf usup
  row=$(awk -F, 'NR == 2' "$work/fc-$name/forecast.csv") # issued at 0
  # (The run's mass ledger removes round-off at its checks, a member's does not: to 1e-12, not bits.)
  same "$name: the member's delta z against the followed run's at 0.1 s (relative 1e-12)" \
    "$(awk -F, '{ printf "%.17g", $4 * 1e3 }' <<<"$row")" \
    "$(awk -F, '!/^[#t]/ && $1 > 0.0999 && $1 < 0.1001 { printf "%.17g", $5 * 1e3 }' "$work/follow-$name/cog.csv")" 1e-12
  read -r d32 umf usup < <(awk -F, '!/^[#t]/ && $1 > 0.0999 && $1 < 0.1001 { print $2, $3, $4 }' \
    "$work/follow-$name/bottom.csv")
  same "$name: the member's bottom d32 [mm] and u_mf/u_sup (bottom.csv's 10 digits)" \
    "$(awk -F, '{ printf "%.17g %.17g", $6 * 1e3, $8 }' <<<"$row")" \
    "$(awk -v d="$d32" -v a="$umf" -v b="$usup" 'BEGIN { printf "%.17g %.17g", d * 1e3, a / b }')" 1e-9
  for f in cog.csv bottom.csv path.txt switches.csv; do # the forecasts change nothing in the live state
    cmp -s "$work/plain-$name/$f" "$work/fc-$name/$f" && ok || fail "$name: the forecasts changed the live run's $f"
  done
}
# A drop from 1.3 to 1.1 m/s: from b to a; a rise from 1.1 to 1.2 m/s blended: a and b at 0.5.
check_case drop schedule 1.3 1.1 b
check_case blend blend 1.1 1.2 a
# With scalars (a spray into the bottom layers, Gunn's exchange with the plug-flow gas): the member's
# switch carries them as the run's does, its bottom layer's moisture that of the followed run.
scalars=(-zones spray -zone_spray_box 0,0.2,0,0.05,0,0.05 -scalars temperature,moisture -scalar_temperature_initial 300
  -scalar_exchange_model gunn -scalar_gas_model plug -scalar_gas_humidity 0.005 -scalar_spray_rate 0.05
  -scalar_gas_temperature 330)
check_case scalars schedule 1.3 1.1 b "${scalars[@]}"
same "scalars: the member's bottom moisture against the followed run's (bottom.csv's 10 digits)" \
  "$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i } NR == 2 { print $c["moisture_bottom_mean"] }' \
    "$work/fc-scalars/forecast.csv")" \
  "$(awk -F, '!/^[#t]/ && $1 > 0.0999 && $1 < 0.1001 { print $NF }' "$work/follow-scalars/bottom.csv")" 1e-11
# Held, the member stays on b (the live file's 1.3 m/s): not the switched member's delta z.
"$rcfd" run "${two[@]}" -db_switch_type schedule -live "$work/held-drop.csv" -live_end 0.2 "${forecast[@]}" \
  -output_dir "$work/fc-held"
[ "$(awk -F, 'NR == 2 { print $4 }' "$work/fc-held/forecast.csv")" != "$(awk -F, 'NR == 2 { print $4 }' \
  "$work/fc-drop/forecast.csv")" ] && ok || fail "a forecast held at 1.3 m/s gave the switched member's delta z"
mpiexec -n 2 "$rcfd" run "${two[@]}" -db_switch_type schedule -live "$work/held-drop.csv" -live_end 0.2 "${forecast[@]}" \
  -forecast_schedule "$work/whatif-drop.csv" -output_dir "$work/fc2"
if "$compare" "$work/fc-drop/forecast.csv" "$work/fc2/forecast.csv" 1e-10 1e-14 >/dev/null; then ok; else
  fail "2 ranks: $("$compare" "$work/fc-drop/forecast.csv" "$work/fc2/forecast.csv" 1e-10 1e-14)"; fi

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
