#!/usr/bin/env bash
# rcfd markov on the small synthetic database: the same numbers on 1 and 2
# ranks (every CSV within 1e-12, the eigenvalue-derived ones within SLEPc's
# tolerance), absorbed + left = 1 for a zone, and bad input refused with one
# sentence before any output is written.
# usage: test_markov_cli.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 compare=$2 data=$3
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
export PATH=/usr/bin:$PATH
db=$data/small.h5
common=(-zones low -zone_low_layers 0,4 -markov_mix_starts all -markov_mix_alpha_min 0.3 -markov_mix_horizon 60
  -markov_mix_tolerance 0.3
  -markov_departures 6 -markov_passage_horizon 5 -markov_passes_time 1 -markov_passes_max 8 -quiet)
# Two size classes drifting by law B: each class's chain.
classes=(-zones low,top -zone_low_layers 0,4 -zone_top_layers 8,11 -markov_mix_alpha_min 0.3 -markov_mix_horizon 20 -markov_mix_tolerance 0.3
  -markov_departures 6 -markov_passage_horizon 5 -quiet -fractions_diameters 1e-3,3e-3 -fractions_mass_shares 0.5,0.5
  -drift_model B -drift_kd 5e4 -markov_passes_time 1 -markov_passes_max 8)
mpiexec -n 1 "$rcfd" markov "$db" "${common[@]}" -plot 1 -o "$work/np1" && ok || fail "rcfd markov on 1 rank failed"
mpiexec -n 2 "$rcfd" markov "$db" "${common[@]}" -o "$work/np2" && ok || fail "rcfd markov on 2 ranks failed"
# Propagations: the sums over cells differ in order only (1e-12).  lambda2_decay
# comes from SLEPc's eigenvalue (1e-8 absolute on numbers below 1).
"$compare" "$work/np1/mixing.csv" "$work/np2/mixing.csv" 1e-12 && ok || fail "mixing.csv differs between 1 and 2 ranks"
"$compare" "$work/np1/relaxation.csv" "$work/np2/relaxation.csv" 1e-12 1e-15 lambda2_decay=1e-8 && ok ||
  fail "relaxation.csv differs between 1 and 2 ranks"
"$compare" "$work/np1/zone_low.csv" "$work/np2/zone_low.csv" 1e-12 1e-15 && ok || fail "zone_low.csv differs"
"$compare" "$work/np1/passes_low.csv" "$work/np2/passes_low.csv" 1e-12 1e-15 && ok || fail "passes_low.csv differs"
value() { grep "^$2," "$1/summary.csv" | cut -d, -f2; }
# Size classes (the drift linearised on the mean composition): the same on 2 ranks; the small class
# spends less of its time in the low zone than the large one (Kac's share: 0.46 against 0.76) and
# more in the top zone, the bed's surface (0.073 against 0.056).
mpiexec -n 1 "$rcfd" markov "$db" "${classes[@]}" -o "$work/classes1" && ok || fail "rcfd markov with classes, 1 rank"
mpiexec -n 2 "$rcfd" markov "$db" "${classes[@]}" -o "$work/classes2" && ok || fail "rcfd markov with classes, 2 ranks"
"$compare" "$work/classes1/classes.csv" "$work/classes2/classes.csv" 1e-12 1e-15 && ok || fail "classes.csv differs"
"$compare" "$work/classes1/zone_low_d1.000mm.csv" "$work/classes2/zone_low_d1.000mm.csv" 1e-12 1e-15 && ok ||
  fail "zone_low_d1.000mm.csv differs"
kac() { awk -F, -v c="$2" -v z="$3" '$1 == c && $3 == z { print $6 }' "$1/classes.csv"; }
awk -v s="$(kac "$work/classes1" d1.000mm low)" -v l="$(kac "$work/classes1" d3.000mm low)" 'BEGIN { exit !(s > 0 && l > s + 0.1) }' &&
  ok || fail "low zone's share of time: small class $(kac "$work/classes1" d1.000mm low), large $(kac "$work/classes1" d3.000mm low)"
awk -v s="$(kac "$work/classes1" d1.000mm top)" -v l="$(kac "$work/classes1" d3.000mm top)" 'BEGIN { exit !(l > 0 && s > 1.2 * l) }' &&
  ok || fail "top zone's share of time: small class $(kac "$work/classes1" d1.000mm top), large $(kac "$work/classes1" d3.000mm top)"
awk -F, 'NR > 2 && !($9 < 1e-12) { bad = 1 } END { exit bad }' "$work/classes1/classes.csv" && ok ||
  fail "a class's absorbed + left is not 1 within 1e-12"
# Each class's drift read off as a matrix per frame (the default) against the drift operator at
# every step: the same numbers (the conservation column is round-off, 1e-15, in both).
mpiexec -n 1 "$rcfd" markov "$db" "${classes[@]}" -markov_class_drift operator -o "$work/classes_op" && ok ||
  fail "rcfd markov -markov_class_drift operator"
"$compare" "$work/classes1/classes.csv" "$work/classes_op/classes.csv" 1e-12 1e-15 conservation=1e-14 && ok ||
  fail "classes.csv differs between -markov_class_drift matrix and operator"
for f in zone_top_d1.000mm.csv passes_low_d3.000mm.csv passes_top_d1.000mm.csv; do
  "$compare" "$work/classes1/$f" "$work/classes_op/$f" 1e-12 1e-15 && ok ||
    fail "$f differs between -markov_class_drift matrix and operator"
done
"$compare" "$work/classes1/passes_top_d1.000mm.csv" "$work/classes2/passes_top_d1.000mm.csv" 1e-12 1e-15 && ok ||
  fail "passes_top_d1.000mm.csv differs between 1 and 2 ranks"
# Per class, the pass counts: each distribution sums to 1 (to the files' 10 digits), and the small class enters the top zone,
# the bed's surface, more often within 1 s than the large one (0.46 against 0.27 entries).
for f in "$work"/classes1/passes_*_d*.csv; do
  awk -F, 'NR > 2 { s += $2 } END { exit !(s > 1 - 1e-9 && s < 1 + 1e-9) }' "$f" && ok || fail "$(basename "$f") does not sum to 1"
done
passes() { awk -F, -v c="$2" -v z="$3" '$1 == c && $3 == z { print $10 }' "$1/classes.csv"; }
awk -v s="$(passes "$work/classes1" d1.000mm top)" -v l="$(passes "$work/classes1" d3.000mm top)" 'BEGIN { exit !(l > 0 && s > 1.3 * l) }' &&
  ok || fail "entries into the top zone within 1 s: small class $(passes "$work/classes1" d1.000mm top), large $(passes "$work/classes1" d3.000mm top)"
"$compare" "$work/np1/stationary.csv" "$work/np2/stationary.csv" 1e-12 1e-15 stationary_share=1e-8 && ok ||
  fail "stationary.csv differs"
# The period chain (-markov_spectrum period), the wrap carried: the synthetic frames move alpha_k
# onto alpha_{k+1} and the carry closes the wrap, so frame 0's share is its stationary distribution
# (to SLEPc's tolerance) and lambda1 = 1; each class's too, the small class's centre above the large's.
period=(-markov_spectrum period -markov_wrap carry -markov_mix 0 -quiet -fractions_diameters 1e-3,3e-3
  -fractions_mass_shares 0.5,0.5 -drift_model B -drift_kd 5e4)
mpiexec -n 1 "$rcfd" markov "$db" "${period[@]}" -o "$work/period1" && ok || fail "rcfd markov -markov_spectrum period, 1 rank"
mpiexec -n 2 "$rcfd" markov "$db" "${period[@]}" -o "$work/period2" && ok || fail "rcfd markov -markov_spectrum period, 2 ranks"
awk -v r="$(value "$work/period1" period_residual)" -v l="$(value "$work/period1" period_stationary_l1)" \
  -v m="$(value "$work/period1" period_lambda1)" 'BEGIN { exit !(r != "" && r < 1e-14 && l < 1e-10 && m - 1 < 1e-10 && 1 - m < 1e-10) }' &&
  ok || fail "period chain: |P m0 - m0| $(value "$work/period1" period_residual), L1 $(value "$work/period1" period_stationary_l1), lambda1 $(value "$work/period1" period_lambda1)"
awk -v s="$(value "$work/period1" class_d1.000mm_period_height)" -v l="$(value "$work/period1" class_d3.000mm_period_height)" \
  -v b="$(value "$work/period1" period_height)" 'BEGIN { exit !(s != "" && s > b + 0.02 && l < b - 0.02) }' &&
  ok || fail "period chain's centres: small $(value "$work/period1" class_d1.000mm_period_height), large $(value "$work/period1" class_d3.000mm_period_height), bulk $(value "$work/period1" period_height)"
"$compare" "$work/period1/stationary.csv" "$work/period2/stationary.csv" 1e-12 1e-15 stationary_share=1e-8 \
  period_stationary_share=1e-8 period_stationary_d1.000mm=1e-8 period_stationary_d3.000mm=1e-8 && ok ||
  fail "stationary.csv with the period chain differs between 1 and 2 ranks"
awk -v a="$(value "$work/period1" class_d3.000mm_period_relaxation_time)" -v b="$(value "$work/period2" class_d3.000mm_period_relaxation_time)" \
  'BEGIN { exit !(a > 0 && (a - b < 1e-6 * a && b - a < 1e-6 * a)) }' && ok ||
  fail "the large class's period relaxation time: $(value "$work/period1" class_d3.000mm_period_relaxation_time) vs $(value "$work/period2" class_d3.000mm_period_relaxation_time)"
# The classes' background from their own chains (-markov_class_background stationary): the
# iteration's fixed point is the run's own periodic state, so each class's period stationary centre
# is a long run's at frame 0 (30 s, 25 periods: the small class 0.1733 m, the large 0.0960 m) within
# 1 mm, where the mean composition's chain is off by about a centimetre (0.1837 and 0.0859 m); the
# same on 2 ranks (1e-8), and the iterations' changes shrink to the tolerance.
mpiexec -n 1 "$rcfd" markov "$db" "${period[@]}" -markov_class_background stationary -o "$work/background1" && ok ||
  fail "rcfd markov -markov_class_background stationary, 1 rank"
mpiexec -n 2 "$rcfd" markov "$db" "${period[@]}" -markov_class_background stationary -o "$work/background2" && ok ||
  fail "rcfd markov -markov_class_background stationary, 2 ranks"
"$rcfd" run -db "$db" -fractions_diameters 1e-3,3e-3 -fractions_mass_shares 0.5,0.5 -drift_model B -drift_kd 5e4 \
  -t_end 30 -profiles -profiles_window 30,30 -observables_every 300 -output_dir "$work/segregated" -quiet -plot 0 && ok ||
  fail "the 30 s run to compare the classes' background with"
centres=$(awk -F, '!/^#/ && $1 != "z" { s += $1 * $2; n += $2; l += $1 * $3; m += $3 } END { printf "%.6f %.6f", s / n, l / m }' \
  "$work/segregated/profiles.csv")
read -r small large <<<"$centres"
for dir in background1 period1; do
  tol=1e-3 && [ $dir = period1 ] && tol=-5e-3 # the mean composition's chain: off by more than 5 mm
  awk -v s="$(value "$work/$dir" class_d1.000mm_period_height)" -v l="$(value "$work/$dir" class_d3.000mm_period_height)" \
    -v rs="$small" -v rl="$large" -v t=$tol 'function abs(x) { return x < 0 ? -x : x }
    BEGIN { if (t > 0) exit !(s != "" && abs(s - rs) < t && abs(l - rl) < t); exit !(s != "" && abs(s - rs) > -t && abs(l - rl) > -t) }' &&
    ok || fail "$dir: the classes' centres $(value "$work/$dir" class_d1.000mm_period_height), $(value "$work/$dir" class_d3.000mm_period_height) against the run's $small, $large"
done
"$compare" "$work/background1/background.csv" "$work/background2/background.csv" 1e-8 && ok ||
  fail "background.csv differs between 1 and 2 ranks"
awk -v c="$(value "$work/background1" background_last_change)" 'BEGIN { exit !(c != "" && c < 1e-4) }' && ok ||
  fail "the background's last change $(value "$work/background1" background_last_change) m"
# Most tracers mixed within 60 s (the bed relaxes in about 16 s; starts in nearly dead cells do not: 123 of 138).
awk -v m="$(value "$work/np1" mixing_mixed)" -v n="$(value "$work/np1" mixing_starts)" 'BEGIN { exit !(n > 100 && m > n / 2) }' &&
  ok || fail "$(value "$work/np1" mixing_mixed) of $(value "$work/np1" mixing_starts) tracers mixed within 60 s"
awk -v a="$(value "$work/np1" relaxation_time)" -v b="$(value "$work/np2" relaxation_time)" \
  'BEGIN { exit !(a > 0 && (a - b < 1e-6 * a && b - a < 1e-6 * a)) }' && ok ||
  fail "relaxation time $(value "$work/np1" relaxation_time) vs $(value "$work/np2" relaxation_time)"
awk -v c="$(value "$work/np1" zone_low_conservation)" 'BEGIN { exit !(c < 1e-12) }' && ok ||
  fail "absorbed + left - 1 = $(value "$work/np1" zone_low_conservation)"
awk -v c="$(value "$work/np1" zone_low_passes_conservation)" 'BEGIN { exit !(c < 1e-12) }' && ok ||
  fail "sum of the pass counts - 1 = $(value "$work/np1" zone_low_passes_conservation)"
# The run's markov monitor: the same chain as rcfd markov with the wrap carried (as the run carries
# its state) and the run's fractions and drift (the defaults: 1.95 and 2.82 mm, law B): the same
# distributions, to the digits written.
zone=(-zones low -zone_low_layers 0,4 -markov_departures 6 -markov_passage_horizon 5)
"$rcfd" run -db "$db" -t_end 0.01 -quiet -monitors markov "${zone[@]}" -output_dir "$work/run" && ok ||
  fail "rcfd run -monitors markov failed"
"$rcfd" markov "$db" "${zone[@]}" -markov_mix 0 -markov_wrap carry -quiet -fractions_diameters 1.95e-3,2.82e-3 \
  -fractions_mass_shares 0.473,0.527 -drift_model B -o "$work/carried" && ok || fail "rcfd markov -markov_wrap carry failed"
for f in low low_d1.950mm low_d2.820mm; do
  cmp <(tail -n +2 "$work/run/markov_zone_$f.csv") <(tail -n +2 "$work/carried/zone_$f.csv") && ok ||
    fail "the run's markov_zone_$f.csv differs from rcfd markov's zone_$f.csv"
done
grep -q "^wrap,carry column$" "$work/carried/summary.csv" && ok || fail "summary.csv does not say the wrap was carried"
# The same with each class's drift on the stationary background (-markov_class_background
# stationary, read by both under the same name): the same distributions again.
"$rcfd" run -db "$db" -t_end 0.01 -quiet -monitors markov "${zone[@]}" -markov_class_background stationary \
  -output_dir "$work/run-bg" && ok || fail "rcfd run -monitors markov -markov_class_background stationary failed"
"$rcfd" markov "$db" "${zone[@]}" -markov_mix 0 -markov_wrap carry -quiet -fractions_diameters 1.95e-3,2.82e-3 \
  -fractions_mass_shares 0.473,0.527 -drift_model B -markov_class_background stationary -o "$work/carried-bg" && ok ||
  fail "rcfd markov -markov_wrap carry -markov_class_background stationary failed"
for f in low_d1.950mm low_d2.820mm; do
  cmp <(tail -n +2 "$work/run-bg/markov_zone_$f.csv") <(tail -n +2 "$work/carried-bg/zone_$f.csv") && ok ||
    fail "with the stationary background, the run's markov_zone_$f.csv differs from rcfd markov's"
  cmp -s <(tail -n +2 "$work/run-bg/markov_zone_$f.csv") <(tail -n +2 "$work/run/markov_zone_$f.csv") && 
    fail "the stationary background left the run's markov_zone_$f.csv as the mean composition's" || ok
done
expect_error "-monitors markov needs zones" run -db "$db" -t_end 0.01 -monitors markov -output_dir "$work/refused-run"
# The figures, where matplotlib is there to draw them.
if /usr/bin/python3 -c "import matplotlib, numpy" 2>/dev/null; then
  for png in relaxation zone_low passes_low; do
    [ "$(head -c 4 "$work/np1/$png.png" | tail -c 3)" = PNG ] && ok || fail "$work/np1/$png.png is not a PNG"
  done
  [ ! -e "$work/np2/relaxation.png" ] && ok || fail "RCFD_PLOT=0 drew $work/np2/relaxation.png"
fi
# Refusals: one sentence, nothing written.
expect_error "Unknown option -markov_mix_tolerence" markov "$db" -markov_mix_tolerence 0.1 -o "$work/bad"
expect_error "-markov_mix_tolerance 2: expected a number between 0 and 1" markov "$db" -markov_mix_tolerance 2 -o "$work/bad"
expect_error "No database given" markov -o "$work/bad"
expect_error "Unknown option nope for -markov_spectrum. Available options: average period" markov "$db" -markov_spectrum nope -o "$work/bad"
expect_error "-markov_mix_zone nope is none of -zones" markov "$db" -zones low -zone_low_layers 0,4 -markov_mix_zone nope -o "$work/bad"
# SLEPc's spectrum slicing crashed on the chain's non-symmetric matrix (found by the option fuzz):
# refused before SLEPc reads it; other eigenpairs than the largest in modulus are not the answers.
expect_error "-markov_eps_interval: the chain's matrix is not symmetric" markov "$db" -markov_eps_interval 0.5,1 -o "$work/bad"
expect_error "rcfd markov needs the chain's eigenvalues largest in modulus" markov "$db" -markov_eps_smallest_real -o "$work/bad"
[ ! -e "$work/bad" ] && ok || fail "a refused rcfd markov wrote $work/bad"
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
