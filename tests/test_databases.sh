#!/usr/bin/env bash
# Runs on several databases (docs/databases.md), on small synthetic beds recorded
# at two conditions: a mesh or dt_rec mismatch refused with its sentence; a
# database blended with itself runs as the database alone (to round-off); the
# schedule switches at its times and every switch keeps every fraction's mass
# (1e-12, ledger off) and no mass negative; markov switch times the same at 1
# and 2 ranks and after a restart across a switch (byte for byte); the
# validity warning once, at the step the schedule leaves the databases'
# range; bottom.csv's u_sup the schedule's at every row, also between the
# databases', and the warning's umf_usup bottom.csv's ratio (1 and 2 ranks, a
# restart); a blend restarted while active (byte for byte); the state rule
# switching on the bottom layer's d32; databases of different lengths (masses,
# 1 and 2 ranks, a restart across a switch, every wrap in jumps.csv); a blend
# paired by recurrence stepping its second database's wrap inside it as a jump
# (bulk, masses, 1 and 2 ranks); at most one database held by a schedule over
# four, two by a blend.
# usage: test_databases.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -eu
rcfd=$1 compare=$2
source "$4/tests/script_helpers.sh"
write_two_velocity_beds
"$rcfd" synth -o "$work/tall.h5" -synth_cells 10,2,30 -synth_frames 40 -synth_warm_up 0.2 -quiet
"$rcfd" synth -o "$work/slow.h5" "${bed[@]}" -synth_dt 0.01
a=$work/a.h5 b=$work/b.h5
common=(-fields 0 -monitor_digits 17 -t_end 0.5)

expect_error "Databases '$a' and '$work/tall.h5' are on different meshes (10 x 2 x 20 cells" \
  run -db "$a,$work/tall.h5" -db_switch_schedule 0:1.1 -output_dir "$work/refused"
expect_error "Databases '$a' and '$work/slow.h5' were recorded with different dt_rec (0.005 s and 0.01 s)" \
  run -db "$a,$work/slow.h5" -db_switch_schedule 0:1.1 -output_dir "$work/refused"
expect_error "-db_conditions has 3 superficial velocities for the 2 databases of -db" \
  run -db "$a,$b" -db_conditions 1,2,3 -db_switch_schedule 0:1.1 -output_dir "$work/refused"
expect_error "-superficial_velocity 1.2 and the schedule rule's -db_switch_schedule both give u_sup; give it once" \
  run -db "$a,$b" -db_switch_schedule 0:1.1 -superficial_velocity 1.2 -bottom_layer -output_dir "$work/refused"

# A database blended with itself (weight 1/2) is the database.
"$rcfd" run -db "$a" "${common[@]}" -quiet -output_dir "$work/alone"
"$rcfd" run -db "$a,$a" -db_conditions 1.0,1.2 -db_switch_type blend -db_switch_schedule 0:1.1 "${common[@]}" -quiet \
  -output_dir "$work/self"
if "$compare" "$work/alone/cog.csv" "$work/self/cog.csv" 1e-12 1e-15 >/dev/null; then ok; else
  fail "a database blended with itself: $("$compare" "$work/alone/cog.csv" "$work/self/cog.csv" 1e-12 1e-15)"; fi
# Ensembles and calibrations share one loaded database: refused before anything runs, saying what to do.
expect_error "-ensemble 2 with several databases in -db: an ensemble's members share one loaded database" \
  run -db "$a,$b" -db_switch_schedule 0:1.1 -ensemble 2 -path_type random -output_dir "$work/refused"
expect_error "calibrate on each database of the set alone (-db a.h5), then run the set" \
  calibrate -db "$a,$b" -db_switch_schedule 0:1.1 -reference "$work/alone/cog.csv" -output_dir "$work/refused"

# Schedule: 1.1 -> 1.3 -> (1.2: nearest of a tie is the first) -> 1.5 (outside: warned once, step 80).
"$rcfd" run -db "$a,$b" -db_switch_schedule 0:1.1,0.1:1.3,0.2:1.2,0.25:1.3,0.4:1.5 -mass_check_every 0 "${common[@]}" \
  -output_dir "$work/schedule" >"$work/schedule.txt"
same "switch times and targets" "$(awk -F, '/switch$/ {print $1, $2, $3}' "$work/schedule/switches.csv")" \
  "0.1 0 1 0.2 1 0 0.25 0 1"
same "the warning's row" "$(awk -F, '/extrapolating$/ {print $1, $4}' "$work/schedule/switches.csv")" "0.4 1.5"
same "the warning, once" "$(grep -c 'rcfd is extrapolating from t = 0.4 s (step 80): u_sup = 1.5 m/s' "$work/schedule.txt")" 1
same "printed switches" "$(grep -c '^Switched from database' "$work/schedule.txt")" 3
# masses_kept DIR: every fraction's mass through the run in DIR/cog.csv to 1e-12, and no negative cell mass.
masses_kept() {
  local worst
  worst=$(awk -F, 'NR == 2 {a = $6; b = $7} NR > 2 { for (i = 6; i <= 7; ++i) { r = ($i - (i == 6 ? a : b)) / (i == 6 ? a : b);
    if (r < 0) r = -r; if (r > w) w = r } if ($8 < 0) neg = 1 } END { print (neg ? 1 : w + 0) }' "$1/cog.csv")
  if awk -v w="$worst" 'BEGIN { exit !(w < 1e-12) }'; then ok; else fail "$1: mass changed by $worst across switches (or went negative)"; fi
}
masses_kept "$work/schedule" # switches at rows 21, 41, 51

# alike NAME ARGS...: a run at 1 and at 2 ranks with a checkpoint at 0.2 s, and each again from that
# checkpoint: switches.csv, cog.csv, path.txt, jumps.csv (and bottom.csv, when written) byte for byte
# after the restart; switches.csv and jumps.csv the same and cog.csv (bottom.csv) within 1e-10 at 2 ranks.
alike() {
  local name=$1 written=(switches.csv cog.csv path.txt jumps.csv) near=(cog.csv)
  shift
  for np in 1 2; do
    mpiexec -n $np "$rcfd" run "$@" -checkpoint_every 0.2 -output_dir "$work/$name$np"
    mpiexec -n $np "$rcfd" run "$@" -restart "$work/$name$np/checkpoint.h5" -output_dir "$work/${name}_again$np"
    if [ $np = 1 ] && [ -f "$work/${name}1/bottom.csv" ]; then written+=(bottom.csv) near+=(bottom.csv); fi
    for f in "${written[@]}"; do
      if cmp -s "$work/$name$np/$f" "$work/${name}_again$np/$f"; then ok; else fail "$name, restart at $np ranks: $f differs"; fi
    done
  done
  for f in switches.csv jumps.csv; do
    if cmp -s "$work/${name}1/$f" "$work/${name}2/$f"; then ok; else fail "$name: $f differs at 2 ranks"; fi
  done
  for f in "${near[@]}"; do
    if "$compare" "$work/${name}1/$f" "$work/${name}2/$f" 1e-10 1e-14 >/dev/null; then ok; else
      fail "$name at 2 ranks: $("$compare" "$work/${name}1/$f" "$work/${name}2/$f" 1e-10 1e-14)"; fi
  done
}

# The operating u_sup is the schedule's, also between the databases' (1.25 on b without a switch, 1.15 on a
# without one) as where it is one's (1.3, 1.1): bottom.csv's usup_m_s is the schedule's value at every row
# (the nearest database's, 1.3 and 1.1, before).  In the gas of -gas_density 0.68 (u_mf 1.268 m/s) the bottom
# de-fluidizes when the schedule goes down to 1.25 at 0.1 s: bottom.csv's first de-fluidized row and the
# switcher's validity warning are there, its trigger (umf_usup) bottom.csv's u_mf/u_sup.  1 and 2 ranks
# alike, and a restart from 0.2 s (after the switch to a; 1.15 from 0.3 s) byte for byte.
alike operating -db "$a,$b" -db_switch_schedule 0:1.3,0.1:1.25,0.2:1.1,0.3:1.15 -bottom_layer -gas_density 0.68 \
  -quiet "${common[@]}"
for np in 1 2; do
  got=$(awk -F, 'NR > 1 { u = $1 < 0.1 - 1e-9 ? 1.3 : $1 < 0.2 - 1e-9 ? 1.25 : $1 < 0.3 - 1e-9 ? 1.1 : 1.15
    if ($4 != u) ++off; if ($5 == 1 && first == "") first = $1; if ($1 == 0.1) ratio = $3 / $4 }
    END { printf "%d %d %s %.12g", NR - 1, off, first, ratio }' "$work/operating$np/bottom.csv")
  warned=$(awk -F, '/extrapolating$/ {print $1, $4}' "$work/operating$np/switches.csv")
  same "the operating u_sup at $np ranks: rows, rows off the schedule, first de-fluidized row" "${got% *}" "101 0 0.1"
  same "the validity warning and its umf_usup at $np ranks" "$warned" "0.1 ${got##* }" 1e-9
done
# A blend's u_sup is the schedule's too, where it leaves the databases' range and runs on the nearest
# alone (1.5 from 0.1 s; b's 1.3 before).
"$rcfd" run -db "$a,$b" -db_switch_type blend -db_switch_schedule 0:1.15,0.05:1.2,0.1:1.5 -bottom_layer "${common[@]}" \
  -t_end 0.15 -output_dir "$work/blend_usup" >/dev/null
same "a blend's u_sup: rows off the schedule" "$(awk -F, 'NR > 1 { u = $1 < 0.05 - 1e-9 ? 1.15 : $1 < 0.1 - 1e-9 ? 1.2 : 1.5
  if ($4 != u) ++off } END { print NR - 1, off + 0 }' "$work/blend_usup/bottom.csv")" "31 0"

# Markov: the same switches at 1 and 2 ranks, and after a restart from a checkpoint after a switch.
alike markov -db "$a,$b" -db_switch_type markov -db_switch_interval 0.05 -db_switch_seed 3 -quiet "${common[@]}"
same "markov switches" "$(grep -c 'switch$' "$work/markov1/switches.csv")" 6
# Blend: restarted from a checkpoint (0.4 s) while a blend is active, byte for byte.
blend=(-db "$a,$b" -db_switch_type blend -db_switch_schedule 0:1.1,0.1:1.2,0.3:1.25 -quiet "${common[@]}")
"$rcfd" run "${blend[@]}" -checkpoint_every 0.2 -output_dir "$work/blend"
"$rcfd" run "${blend[@]}" -restart "$work/blend/checkpoint.h5" -output_dir "$work/blend_again"
got=$(awk -F, '/switch$/ {printf "%s %s ", $1, $3}' "$work/blend/switches.csv")
if [ "$got" = "0.1 0+1@0.5 0.3 0+1@0.25 " ]; then ok; else fail "blend switches: got '$got'"; fi
for f in switches.csv cog.csv; do
  if cmp -s "$work/blend/$f" "$work/blend_again/$f"; then ok; else fail "blend restart: $f differs"; fi
done
# A checkpoint of a run on several databases is refused by a run on one.
expect_error "continues a run made with another database" \
  run -db "$a" -quiet "${common[@]}" -restart "$work/markov1/checkpoint.h5" -output_dir "$work/refused"

# State: the bottom layer's d32 rises through 2.3305 mm (margin 1e-5): one switch, to database 1.
"$rcfd" run -db "$a,$b" -db_switch_type state -db_switch_quantity bottom_d32 -db_switch_thresholds 0.0023305 \
  -db_switch_hysteresis 1e-5 -quiet "${common[@]}" -output_dir "$work/state"
same "state switch" "$(awk -F, '/switch$/ {print $2, $3, ($4 > 0.0023305 * (1 + 1e-5))}' "$work/state/switches.csv")" "0 1 1"

# State on a monitor's signal: cog.csv's delta_z, sampled every 20 steps (0.1 s), passes 2.5e-4 m
# between the samples at 0.1 and 0.2 s, so the run switches at the step after the 0.2 s sample (the
# rule sees a monitor's latest sample).  A run stopped at 0.2 s and restarted from its checkpoint
# (which keeps that sample) writes the same files byte for byte: without it, it would switch 0.1 s late.
signal=(-db "$a,$b" -db_switch_type state -db_switch_quantity delta_z -db_switch_thresholds 2.5e-4
  -db_switch_hysteresis 1e-5 -monitor_every 20 -quiet "${common[@]}")
"$rcfd" run "${signal[@]}" -output_dir "$work/signal"
same "switch on delta_z" "$(awk -F, '/switch$/ {print $1, $2, $3}' "$work/signal/switches.csv")" "0.205 0 1"
"$rcfd" run "${signal[@]}" -t_end 0.2 -checkpoint_every 0.2 -output_dir "$work/signal2"
"$rcfd" run "${signal[@]}" -restart "$work/signal2/checkpoint.h5" -output_dir "$work/signal2"
for f in switches.csv cog.csv path.txt; do
  if cmp -s "$work/signal/$f" "$work/signal2/$f"; then ok; else fail "restart before a switch on delta_z: $f differs"; fi
done
expect_error "The state switching rule decides on 'nonsense', which is neither a built-in signal (inventory_d32, \
bottom_d32, umf_usup) nor one of this run's monitors' (delta_z, z_cog_bed)" run "${signal[@]}" \
  -db_switch_quantity nonsense -output_dir "$work/refused"

# Databases of different lengths: a (40 frames, 1.1 m/s) and a 25-frame bed at 1.3 m/s.  The path runs over
# a's frames; the short one takes the path's frame modulo 25 (a jump where it wraps).  Masses kept across the
# switches, the same at 1 and 2 ranks, and a restart from a checkpoint (0.2 s) while the short one is active
# writes the same files byte for byte.
"$rcfd" synth -o "$work/c25.h5" -synth_cells 10,2,20 -synth_frames 25 -synth_warm_up 0.2 -quiet \
  -synth_nucleation_rate 4000 -synth_seed 2 -superficial_velocity 1.3
alike lengths -db "$a,$work/c25.h5" -db_switch_schedule 0:1.1,0.1:1.3,0.35:1.1 -mass_check_every 0 -quiet "${common[@]}"
masses_kept "$work/lengths1"
masses_kept "$work/lengths2"
same "switches between different lengths" "$(awk -F, '/switch$/ {print $1, $2, $3}' "$work/lengths1/switches.csv")" "0.1 0 1 0.35 1 0"
# The short bed's bulk is followed through its wraps: cog.csv's mismatch against the frame in use stays at
# the beds' own (4e-7; 0.07 when its wrap is not stepped as a jump).
worst=$(awk -F, 'NR > 1 && $1 > 0.1 && $1 < 0.35 && $9 > w {w = $9} END {print w + 0}' "$work/lengths1/cog.csv")
if awk -v w="$worst" 'BEGIN { exit !(w < 1e-5) }'; then ok; else fail "different lengths: the bulk strays $worst from the short bed's frames"; fi
# jumps.csv lists every step taken as a jump, in the frames of the database in use: the short bed's own wraps
# (after the path's frames 24 and 64, its frame 24 to 0), the path's wrap while it is in use (its frame 14 to
# 0) and a's wrap after the switch back (39 to 0).
same "jumps between different lengths" "$(tail -n +3 "$work/lengths1/jumps.csv" | cut -d, -f1-5 | tr ',' ' ' | paste -sd' ')" \
  "25 0.125 24 0 1 40 0.2 14 0 1 65 0.325 24 0 1 80 0.4 39 0 0"

# A blend paired by recurrence: a with the same bed recorded from 7 frames later (a7's frame j is a's j + 7)
# pairs a's frame k with a7's k + 33 (mod 40), a's own for k >= 7, so a7 wraps inside the blend after its
# frame 6.  The run steps that frame as a jump: the bulk follows the blend's frames there (3e-7; 0.032 from
# that row to the path's wrap when it is stepped as a shift), every mass is kept and none goes negative, the
# same at 1 and 2 ranks and across a restart, and jumps.csv lists it.
"$rcfd" synth -o "$work/a7.h5" "${bed[@]}" -synth_warm_up 0.235 -synth_nucleation_rate 1500 -synth_seed 1 \
  -superficial_velocity 1.1
alike lagged -db "$a,$work/a7.h5" -db_conditions 1.0,1.2 -db_switch_type blend -db_switch_schedule 0:1.1 \
  -db_blend_pairing recurrence -mass_check_every 0 -plot false "${common[@]}" -quiet
masses_kept "$work/lagged1"
masses_kept "$work/lagged2"
same "jumps of a lagged blend" "$(tail -n +3 "$work/lagged1/jumps.csv" | cut -d, -f1,3,4 | tr ',' ' ' | paste -sd' ')" \
  "7 6 7 40 39 0 47 6 7 80 39 0 87 6 7"
"$rcfd" run -db "$a,$work/a7.h5" -db_conditions 1.0,1.2 -db_switch_type blend -db_switch_schedule 0:1.1 \
  -db_blend_pairing recurrence -fields 0 -t_end 0.01 -output_dir "$work/lagview" -run_view >"$work/lagview.txt"
same "the lag -run_view names" "$(sed -n 's/.*blend of 0 and 1 paired by recurrence: frame k with frame k + \([0-9]*\) of 1.*/\1/p' "$work/lagview.txt")" "33"
for np in 1 2; do
  worst=$(awk -F, 'NR > 1 && $9 > w {w = $9} END {print w + 0}' "$work/lagged$np/cog.csv")
  if awk -v w="$worst" 'BEGIN { exit !(w < 1e-5) }'; then ok; else fail "lagged blend at $np ranks: the bulk strays $worst from the blend's frames"; fi
done

# Memory: a schedule over four databases reads each when it is switched to and holds one at a time (the
# summary's count of the set); a blend holds its two while it is made, and keeps neither: a+b, then b+c
# read again, then a alone is 5 loads.
"$rcfd" run -db "$a,$b,$work/c25.h5,$a" -db_conditions 1.1,1.2,1.3,1.4 \
  -db_switch_schedule 0:1.1,0.1:1.2,0.2:1.3,0.3:1.4,0.4:1.1 "${common[@]}" -output_dir "$work/four" >"$work/four.txt"
same "four databases: switches, loads, held" "$(sed -n 's/.*databases: \([0-9]*\) switches, \([0-9]*\) loads.*at most \([0-9]*\) held.*/\1 \2 \3/p' "$work/four.txt")" "4 5 1"
"$rcfd" run -db "$a,$b,$work/c25.h5" -db_conditions 1.1,1.2,1.3 -db_switch_type blend \
  -db_switch_schedule 0:1.15,0.1:1.25,0.2:1.1 "${common[@]}" -output_dir "$work/blend3" >"$work/blend3.txt"
same "three databases blended: switches, loads, held" "$(sed -n 's/.*databases: \([0-9]*\) switches, \([0-9]*\) loads.*at most \([0-9]*\) held.*/\1 \2 \3/p' "$work/blend3.txt")" "2 5 2"

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
