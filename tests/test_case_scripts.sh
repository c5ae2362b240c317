#!/usr/bin/env bash
# The case scripts that keep databases in build/ (velocity-schedule, granulator-regimes,
# granulator) run in a checkout without build/, as with an installed rcfd given by RCFD=:
# they create what they write into.  rcfd is stood in for by a script that writes what
# rcfd would (the -o file, the -output_dir's CSV files) and fails as rcfd does when it
# cannot create a file, so the test checks the scripts' files, not the runs (seconds).
# usage: test_case_scripts.sh RCFD CSV_COMPARE DATA_DIR SOURCE_DIR
set -u
rcfd=$1 source_dir=$4
source "$(dirname "${BASH_SOURCE[0]}")/script_helpers.sh"

checkout=$work/checkout
mkdir -p "$checkout" "$work/bin"
cp -r "$source_dir/cases" "$checkout/"
stub=$work/bin/rcfd
cat >"$stub" <<'STUB'
#!/usr/bin/env bash
cmd=$1 o="" dir=""
while [ $# -gt 0 ]; do
  case $1 in -o) o=$2; shift ;; -output_dir) dir=$2; shift ;; esac
  shift
done
if [ -n "$o" ]; then
  if [ "$cmd" = reference ]; then mkdir -p "$o"; else
    echo stand-in 2>/dev/null >"$o" || { echo "rcfd $cmd: error: cannot create HDF5 file '$o'" >&2; exit 1; }
  fi
fi
if [ -n "$dir" ]; then
  mkdir -p "$dir" || exit 1
  for f in cog.csv bottom.csv halves.csv switches.csv; do echo time_s >"$dir/$f"; done
  echo "Done."
fi
STUB
chmod +x "$stub"

for name in velocity-schedule granulator-regimes granulator; do
  script=$checkout/cases/$name/run.sh
  if RCFD=$stub NP=1 RCFD_PYTHON=false timeout 120 bash "$script" "$work/out-$name" >"$work/log" 2>&1; then
    ok
  else
    fail "cases/$name/run.sh without build/: $(grep -v '^ ' "$work/log" | tail -3)"
  fi
done
# The databases the scripts made, where their comments say.
for db in velocity-1.1 velocity-1.2 velocity-1.3 regimes-1.1 regimes-0.9 default-bed; do
  [ -s "$checkout/build/$db.h5" ] && ok || fail "build/$db.h5 was not written"
done
echo "$passed passed, $failures failed"
[ $failures -eq 0 ]
