# Shared by the shell tests: counters, one-line error checks, and the three
# hand-made dumps of two particles (see test_particle_cli.sh for their story).
# Source after setting `rcfd` and `work`.
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
