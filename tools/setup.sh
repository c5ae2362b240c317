#!/usr/bin/env bash
# Install what is missing (Debian 12, as root) and build rcfd in Release.
# Used by the two README commands; safe to run again (only missing packages
# are installed, and the build is incremental).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config petsc-dev slepc-dev libhdf5-openmpi-dev libmetis-dev
  libopenmpi-dev openmpi-bin zlib1g-dev python3-matplotlib valgrind)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

echo "== building (Release)"
# RCFD_WERROR=ON (CI, .ci/run): a compiler warning stops the build.  Not passed otherwise, so
# that a build configured once keeps its setting.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release ${RCFD_WERROR:+-DRCFD_WERROR=$RCFD_WERROR} >/dev/null
cmake --build build --parallel 2
