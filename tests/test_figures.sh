#!/usr/bin/env bash
# Figures: rcfd's matplotlib scripts draw real PNGs from the CSV files; without
# python3 + matplotlib a run says so once and still writes every number; a
# failing script is a clear error on every rank.  Exits 77 (skipped) when this
# machine has no matplotlib, after the checks that do not need it.
# usage: test_figures.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"
unset RCFD_PLOT # the suite turns figures off by default (tests/CMakeLists.txt); here they are the subject
skipped="figures skipped: python3 with matplotlib not found (every number is still in the CSV files)"
python=${RCFD_PYTHON:-/usr/bin/python3}
[ -x "$python" ] || python=python3
have_matplotlib=0
"$python" -c 'import matplotlib, numpy' 2>/dev/null && have_matplotlib=1

# png_ok FILE: a PNG (its signature) of a sensible size (IHDR width and height, bytes 17-24).
png_ok() {
  local sig w h
  sig=$(od -An -tx1 -N8 "$1" 2>/dev/null | tr -d ' \n')
  read -r w h < <(od -An -tu1 -j16 -N8 "$1" | awk '{ print $1*16777216+$2*65536+$3*256+$4, $5*16777216+$6*65536+$7*256+$8 }')
  if [ "$sig" != 89504e470d0a1a0a ]; then
    fail "$1 is not a PNG file (signature '$sig')"
  elif [ "$w" -lt 600 ] || [ "$w" -gt 3000 ] || [ "$h" -lt 400 ] || [ "$h" -gt 2000 ]; then
    fail "$1 is $w x $h pixels; expected 600-3000 x 400-2000"
  elif [ "$(stat -c %s "$1")" -lt 20000 ]; then
    fail "$1 has only $(stat -c %s "$1") bytes: an empty figure?"
  else
    ok
  fi
}

"$rcfd" synth -o "$work/db.h5" -synth_cells 8,2,16 -synth_frames 12 -quiet
small=(-db "$work/db.h5" -t_end 0.1 -fields 0 -quiet)

# Without matplotlib (at 2 ranks, two figures): one sentence, cog.csv, exit code 0, no PNG.
if out=$(RCFD_PYTHON=/nonexistent mpiexec -n 2 "$rcfd" run "${small[@]}" -output_dir "$work/hidden" 2>&1); then
  ok
else
  fail "a run without matplotlib failed: $out"
fi
same "times the skipped-figures sentence is said" "$(grep -cxF "$skipped" <<<"$out")" 1
same "data rows of cog.csv without matplotlib" "$(($(wc -l <"$work/hidden/cog.csv") - 1))" 21
[ ! -e "$work/hidden/cog.png" ] && ok || fail "cog.png was drawn without matplotlib"

# A failing script: an error naming the script and its command, at 1 and 2 ranks.
mkdir -p "$work/broken"
printf 'import sys\nsys.exit("cog.py: this script is broken on purpose")\n' >"$work/broken/cog.py"
for np in 1 2; do
  if out=$(RCFD_FIGURES_DIR="$work/broken" mpiexec -n $np "$rcfd" plot "$work/hidden/cog.csv" -o "$work/b.png" 2>&1); then
    fail "a failing figure script at $np ranks gave exit code 0"
  elif ! grep -qF "rcfd plot: error: the figure script cog.py failed with exit status 1 (its message is above): " <<<"$out" ||
    ! grep -qF "cog.py $work/hidden/cog.csv -o $work/b.png" <<<"$out" ||
    ! grep -qF "this script is broken on purpose" <<<"$out"; then
    fail "a failing figure script at $np ranks: $out"
  else
    ok
  fi
done
expect_error "rcfd plot: cannot read the CSV file '$work/none.csv'" plot "$work/none.csv"

if [ $have_matplotlib = 0 ]; then
  echo "$passed passed, $failures failed; no matplotlib on this machine: figures not checked"
  [ $failures -eq 0 ] && exit 77
  exit 1
fi

# rcfd plot on a run's cog.csv: both figures, next to the CSV by default.
run "rcfd plot" "$rcfd" plot "$work/hidden/cog.csv" && png_ok "$work/hidden/cog.png" && png_ok "$work/hidden/cog-delta.png"
# A run draws its figures unless -plot 0; so does an ensemble, from ensemble.csv.
run "run" "$rcfd" run "${small[@]}" -output_dir "$work/drawn" && png_ok "$work/drawn/cog.png" &&
  png_ok "$work/drawn/cog-delta.png"
run "run -plot 0" "$rcfd" run "${small[@]}" -output_dir "$work/bare" -plot 0
[ ! -e "$work/bare/cog.png" ] && ok || fail "-plot 0 drew cog.png"
# RCFD_PLOT=0 makes -plot 0 the default; -plot 1 still draws.
run "RCFD_PLOT=0" env RCFD_PLOT=0 "$rcfd" run "${small[@]}" -output_dir "$work/env0"
[ ! -e "$work/env0/cog.png" ] && ok || fail "RCFD_PLOT=0 drew cog.png"
run "RCFD_PLOT=0 -plot 1" env RCFD_PLOT=0 "$rcfd" run "${small[@]}" -output_dir "$work/env1" -plot 1 &&
  png_ok "$work/env1/cog.png"
run "ensemble" "$rcfd" run "${small[@]}" -output_dir "$work/ens" -ensemble 2 -path_type random &&
  png_ok "$work/ens/ensemble.png" && png_ok "$work/ens/ensemble-delta.png"
# The recurrence matrix: K x K numbers in the CSV, the heat map from them.
run "recurrence" "$rcfd" recurrence "$work/db.h5" -store 0 && png_ok "$work/db-recurrence.png"
same "rows and columns of db-recurrence.csv" \
  "$(awk -F, '!/^#/ { n++; if (NF != 12) bad++ } END { print n, bad + 0 }' "$work/db-recurrence.csv")" "12 0"
# Validation curves: -png alone writes the figure's CSV next to it.
run "compare" "$rcfd" compare -reference "$work/drawn/cog.csv" -rcfd "$work/bare/cog.csv,$work/ens/member_1/cog.csv" \
  -labels same,other -score_window 0.02,0.08 -png "$work/cmp/delta_z.png" && png_ok "$work/cmp/delta_z.png"
same "header of the compare CSV" "$(head -1 "$work/cmp/delta_z.csv")" \
  "time_s,delta_z_reference_m,delta_z_same_m,delta_z_other_m"
# The scripts run by hand too, as the docs say (here: another title, another file).
run "cog.py by hand" "$python" "$4/src/cli/figures/cog.py" "$work/drawn/cog.csv" -o "$work/paper.png" --title "" &&
  png_ok "$work/paper.png"
ls "$work"/drawn/.*.tmp >/dev/null 2>&1 && fail "a temporary file was left next to the figures" || ok

echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
