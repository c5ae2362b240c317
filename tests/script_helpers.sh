# Shared by the shell tests: counters, one-line error checks, and the three
# hand-made dumps of two particles (see test_particle_cli.sh for their story).
# Source after setting `rcfd`: it lets Open MPI run as root and makes the
# scratch directory `work`, removed on exit (unless the test made its own).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
if [ -z "${work:-}" ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
failures=0 passed=0

fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
ok() { passed=$((passed + 1)); }

# expect_error "expected text" args...: rcfd fails with exactly one line
# containing the text, and no PETSc traceback.
expect_error() {
  local expected=$1
  shift
  local out
  if out=$("$rcfd" "$@" 2>&1 >/dev/null); then
    fail "rcfd $* succeeded; expected an error containing: $expected"
  elif ! grep -qF -- "$expected" <<<"$out"; then
    fail "rcfd $*: expected '$expected', got: $out"
  elif [ "$(grep -c . <<<"$out")" -ne 1 ] || grep -q "PETSC ERROR" <<<"$out"; then
    fail "rcfd $*: expected one line, got: $out"
  else
    ok
  fi
}

# same [--nan] "label" "actual values" "expected values" [tolerance]: element-wise; numbers
# within tolerance relative to max(1, |expected|), words (a header, a label) equal.  A "nan"
# or "inf" fails, even against itself (awks disagree on what "nan" - 0.5 is: mawk's NaN
# compares as equal to any number); with --nan a "nan" matches a "nan" in the same place.
same() {
  local nan=0
  if [ "$1" = --nan ]; then
    nan=1
    shift
  fi
  if awk -v a="$2" -v b="$3" -v tol="${4:-1e-12}" -v nan=$nan 'BEGIN {
      gsub(/^[ \t\n]+|[ \t\n]+$/, "", a); gsub(/^[ \t\n]+|[ \t\n]+$/, "", b);
      na = split(a, x, /[ \t\n]+/); nb = split(b, y, /[ \t\n]+/);
      if (na != nb) exit 1;
      number = "^[-+]?([0-9]+[.]?[0-9]*|[.][0-9]+)([eE][-+]?[0-9]+)?$";
      special = "^[-+]?(nan|inf|infinity)$";
      for (i = 1; i <= na; ++i) {
        if (tolower(x[i]) ~ special || tolower(y[i]) ~ special) {
          if (nan && tolower(x[i]) == "nan" && tolower(y[i]) == "nan") continue;
          exit 1
        }
        if (x[i] !~ number || y[i] !~ number) { if (x[i] != y[i]) exit 1; continue }
        d = x[i] - y[i]; if (d < 0) d = -d;
        s = x[i] < 0 ? -x[i] : x[i]; if (s < 1) s = 1; if (d > tol * s) exit 1 }
      exit 0 }'; then ok; else fail "$1: got '$(echo $2)', expected '$(echo $3)'"; fi
}

run() { # run "label" args...: the command must succeed
  local label=$1
  shift
  if ! "$@" >"$work/out.txt" 2>&1; then
    fail "$label: $(cat "$work/out.txt")"
    return 1
  fi
  ok
}

# Two small synthetic beds of one mesh recorded at u_sup 1.1 and 1.3 m/s, $work/a.h5 and
# $work/b.h5 (400 cells, 40 frames), for the runs on several databases; `bed`: their options.
write_two_velocity_beds() {
  bed=(-synth_cells 10,2,20 -synth_frames 40 -synth_warm_up 0.2 -quiet)
  "$rcfd" synth -o "$work/a.h5" "${bed[@]}" -synth_nucleation_rate 1500 -synth_seed 1 -superficial_velocity 1.1
  "$rcfd" synth -o "$work/b.h5" "${bed[@]}" -synth_nucleation_rate 4000 -synth_seed 2 -superficial_velocity 1.3
}

dump() { # dump FILE TIMESTEP PARTICLE_LINE PARTICLE_LINE
  {
    printf 'ITEM: TIMESTEP\n%s\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS ff ff ff\n' "$2"
    printf '0 0.02\n0 0.01\n0 0.02\nITEM: ATOMS id type x y z radius\n'
    printf '%s\n' "$3" "$4"
  } >"$1"
}

# Three dumps of two particles in $work/dump, their times, and `common`, the
# rcfd options that read them on a 2 x 1 x 2 mesh.
write_two_particle_dumps() {
  mkdir -p "$work/dump"
  dump "$work/dump/dump.0.txt" 1000 "1 1 0.005 0.005 0.004 0.0005" "2 2 0.005 0.005 0.006 0.001"
  dump "$work/dump/dump.1.txt" 2000 "1 1 0.005 0.005 0.015 0.0005" "2 2 0.015 0.005 0.005 0.001"
  dump "$work/dump/dump.2.txt" 3000 "1 1 0.015 0.005 0.015 0.0005" "2 2 0.015 0.005 0.005 0.001"
  printf '# index time\n0 0.1\n1 0.2\n2 0.3\n' >"$work/dump/times.txt"
  common=(-dumps "$work/dump/dump.*.txt" -times "$work/dump/times.txt" -mesh_cells 2,1,2)
}

# The example projects of docs/examples against the installed package (test_user_*_example*.sh):
# install_build BUILD PREFIX CMAKE: the library and the program built (a no-op when they are) and
# installed into PREFIX; build_example NAME SOURCE_DIR PREFIX CMAKE CXX: docs/examples/NAME
# configured against PREFIX only (the source tree is on no path it sees) and built in $work/NAME.
# Both stop the test at a failure.
install_build() {
  "$3" --build "$1" --target rcfd_lib rcfd >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
  "$3" --install "$1" --prefix "$2" >"$work/install.log"
}
build_example() {
  "$4" -S "$2/docs/examples/$1" -B "$work/$1" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$5" \
    -DCMAKE_PREFIX_PATH="$3" >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }
  grep -q "$3/lib/cmake/rcfd" "$work/$1/CMakeCache.txt" || fail "$1 did not find rcfd in the installed prefix"
  "$4" --build "$work/$1" >"$work/$1.log" 2>&1 || { cat "$work/$1.log"; exit 1; }
}
