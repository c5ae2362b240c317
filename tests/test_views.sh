#!/usr/bin/env bash
# Stored expected output, in the PETSc manner: `rcfd run` with -run_view,
# -drift_view and -shift_view on a tiny synthetic bed (two fractions, drift)
# at 1 and 2 ranks, filtered -- numbers to 3 significant digits, round-off
# (|x| < 1e-12) to 0, timings and memory dropped -- and compared with
# tests/expected/views_np<N>.out.  A changed answer shows up as a diff.
# After an intended change, regenerate the files and review their diff:
#   RCFD_BLESS=1 ctest -R test_views      (or: RCFD_BLESS=1 bash tests/test_views.sh ...)
# usage: test_views.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
rcfd=$(realpath "$1") expected=$(realpath "$4")/tests/expected
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work" # relative names, so that no path of this machine lands in the output

# Timings, rates and memory change from run to run; numbers are rounded so
# that round-off (and its order on 1 vs 2 ranks) does not show.
filter() {
  grep -v -E "steps/s|wall|peak memory|ETA" |
    perl -pe 's{(?<![\w.])([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(?![\w.])}{
      my $x = $1; abs($x) < 1e-12 ? "0" : sprintf("%.3g", $x) }ge'
}

"$rcfd" synth -o bed.h5 -synth_cells 6,2,12 -synth_frames 20 -quiet || exit 1
failures=0
for np in 1 2; do
  mpiexec -n $np "$rcfd" run -db bed.h5 -t_end 0.1 -fractions_diameters 1e-3,3e-3 \
    -fractions_mass_shares 0.5,0.5 -drift_model B -drift_kd 5e3 -output_dir out -fields 0 -plot 0 \
    -quiet -run_view -drift_view -shift_view >raw$np.txt 2>&1 ||
    { echo "FAIL: rcfd run at $np ranks: $(cat raw$np.txt)"; exit 1; }
  filter <raw$np.txt >views_np$np.out
  if [ "${RCFD_BLESS:-0}" = 1 ]; then
    cp views_np$np.out "$expected/views_np$np.out"
    echo "blessed $expected/views_np$np.out"
  elif ! diff -u "$expected/views_np$np.out" views_np$np.out; then
    echo "FAIL: the views at $np rank(s) differ from tests/expected/views_np$np.out (above: - stored, + now;"
    echo "      if the change is intended, regenerate with RCFD_BLESS=1 and review the diff)"
    failures=$((failures + 1))
  fi
done
echo "$((2 - failures)) passed, $failures failed"
[ $failures -eq 0 ]
