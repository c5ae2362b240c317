#!/usr/bin/env bash
# The status page (docs/live.md) in a real headless browser: live runs write
# status.json and status.html; python3's static server serves the output
# directory; Debian's chromium loads the page, runs its script and dumps the
# DOM.  A run whose live u_sup drops to 0.9 m/s at 0.3 s (the bottom layer's
# de-fluidization warning fires then) shows the latest time and the warning in
# words; one at a constant 1.25 m/s shows the time and no warning.  The same
# page with its script broken shows no time (the check can fail).  status.json:
# its numbers are those of bottom.csv and forecast.csv's last rows (also when
# it is written seldom), 2 ranks write 1 rank's; without -live the page is off unless -status is given.
# The database in use: named in status.json and on the page, b.h5 after a switch, a.h5 after the switch
# back (a restart), a blend's two with their weights.  The granulator's forecast product: in status.json
# as in forecast.csv, on the page as a row and a bar per class.  A forecast under a what-if schedule
# names it (status.json's warning, the page), one without says it holds the latest conditions.  A live
# spray-dry bed's forecast wet-bottom warning: in status.json and on the page, with its moisture.
# Skipped (77) without chromium (tools/run-tests.sh installs it).
# usage: test_status_page.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1
browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  echo "chromium is not installed: skipped (tools/run-tests.sh installs it)"
  exit 77
fi
source "$4/tests/script_helpers.sh"
"$rcfd" synth -o "$work/a.h5" -synth_cells 10,2,20 -synth_frames 40 -synth_warm_up 0.2 -quiet \
  -synth_nucleation_rate 1500 -synth_seed 1 -superficial_velocity 1.1
common=(-db "$work/a.h5" -fields 0 -plot 0 -quiet -bottom_layer -live_poll 0.02 -live_end 0.5
  -forecast_horizon 0.15 -forecast_members 2)
printf 'time_s,u_sup\n0,1.1\n0.3,0.9\n0.5,0.9\n' >"$work/drop.csv"
printf 'time_s,u_sup\n0,1.25\n0.5,1.25\n' >"$work/steady.csv"
"$rcfd" run "${common[@]}" -forecast_every 0.1 -live "$work/drop.csv" -output_dir "$work/drop" 2>/dev/null
# (-status_every 1e9: written at its first step, at each forecast (0, 0.2, 0.4 s) and at the end)
"$rcfd" run "${common[@]}" -forecast_every 0.2 -live "$work/steady.csv" -status_every 1e9 -output_dir "$work/steady"
for d in drop steady; do
  [ -s "$work/$d/status.html" ] && [ -s "$work/$d/status.json" ] && ok || fail "$d: no status.html or status.json"
done

# status.json against the CSV files' last rows (the page's numbers are the run's).
value() { sed -n "s/.*\"$2\": \([^,}]*\).*/\1/p" "$1" | head -n 1; }
j=$work/drop/status.json
last_bottom=$(tail -n 1 "$work/drop/bottom.csv")
same "status.json of the drop: time, d32, u_mf/u_sup" "$(value "$j" time_s) $(value "$j" d32_bottom_m) $(value "$j" umf_usup)" \
  "$(awk -F, '{ printf "%s %s %.10g", $1, $2, $3 / $4 }' <<<"$last_bottom")" 1e-9
same "status.json of the drop: the forecast's time and warning members" \
  "$(value "$j" warning_members) $(sed -n 's/.*"forecast": {"time_s": \([^,]*\).*/\1/p' "$j")" \
  "$(tail -n 1 "$work/drop/forecast.csv" | awk -F, '{ print $10, $1 }')" 1e-12
grep -q '"De-fluidization: the bottom layer.s minimum fluidization velocity reached the gas velocity at t = 0.3 s' "$j" &&
  ok || fail "status.json of the drop has no de-fluidization warning: $(cat "$j")"
same "status.json of the steady run (-status_every 1e9): time, d32" \
  "$(value "$work/steady/status.json" time_s) $(value "$work/steady/status.json" d32_bottom_m)" \
  "$(tail -n 1 "$work/steady/bottom.csv" | awk -F, '{ print $1, $2 }')" 1e-9
# The gas back up at 0.35 s: the warning stays on the page, said to be over.
printf 'time_s,u_sup\n0,1.1\n0.3,0.9\n0.35,1.25\n0.5,1.25\n' >"$work/back.csv"
"$rcfd" run "${common[@]}" -forecast_every 0.1 -live "$work/back.csv" -output_dir "$work/back" 2>/dev/null
grep -q '"De-fluidization from t = 0.3 s, over now: the bottom layer.s u_mf = [0-9.]* m/s is below u_sup = 1.25 m/s again' \
  "$work/back/status.json" && ok || fail "status.json after the recovery: $(cat "$work/back/status.json")"
grep -q '"warnings": \[\]' "$work/steady/status.json" && ok || fail "status.json of the steady run warns: $(cat "$work/steady/status.json")"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpiexec -n 2 "$rcfd" run "${common[@]}" -forecast_every 0.1 -live "$work/drop.csv" -output_dir "$work/drop2" 2>/dev/null
cmp -s "$j" "$work/drop2/status.json" && ok || fail "2 ranks: $(diff "$j" "$work/drop2/status.json")"

# A forecast under a what-if schedule says so (status.json's warning, the page's row).
printf 'time_s,u_sup\n0,1.1\n0.05,0.9\n' >"$work/whatif.csv"
"$rcfd" run "${common[@]}" -forecast_every 0.1 -live "$work/steady.csv" -forecast_schedule "$work/whatif.csv" \
  -output_dir "$work/whatif" 2>/dev/null
grep -qF "Forecast: 2 of 2 members de-fluidize within 0.15 s, in about 0.055 s (forecast issued at t = 0.5 s, under the what-if $work/whatif.csv)." \
  "$work/whatif/status.json" && ok || fail "status.json of a what-if forecast: $(grep -A 3 warnings "$work/whatif/status.json")"
# The database in use: a live run on two databases switching with its u_sup (a.h5 to b.h5 at 0.2 s,
# back at 0.35 s), stopped by its stop file at 0.3 s, names b.h5; continued to 0.5 s, a.h5 again; a
# blend names both with their weights.
"$rcfd" synth -o "$work/b.h5" -synth_cells 10,2,20 -synth_frames 40 -synth_warm_up 0.2 -quiet \
  -synth_nucleation_rate 4000 -synth_seed 2 -superficial_velocity 1.3
two=(-db "$work/a.h5,$work/b.h5" -fields 0 -plot 0 -quiet -bottom_layer -live_poll 0.02)
printf 'time_s,u_sup\n0,1.1\n0.2,1.3\n0.3,1.3\n' >"$work/switch.csv"
touch "$work/stop"
"$rcfd" run "${two[@]}" -db_switch_type schedule -live "$work/switch.csv" -live_stop_file "$work/stop" \
  -output_dir "$work/switch" 2>/dev/null
same "status.json at the stop: the database in use" "$(value "$work/switch/status.json" database)" "\"$work/b.h5\""
cp -r "$work/switch" "$work/switch-at-stop"
rm "$work/stop"
printf '0.35,1.2\n0.5,1.2\n' >>"$work/switch.csv"
"$rcfd" run "${two[@]}" -db_switch_type schedule -live "$work/switch.csv" -live_end 0.5 \
  -restart "$work/switch/checkpoint.h5" -output_dir "$work/switch" 2>/dev/null
same "status.json at the end: the database in use" "$(value "$work/switch/status.json" database)" "\"$work/a.h5\""
"$rcfd" run "${two[@]}" -db_switch_type blend -live "$work/switch.csv" -live_end 0.5 -output_dir "$work/blend" 2>/dev/null
grep -qF "\"database\": \"$work/a.h5 (weight 0.5) blended with $work/b.h5 (weight 0.5)\"" "$work/blend/status.json" && ok ||
  fail "status.json of a blend: $(grep database "$work/blend/status.json")"
# The granulator's forecast: the product's mass and size distribution over the horizon, as forecast.csv's last row.
gran=(-db "$work/a.h5" -fields 0 -plot 0 -quiet -live_poll 0.02 -live_end 0.5 -pipeline shift,drift,carry,growth,feed,discharge
  -zones spray,feed,discharge -zone_spray_box 0.07,0.13,0,0.05,0.18,0.26 -zone_feed_box 0,0.02,0,0.05,0,0.03
  -zone_discharge_box 0.18,0.2,0,0.05,0,0.03 -fractions_diameters 1.5e-3,2.5e-3,3.5e-3 -fractions_mass_shares 0.3,0.4,0.3
  -forecast_every 0.25 -forecast_horizon 0.3 -forecast_members 2 -discharge_sample_interval 0.1)
printf 'time_s,growth_rate,feed_rate,discharge_rate\n0,1,0.2,0.2\n0.5,1,0.2,0.2\n' >"$work/rates.csv"
"$rcfd" run "${gran[@]}" -live "$work/rates.csv" -output_dir "$work/gran" 2>/dev/null
same "status.json of the granulator: the forecast's product mass and first share" \
  "$(value "$work/gran/status.json" product_mass_mean_kg) $(sed -n 's/.*"product_shares": \[{"label": "d1.500mm", "mean": \([^,]*\).*/\1/p' "$work/gran/status.json")" \
  "$(tail -n 1 "$work/gran/forecast.csv" | awk -F, '{ print $13, $15 }')" 1e-12
# A live spray-dry bed (docs/live.md, "Forecasts with scalars"): the forecast's wet-bottom warning in words.
printf 'time_s,spray_rate,gas_temperature\n0,0.05,330\n0.3,0.05,330\n' >"$work/spray.csv"
"$rcfd" run -db "$work/a.h5" -fields 0 -plot 0 -quiet -live_poll 0.02 -live_end 0.3 -live "$work/spray.csv" \
  -fractions_diameters 1.459e-3,4.075e-3 -fractions_mass_shares 0.564,0.436 -zones spray \
  -zone_spray_box 0,0.2,0,0.05,0,0.05 -scalars temperature,moisture -scalar_temperature_initial 300 \
  -scalar_exchange_model gunn -scalar_gas_model plug -scalar_gas_humidity 0.005 -bottom_layer -moisture_warning 0.03 \
  -moisture_warning_umf_share 0.5 -forecast_every 0.1 -forecast_horizon 0.1 -forecast_members 2 \
  -output_dir "$work/spray" 2>/dev/null
grep -q "Forecast: 2 of 2 members' bottom layers get wet near de-fluidization within 0.1 s" "$work/spray/status.json" &&
  ok || fail "status.json of the spray-dry bed has no forecast wet warning: $(grep -A 3 warnings "$work/spray/status.json")"

# Off without -live, on with -status.
plain=(-db "$work/a.h5" -fields 0 -plot 0 -quiet -t_end 0.05)
"$rcfd" run "${plain[@]}" -output_dir "$work/plain"
[ ! -e "$work/plain/status.json" ] && [ ! -e "$work/plain/status.html" ] && ok || fail "a run without -live wrote the status page"
"$rcfd" run "${plain[@]}" -status -output_dir "$work/plain-status"
same "-status without -live: status.json's time" "$(value "$work/plain-status/status.json" time_s)" 0.05 1e-12
RCFD_STATUS_PAGE=$work/none.html expect_error \
  "-status: cannot read the status page '$work/none.html'; install rcfd, set RCFD_STATUS_PAGE to the page, or give -status 0" \
  run "${plain[@]}" -status -output_dir "$work/refused"
RCFD_STATUS_PAGE=$work expect_error "input file '$work' is a directory, not a regular file" \
  run "${plain[@]}" -status -output_dir "$work/refused"

# The browser: serve each directory, load the page, read the DOM once its script has polled.
page() { # page DIR: the DOM of DIR/status.html as chromium shows it
  local log=$work/server-$$-$RANDOM.log port="" server
  python3 -u -m http.server 0 --bind 127.0.0.1 --directory "$1" >"$log" 2>&1 &
  server=$!
  for _ in $(seq 400); do # a python3 behind a version manager's shim starts in a second or more
    port=$(sed -n 's/.*port \([0-9]*\).*/\1/p' "$log" | head -n 1)
    [ -n "$port" ] && break
    sleep 0.05
  done
  timeout 60 "$browser" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run \
    --user-data-dir="$work/profile" --virtual-time-budget=5000 --dump-dom "http://127.0.0.1:$port/status.html" \
    2>/dev/null || true
  kill "$server"
  wait "$server" 2>/dev/null || true
}
page "$work/drop" >"$work/drop.dom"
grep -q '<b id="time">0.500000</b>' "$work/drop.dom" && ok || fail "the drop's page does not show t = 0.5 s: $(grep -o '<b id="time">[^<]*' "$work/drop.dom")"
grep -q "De-fluidization: the bottom layer's minimum fluidization velocity reached the gas velocity at t = 0.3 s" \
  "$work/drop.dom" && ok || fail "the drop's page shows no de-fluidization warning"
grep -q "<polyline" "$work/drop.dom" && ok || fail "the drop's page draws no curve"
page "$work/steady" >"$work/steady.dom"
grep -q '<b id="time">0.500000</b>' "$work/steady.dom" && ok || fail "the steady page does not show t = 0.5 s"
if grep -q "De-fluidization" "$work/steady.dom"; then fail "the steady page shows a warning"; else ok; fi
grep -q "No warning: the bed is fluidized." "$work/steady.dom" && ok || fail "the steady page does not say there is no warning"
grep -q "<td>0.500000 s, 0.1500 s ahead, 2 members, holding the latest conditions</td>" "$work/drop.dom" && ok ||
  fail "the drop's page does not say its forecast holds the latest conditions"
page "$work/whatif" >"$work/whatif.dom"
grep -qF "<td>0.500000 s, 0.1500 s ahead, 2 members, under the what-if $work/whatif.csv</td>" "$work/whatif.dom" && ok ||
  fail "the what-if page does not name its schedule: $(grep -o '<th>forecast issued at</th><td>[^<]*' "$work/whatif.dom")"
page "$work/switch-at-stop" >"$work/switch-at-stop.dom"
grep -qF "<b id=\"database\">$work/b.h5</b>" "$work/switch-at-stop.dom" && ok ||
  fail "the page at the stop does not name b.h5: $(grep -o '<b id="database">[^<]*' "$work/switch-at-stop.dom")"
page "$work/switch" >"$work/switch.dom"
grep -qF "<b id=\"database\">$work/a.h5</b>" "$work/switch.dom" && ok ||
  fail "the page at the end does not name a.h5: $(grep -o '<b id="database">[^<]*' "$work/switch.dom")"
page "$work/gran" >"$work/gran.dom"
grep -q "<th>forecast product</th><td>0.06000 ± [^<]* kg over 0.3000 s; shares d1.500mm 0\.[0-9]*, d2.500mm" "$work/gran.dom" && ok ||
  fail "the granulator's page shows no forecast product: $(grep -o '<th>forecast product[^/]*' "$work/gran.dom")"
[ "$(grep -o 'class="forecast-share"' "$work/gran.dom" | wc -l)" -eq 3 ] && ok ||
  fail "the granulator's page draws $(grep -o 'class="forecast-share"' "$work/gran.dom" | wc -l) forecast product bars, expected 3"
page "$work/spray" >"$work/spray.dom"
grep -q "members' bottom layers get wet near de-fluidization" "$work/spray.dom" && ok ||
  fail "the spray-dry page shows no forecast wet warning"
grep -q "<th>forecast bottom moisture</th><td>0\.0[0-9]* ± [^<]* kg/kg</td>" "$work/spray.dom" && ok ||
  fail "the spray-dry page shows no forecast moisture: $(grep -o '<th>forecast bottom[^/]*' "$work/spray.dom")"
# A page whose script does not run shows no time: the checks above can fail.
sed -i 's/^refresh();$/refresh(;/' "$work/drop/status.html"
page "$work/drop" >"$work/broken.dom"
if grep -q '<b id="time">0.500000</b>' "$work/broken.dom"; then fail "a broken page showed the time"; else ok; fi

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
