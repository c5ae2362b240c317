# Sourced by the vessel tests (usage: SCRIPT RCFD CSV_COMPARE DATA_DIR SOURCE_DIR): strict mode,
# MPI as root, rcfd, compare, h5print, a work directory removed on exit, fail, and run_on_ranks.
set -eu
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rcfd=$1 compare=$2
h5print=$(dirname "$compare")/h5_print
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# run_on_ranks LABEL RUN_OPTIONS...: the options (with -halves) run into $work/np1 and $work/np2;
# cog and halves agree to 1e-12, every fraction's mass is kept to 1e-12 and no cell turns
# negative, or the test fails naming LABEL.
run_on_ranks() {
  local label=$1
  shift
  mpiexec -n 1 "$rcfd" run "$@" -output_dir "$work/np1"
  mpiexec -n 2 "$rcfd" run "$@" -output_dir "$work/np2"
  "$compare" "$work/np1/cog.csv" "$work/np2/cog.csv" 1e-12 1e-15 bulk_mismatch=1e-12
  "$compare" "$work/np1/halves.csv" "$work/np2/halves.csv" 1e-12 1e-15
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) { if ($i ~ /^mass_/) m[i] = 1; if ($i == "min_cell_mass_kg") low = i }; next }
    NR == 2 { for (i in m) first[i] = $i }
    { for (i in m) if (($i - first[i]) > 1e-12 * first[i] || (first[i] - $i) > 1e-12 * first[i]) { print "mass " $i " vs " first[i]; bad = 1 }
      if (low && $low < 0) { print "negative cell mass " $low; bad = 1 } }
    END { exit bad }' "$work/np1/cog.csv" || fail "the run on $label lost mass or made a negative cell"
}

# restart_repeats LABEL RUN_OPTIONS...: a run of the options to 1 s on 2 ranks, and the same run
# stopped at 0.8 s with a checkpoint at 0.5 s and restarted from it to 1 s: cog.csv, bottom.csv,
# path.txt and jumps.csv the same byte for byte (the options must give -bottom_layer), or the test
# fails naming LABEL.
restart_repeats() {
  local label=$1
  shift
  mpiexec -n 2 "$rcfd" run "$@" -t_end 1 -output_dir "$work/full"
  mpiexec -n 2 "$rcfd" run "$@" -t_end 0.8 -checkpoint_every 0.5 -output_dir "$work/first"
  mpiexec -n 2 "$rcfd" run "$@" -t_end 1 -restart "$work/first/checkpoint.h5" -output_dir "$work/second"
  for f in cog.csv bottom.csv path.txt jumps.csv; do
    cmp -s "$work/full/$f" "$work/second/$f" || fail "the restarted run on $label: $f differs from the uninterrupted one's"
  done
}
