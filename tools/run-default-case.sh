#!/usr/bin/env bash
# README command 1: set up, make the embedded default database, and run the
# default case end to end.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Made again whenever the program is newer than the file, so that the
# database always comes from the current generator.
if [ ! -s build/default-bed.h5 ] || [ build/rcfd -nt build/default-bed.h5 ]; then
  echo "== generating the default database (synthetic bubbling bed, 300 frames)"
  ./build/rcfd synth -o build/default-bed.h5
fi
echo "== running cases/bubbling-bi-narrow on 2 MPI ranks"
mpiexec -n 2 ./build/rcfd run -options_file cases/bubbling-bi-narrow/case.yaml
