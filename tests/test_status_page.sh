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
# A page whose script does not run shows no time: the checks above can fail.
sed -i 's/^refresh();$/refresh(;/' "$work/drop/status.html"
page "$work/drop" >"$work/broken.dom"
if grep -q '<b id="time">0.500000</b>' "$work/broken.dom"; then fail "a broken page showed the time"; else ok; fi

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
