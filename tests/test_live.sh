#!/usr/bin/env bash
# rcfd run -live FILE (docs/live.md), on small synthetic beds recorded at two
# gas velocities: a live run fed a schedule's u_sup gives the schedule run's
# files byte for byte (schedule and blend rules; one database's bottom.csv
# against -superficial_velocity); the granulator's rates from the file give the
# options' bits, and a feed rate that changes feeds its integral to 1e-12; a
# file written in bursts (pauses, a partial last line) gives the bits of the
# file written at once, and the run waited for it; an unknown column, NaN,
# backwards time, a malformed line, a column without its operator refused in
# one sentence (with the line's number), a malformed line skipped on request;
# a run stopped by its stop file and one stopped by SIGTERM while waiting,
# both restarted from their checkpoints, give the uninterrupted run's files
# (no row lost or repeated); 2 ranks give 1 rank's numbers.  Forecasts: the live state's bits
# unchanged, the latest conditions held, 1 = 2 ranks, a restart across them; the granulator's product
# over the horizon (its mass and shares); a what-if schedule (-forecast_schedule) equal to the held
# conditions gives the same bits, one that differs (u_sup dropping, no discharge) is followed, neither
# changes the live state; its refusals.
# usage: test_live.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 compare=$2
source "$4/tests/script_helpers.sh"
write_two_velocity_beds
a=$work/a.h5 b=$work/b.h5
common=(-fields 0 -plot 0 -monitor_digits 17 -quiet -bottom_layer -live_poll 0.02)
two=(-db "$a,$b" "${common[@]}")
series=(cog.csv bottom.csv path.txt switches.csv)

same_files() { # same_files LABEL DIR_A DIR_B FILE...: byte-identical (switches.csv: but for its first
  local label=$1 x=$2 y=$3 f # line, a comment that describes the schedule, given or measured)
  shift 3
  for f in "$@"; do
    if cmp -s <(sed '1{/^#/d}' "$x/$f") <(sed '1{/^#/d}' "$y/$f"); then ok; else fail "$label: $y/$f differs from $x/$f"; fi
  done
}
rows() { grep -vc '^[#t]' "$1"; } # data rows of a CSV file

# The schedule and its live file: u_sup from 0, 0.2 and 0.35 s, and a row at the end.
schedule=0:1.1,0.2:1.3,0.35:1.2
printf 'time_s,u_sup\n0,1.1\n0.1,1.1\n0.2,1.3\n0.35,1.2\n0.5,1.2\n' >"$work/u.csv"
for rule in schedule blend; do
  "$rcfd" run "${two[@]}" -db_switch_type $rule -db_switch_schedule $schedule -t_end 0.5 -output_dir "$work/s-$rule"
  "$rcfd" run "${two[@]}" -db_switch_type $rule -live "$work/u.csv" -live_end 0.5 -output_dir "$work/l-$rule"
  same_files "live against -db_switch_type $rule" "$work/s-$rule" "$work/l-$rule" "${series[@]}"
done
[ "$(rows "$work/s-schedule/switches.csv")" -ge 2 ] && ok || fail "the schedule did not switch"
grep -q "^# database switches (schedule of u_sup: measured, from the live file" "$work/l-schedule/switches.csv" && ok ||
  fail "switches.csv of a live run: $(head -n 1 "$work/l-schedule/switches.csv")"
# One database: the live u_sup is what -superficial_velocity gives bottom.csv.
printf 'time_s,u_sup\n0,1.25\n0.5,1.25\n' >"$work/one.csv"
"$rcfd" run -db "$a" "${common[@]}" -superficial_velocity 1.25 -t_end 0.5 -output_dir "$work/s-one"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/one.csv" -live_end 0.5 -output_dir "$work/l-one"
same_files "live u_sup on one database" "$work/s-one" "$work/l-one" cog.csv bottom.csv
# The drift scaled by the excess gas follows the live u_sup: below u_mf until 0.2 s it does not
# drift, from 0.2 s at 1.3 m/s it does, so the classes part from a run held below u_mf.
drift=(-drift_size_law drag -drift_kd 0.06 -drift_excess_gas -fractions_diameters 1.5e-3,3.5e-3
  -fractions_mass_shares 0.5,0.5)
printf 'time_s,u_sup\n0,0.05\n0.2,1.3\n0.5,1.3\n' >"$work/rise.csv"
printf 'time_s,u_sup\n0,0.05\n0.5,0.05\n' >"$work/low.csv"
"$rcfd" run -db "$a" "${common[@]}" "${drift[@]}" -live "$work/rise.csv" -live_end 0.5 -output_dir "$work/l-rise" \
  -forecast_every 0.1 -forecast_members 1 -forecast_horizon 0.2
"$rcfd" run -db "$a" "${common[@]}" "${drift[@]}" -live "$work/low.csv" -live_end 0.5 -output_dir "$work/l-low"
same "rows of cog.csv up to 0.2 s, drift below u_mf either way" \
  "$(awk -F, '!/^[#t]/ && $1 <= 0.2' "$work/l-low/cog.csv" | md5sum)" "$(awk -F, '!/^[#t]/ && $1 <= 0.2' "$work/l-rise/cog.csv" | md5sum)"
paste -d, "$work/l-low/cog.csv" "$work/l-rise/cog.csv" | awk -F, -v n="$(head -n 1 "$work/l-low/cog.csv" | awk -F, '{ print NF }')" '
  !/^[#t]/ && $1 > 0.3 { if ($(n + 5) - $5 > 1e-4) parted++ }
  END { exit !(parted > 0) }' && ok || fail "the drift did not follow the live u_sup from 0.2 s on"
# ... and so do the forecast's members (set up at t = 0, below u_mf): the one issued at 0.3 s parts
# the classes by more than a millimetre beyond the live state's delta z then (held below u_mf, a
# mixed bed's delta z stays 0).
awk -F, -v live="$(awk -F, '!/^[#t]/ && $1 > 0.299 && $1 < 0.301 { print $5 }' "$work/l-rise/cog.csv")" \
  '!/^[#t]/ && $1 > 0.299 && $1 < 0.301 { found = 1; grew = $4 - live > 1e-3 } END { exit !(found && grew) }' \
  "$work/l-rise/forecast.csv" && ok || fail "the forecast's members did not drift at the live u_sup: $(cat "$work/l-rise/forecast.csv")"

# The granulator's rates: constant ones give the options' bits; a feed rate changing at 0.1 and
# 0.3 s feeds 0.2 x 0.1 + 0.5 x 0.2 + 0.1 x 0.2 = 0.14 kg by 0.5 s.
gran=(-db "$a" "${common[@]}" -pipeline shift,drift,carry,growth,feed,discharge -zones spray,feed,discharge
  -zone_spray_box 0.07,0.13,0,0.05,0.18,0.26 -zone_feed_box 0,0.02,0,0.05,0,0.03
  -zone_discharge_box 0.18,0.2,0,0.05,0,0.03 -fractions_diameters 1.5e-3,2.5e-3,3.5e-3
  -fractions_mass_shares 0.3,0.4,0.3 -bottom_layer 0)
printf 'time_s,growth_rate,feed_rate,discharge_rate\n0,1,0.2,0.2\n0.5,1,0.2,0.2\n' >"$work/rates.csv"
"$rcfd" run "${gran[@]}" -growth_rate 1 -feed_rate 0.2 -discharge_rate 0.2 -t_end 0.5 -output_dir "$work/s-gran"
"$rcfd" run "${gran[@]}" -live "$work/rates.csv" -live_end 0.5 -output_dir "$work/l-gran"
same_files "live granulator rates" "$work/s-gran" "$work/l-gran" cog.csv mass_account.csv product.csv
# Forecasts fork the granulator's operators (their held feed, owed discharge) without touching them.
"$rcfd" run "${gran[@]}" -live "$work/rates.csv" -live_end 0.5 -forecast_every 0.25 -forecast_horizon 0.3 \
  -forecast_members 2 -output_dir "$work/l-gran-fc"
same_files "granulator with forecasts" "$work/s-gran" "$work/l-gran-fc" cog.csv mass_account.csv product.csv
# The product over each forecast's horizon: 0.2 kg/s x 0.3 s in every member, its shares summing to 1
# (to the 10 digits forecast.csv prints).
awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) c[$i] = i; next }
  { s = $c["product_share_d1.500mm_mean"] + $c["product_share_d2.500mm_mean"] + $c["product_share_d3.500mm_mean"]
    m = $c["product_mass_mean_kg"]; if (m - 0.06 > 1e-14 || 0.06 - m > 1e-14 || s - 1 > 3e-10 || 1 - s > 3e-10) bad++; n++ }
  END { exit !(n == 3 && !bad) }' "$work/l-gran-fc/forecast.csv" && ok ||
  fail "forecast.csv's product (0.06 kg, shares summing to 1): $(cat "$work/l-gran-fc/forecast.csv")"
mpiexec -n 2 "$rcfd" run "${gran[@]}" -live "$work/rates.csv" -live_end 0.5 -forecast_every 0.25 -forecast_horizon 0.3 \
  -forecast_members 2 -output_dir "$work/l-gran-fc2"
if "$compare" "$work/l-gran-fc/forecast.csv" "$work/l-gran-fc2/forecast.csv" 1e-9 1e-14 >/dev/null; then ok; else
  fail "the granulator's forecast.csv at 2 ranks: $("$compare" "$work/l-gran-fc/forecast.csv" "$work/l-gran-fc2/forecast.csv" 1e-9 1e-14)"; fi
# A what-if schedule equal to the held conditions: the same forecasts, bit for bit; one that stops the
# discharge: no product (shares unknown); neither changes the live state.
"$rcfd" run "${gran[@]}" -live "$work/rates.csv" -live_end 0.5 -forecast_every 0.25 -forecast_horizon 0.3 \
  -forecast_members 2 -forecast_schedule "$work/rates.csv" -output_dir "$work/l-gran-same"
same_files "what-if schedule equal to the held conditions" "$work/l-gran-fc" "$work/l-gran-same" forecast.csv cog.csv \
  mass_account.csv product.csv
printf 'time_s,discharge_rate\n0,0\n' >"$work/no-discharge.csv"
"$rcfd" run "${gran[@]}" -live "$work/rates.csv" -live_end 0.5 -forecast_every 0.25 -forecast_horizon 0.3 \
  -forecast_members 2 -forecast_schedule "$work/no-discharge.csv" -output_dir "$work/l-gran-nod"
same_files "a what-if forecast changes nothing in the live state" "$work/s-gran" "$work/l-gran-nod" cog.csv \
  mass_account.csv product.csv
same --nan "what-if without discharge: product mass and first share" \
  "$(awk -F, 'NR > 1 { printf "%s %s ", $13, $15 }' "$work/l-gran-nod/forecast.csv")" "0 nan 0 nan 0 nan"
printf 'time_s,feed_rate,feed_share_d1.500mm,feed_share_d2.500mm,feed_share_d3.500mm\n0,0.2,1,0,0\n0.1,0.5,1,0,0\n0.3,0.1,0,0,1\n0.5,0.1,0,0,1\n' \
  >"$work/feed.csv"
"$rcfd" run "${gran[@]}" -live "$work/feed.csv" -live_end 0.5 -output_dir "$work/l-feed"
fed=$(awk -F, '/^time/ { for (i = 1; i <= NF; ++i) if ($i ~ /^feed_/) c[i] = 1; next } /^[0-9]/ { s1 = 0;
  for (i in c) s1 += $i; last = s1 } END { printf "%.15g", last }' "$work/l-feed/mass_account.csv")
same "fed mass by 0.5 s (feed_rate 0.2, 0.5, 0.1 from 0, 0.1, 0.3 s)" "$fed" 0.14 1e-12

# Bursts: the same file written by a process, with pauses and a partial last line, while the run
# follows it (and says it waited).
(
  printf 'time_s,u_sup\n0,1.1\n0.1,1.'
  sleep 0.4
  printf '1\n0.2,1.3\n'
  sleep 0.4
  printf '0.35,1.2\n0.'
  sleep 0.3
  printf '5,1.2\n'
) >"$work/burst.csv" &
writer=$!
"$rcfd" run "${two[@]}" -quiet 0 -db_switch_type schedule -live "$work/burst.csv" -live_end 0.5 \
  -output_dir "$work/l-burst" >"$work/burst.txt" 2>&1 || fail "the burst run failed: $(cat "$work/burst.txt")"
wait $writer
same_files "live file written in bursts" "$work/l-schedule" "$work/l-burst" "${series[@]}"
grep -q "waiting for the live file" "$work/burst.txt" && ok || fail "the burst run never waited: $(cat "$work/burst.txt")"

# Refusals, one sentence each.
live_error() { # live_error "expected" CONTENT [options...]
  local expected=$1
  printf "$2" >"$work/bad.csv"
  shift 2
  # The file as its own stop file: a run that did not refuse it ends there instead of waiting.
  expect_error "$expected" run "${two[@]}" -live "$work/bad.csv" -live_stop_file "$work/bad.csv" -live_end 0.5 \
    -output_dir "$work/refused" "$@"
}
live_error "-live $work/bad.csv: the column 'humidity' is not a condition rcfd follows; the columns it knows are time_s, u_sup" \
  'time_s,u_sup,humidity\n0,1.1,3\n'
live_error "-live $work/bad.csv: the column spray_rate needs a scalar named moisture in -scalars (the liquid it adds, kg per kg solid)" \
  'time_s,spray_rate\n0,0.1\n'
live_error "-live $work/bad.csv: the column gas_temperature needs the scalars' exchange with the gas (-scalars temperature and -scalar_exchange_model gunn or constant)" \
  'time_s,gas_temperature\n0,330\n'
live_error "-live $work/bad.csv line 3: gas_temperature 0 is not a positive temperature in K (-live_on_bad_line fail)" \
  'time_s,gas_temperature\n0,330\n0.1,0\n'
live_error "-live $work/bad.csv line 2: spray_rate -0.1 is not a rate >= 0 in kg/s (-live_on_bad_line fail)" \
  'time_s,spray_rate\n0,-0.1\n'
live_error "-live $work/bad.csv line 3: u_sup is nan; expected a finite number (-live_on_bad_line fail)" \
  'time_s,u_sup\n0,1.1\n0.1,nan\n0.5,1.1\n'
live_error "-live $work/bad.csv line 4: time 0.1 s is not after the previous row's 0.2 s; times must increase" \
  'time_s,u_sup\n0,1.1\n0.2,1.2\n0.1,1.3\n0.5,1.1\n'
live_error "-live $work/bad.csv line 3: expected 2 comma-separated numbers (time_s,u_sup), got '0.1;1.2'" \
  'time_s,u_sup\n0,1.1\n0.1;1.2\n0.5,1.1\n'
live_error "-live $work/bad.csv line 2: the first row must be at time 0 s (the run's start), got 0.1 s" \
  'time_s,u_sup\n0.1,1.1\n0.5,1.1\n'
live_error "-live $work/bad.csv: the column discharge_rate needs the discharge operator in -pipeline (-pipeline shift,drift,carry has none)" \
  'time_s,discharge_rate\n0,1\n'
live_error "-live_on_bad_line never is not known; use fail (a malformed line stops the run) or skip" \
  'time_s,u_sup\n0,1.1\n' -live_on_bad_line never
live_error "-live $work/bad.csv: the column u_sup cannot drive the switching: the state switching rule does not run the bed at a u_sup over time" \
  'time_s,u_sup\n0,1.1\n' -db_switch_type state -db_switch_quantity delta_z -db_switch_thresholds 1e-3
expect_error "-ensemble 2 with -live: an ensemble's members run one after the other and cannot each follow the live file" \
  run -db "$a" -live "$work/u.csv" -path_type random -ensemble 2 -output_dir "$work/refused"
expect_error "-live is for rcfd run: a calibration replays its runs many times and follows no file" \
  calibrate -db "$a" -live "$work/u.csv" -calibrate_from measured -output_dir "$work/refused"
# Skipped on request: the run is the file without the line, and says so on stderr.
printf 'time_s,u_sup\n0,1.1\n0.1,1.1\n0.15,oops\n0.2,1.3\n0.35,1.2\n0.5,1.2\n' >"$work/skip.csv"
"$rcfd" run "${two[@]}" -live "$work/skip.csv" -live_end 0.5 -live_on_bad_line skip -output_dir "$work/l-skip" \
  2>"$work/skip.err"
same_files "a malformed line skipped" "$work/l-schedule" "$work/l-skip" "${series[@]}"
grep -q "line 4: u_sup 'oops' is not a number; skipped (-live_on_bad_line skip)" "$work/skip.err" && ok ||
  fail "the skipped line was not reported: $(cat "$work/skip.err")"

# Stopped by its stop file at 0.3 s (the rows so far followed, a checkpoint written), the rest
# appended, restarted into its own directory: the uninterrupted run's files.
for np in 1 2; do
  head -n 4 "$work/u.csv" >"$work/part$np.csv"
  printf '0.3,1.3\n' >>"$work/part$np.csv"
  touch "$work/stop$np"
  mpiexec -n $np "$rcfd" run "${two[@]}" -live "$work/part$np.csv" -live_stop_file "$work/stop$np" \
    -output_dir "$work/r$np"
  [ "$(rows "$work/r$np/cog.csv")" -eq 61 ] && ok || fail "the stop file ended the run at $(tail -n 1 "$work/r$np/cog.csv")"
  rm "$work/stop$np"
  tail -n 2 "$work/u.csv" >>"$work/part$np.csv"
  mpiexec -n $np "$rcfd" run "${two[@]}" -live "$work/part$np.csv" -live_end 0.5 -restart "$work/r$np/checkpoint.h5" \
    -output_dir "$work/r$np"
  [ $np = 1 ] && same_files "restarted after the stop file" "$work/l-schedule" "$work/r1" "${series[@]}"
  [ $np = 2 ] && mpiexec -n 2 "$rcfd" run "${two[@]}" -live "$work/u.csv" -live_end 0.5 -output_dir "$work/l2"
done
same_files "restarted after the stop file, 2 ranks" "$work/l2" "$work/r2" "${series[@]}"
for f in cog.csv bottom.csv; do
  if "$compare" "$work/l-schedule/$f" "$work/l2/$f" 1e-10 1e-14 >/dev/null; then ok; else
    fail "2 ranks: $("$compare" "$work/l-schedule/$f" "$work/l2/$f" 1e-10 1e-14)"; fi
done

# SIGTERM while the run waits for rows after 0.3 s: it checkpoints and exits cleanly; restarted
# with the rest of the file, no row lost or repeated.
head -n 4 "$work/u.csv" >"$work/sig.csv"
printf '0.3,1.3\n' >>"$work/sig.csv"
"$rcfd" run "${two[@]}" -quiet 0 -live "$work/sig.csv" -output_dir "$work/sig" >"$work/sig.txt" 2>&1 &
runner=$!
for _ in $(seq 200); do grep -q "waiting for the live file" "$work/sig.txt" && break; sleep 0.05; done
kill -TERM $runner
if wait $runner; then ok; else fail "SIGTERM: the run did not exit cleanly: $(cat "$work/sig.txt")"; fi
grep -q "Live run stopped at t = 0.3 s (step 60): a signal" "$work/sig.txt" && ok || fail "SIGTERM: $(cat "$work/sig.txt")"
tail -n 2 "$work/u.csv" >>"$work/sig.csv"
"$rcfd" run "${two[@]}" -live "$work/sig.csv" -live_end 0.5 -restart "$work/sig/checkpoint.h5" -output_dir "$work/sig"
same_files "restarted after SIGTERM" "$work/l-schedule" "$work/sig" "${series[@]}"

# Forecasts: members forked from the state change nothing in it (the live run's files, bits); they
# hold the latest conditions (a drop of u_sup to 0.9 m/s at 0.3 s: the forecasts issued before it see
# no de-fluidization within 0.15 s, those from it on see it at their first step); 2 ranks give 1
# rank's forecast.csv; a restart across forecasts gives the uninterrupted forecast.csv byte for byte.
fc=(-forecast_every 0.1 -forecast_horizon 0.15 -forecast_members 2)
"$rcfd" run "${two[@]}" -live "$work/u.csv" -live_end 0.5 "${fc[@]}" -output_dir "$work/l-fc"
same_files "a forecast changes nothing in the live state" "$work/l-schedule" "$work/l-fc" "${series[@]}"
[ "$(rows "$work/l-fc/forecast.csv")" -eq 6 ] && ok || fail "forecast.csv of l-fc: $(cat "$work/l-fc/forecast.csv")"
printf 'time_s,u_sup\n0,1.1\n0.3,0.9\n0.5,0.9\n' >"$work/drop.csv"
for np in 1 2; do
  mpiexec -n $np "$rcfd" run -db "$a" "${common[@]}" -live "$work/drop.csv" -live_end 0.5 "${fc[@]}" \
    -output_dir "$work/drop$np" 2>/dev/null
done
warned=$(awk -F, 'NR > 1 { printf "%s:%s:%s ", $1, $10, $12 }' "$work/drop1/forecast.csv")
same "forecast warnings (time:members warning:first warning in s)" "$warned" \
  "0:0:nan 0.1:0:nan 0.2:0:nan 0.3:2:0.005 0.4:2:0.005 0.5:2:0.005" 1e-9
same "bottom.csv: the live warning at 0.3 s" "$(awk -F, 'NR > 1 && $5 == 1 { print $1; exit }' "$work/drop1/bottom.csv")" 0.3
if "$compare" "$work/drop1/forecast.csv" "$work/drop2/forecast.csv" 1e-10 1e-14 >/dev/null; then ok; else
  fail "forecast.csv at 2 ranks: $("$compare" "$work/drop1/forecast.csv" "$work/drop2/forecast.csv" 1e-10 1e-14)"; fi
# A what-if u_sup: 1.1 m/s, then 0.9 from 0.05 s after each forecast's start: every forecast sees the
# warning after 11 steps (0.055 s), whatever the live file holds; one equal to the held 1.25 m/s
# changes no bit of forecast.csv.
printf 'time_s,u_sup\n0,1.1\n0.05,0.9\n' >"$work/whatif-drop.csv"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/drop.csv" -live_end 0.5 "${fc[@]}" \
  -forecast_schedule "$work/whatif-drop.csv" -output_dir "$work/drop-whatif" 2>/dev/null
same "what-if forecast warnings (time:members warning:first warning in s)" \
  "$(awk -F, 'NR > 1 { printf "%s:%s:%s ", $1, $10, $12 }' "$work/drop-whatif/forecast.csv")" \
  "0:2:0.055 0.1:2:0.055 0.2:2:0.055 0.3:2:0.055 0.4:2:0.055 0.5:2:0.055" 1e-9
same_files "what-if u_sup: the live state" "$work/drop1" "$work/drop-whatif" cog.csv bottom.csv
printf 'time_s,u_sup\n0,1.25\n' >"$work/whatif-held.csv"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/one.csv" -live_end 0.5 "${fc[@]}" -output_dir "$work/one-fc"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/one.csv" -live_end 0.5 "${fc[@]}" \
  -forecast_schedule "$work/whatif-held.csv" -output_dir "$work/one-whatif"
same_files "what-if u_sup equal to the held one" "$work/one-fc" "$work/one-whatif" forecast.csv cog.csv bottom.csv
# Refusals of the what-if schedule, one sentence each.
printf 'time_s,u_sup,spray_rate\n0,1.1,0.1\n' >"$work/whatif-bad.csv"
expect_error "-forecast_schedule $work/whatif-bad.csv: the column spray_rate needs a scalar named moisture in -scalars (the liquid it adds, kg per kg solid)" \
  run -db "$a" "${common[@]}" -t_end 0.1 "${fc[@]}" -forecast_schedule "$work/whatif-bad.csv" -output_dir "$work/refused"
expect_error "-forecast_schedule $work/whatif-held.csv: the column u_sup and -superficial_velocity 1.2 both give the forecast's u_sup; give it once" \
  run -db "$a" "${common[@]}" -t_end 0.1 -superficial_velocity 1.2 "${fc[@]}" -forecast_schedule "$work/whatif-held.csv" \
  -output_dir "$work/refused"
expect_error "-forecast_schedule $work/none.csv: cannot read the file" \
  run -db "$a" "${common[@]}" -t_end 0.1 "${fc[@]}" -forecast_schedule "$work/none.csv" -output_dir "$work/refused"
printf 'time_s,u_sup\n0.1,1.1\n' >"$work/whatif-late.csv"
expect_error "-forecast_schedule $work/whatif-late.csv line 2: the first row must be at time 0 s (the forecast's start), got 0.1 s" \
  run -db "$a" "${common[@]}" -t_end 0.1 "${fc[@]}" -forecast_schedule "$work/whatif-late.csv" -output_dir "$work/refused"
printf 'time_s,u_sup\n' >"$work/whatif-empty.csv"
expect_error "-forecast_schedule $work/whatif-empty.csv: the file holds no row; expected a header (time_s and the conditions) and a row at time 0" \
  run -db "$a" "${common[@]}" -t_end 0.1 "${fc[@]}" -forecast_schedule "$work/whatif-empty.csv" -output_dir "$work/refused"
printf 'time_s,u_sup\n0,1.1\n0.05,-1\n' >"$work/whatif-neg.csv"
expect_error "-forecast_schedule $work/whatif-neg.csv line 3: u_sup -1 is not a positive velocity in m/s" \
  run -db "$a" "${common[@]}" -t_end 0.1 "${fc[@]}" -forecast_schedule "$work/whatif-neg.csv" -output_dir "$work/refused"
head -n 2 "$work/drop.csv" >"$work/drop-part.csv"
printf '0.25,1.1\n' >>"$work/drop-part.csv"
touch "$work/stop-drop"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/drop-part.csv" -live_stop_file "$work/stop-drop" "${fc[@]}" \
  -output_dir "$work/drop-r" 2>/dev/null
tail -n 2 "$work/drop.csv" >>"$work/drop-part.csv"
"$rcfd" run -db "$a" "${common[@]}" -live "$work/drop-part.csv" -live_end 0.5 "${fc[@]}" \
  -restart "$work/drop-r/checkpoint.h5" -output_dir "$work/drop-r" 2>/dev/null
same_files "forecasts across a restart" "$work/drop1" "$work/drop-r" forecast.csv cog.csv bottom.csv

echo "$passed checks passed, $failures failed"
[ "$failures" -eq 0 ]
