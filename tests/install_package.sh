#!/usr/bin/env bash
# The installed package that the example tests build against (CTest fixture installed_package):
# this build's library and program, built if they are not, installed once into PREFIX, and the
# files an outside project needs checked.  The example tests (test_user_operator_example,
# test_user_rule_examples, test_plugin_example, test_study_example) then only read PREFIX.
# usage: install_package.sh BUILD_DIR SOURCE_DIR CMAKE PREFIX
set -eu
build=$1 src=$2 cmake=$3 prefix=$4
work=$build/test-data/install-package
rm -rf "$work" "$prefix"
mkdir -p "$work"
source "$src/tests/script_helpers.sh"

install_build "$build" "$prefix" "$cmake"
for f in include/rcfd/operator.hpp include/rcfd/run.hpp include/rcfd/path.hpp include/rcfd/switching.hpp \
  include/rcfd/plugin.hpp include/rcfd/study.hpp bin/rcfd lib/cmake/rcfd/rcfdConfig.cmake lib/cmake/rcfd/rcfdConfigVersion.cmake \
  lib/cmake/rcfd/rcfdTargets.cmake; do
  [ -e "$prefix/$f" ] && ok || fail "cmake --install did not install $f"
done

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
