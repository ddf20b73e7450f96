#!/usr/bin/env bash
# The README's test command: installs what is missing, builds the checked
# configuration (optimised, eigen_assert and Eigen's malloc guard on) and runs
# the GoogleTest suite with ctest.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bash tools/bootstrap.sh
cmake -S . -B build-tests -DCMAKE_BUILD_TYPE=Release -DGIMBALSIM_CHECKED=ON >/dev/null
cmake --build build-tests -j2
ctest --test-dir build-tests --output-on-failure -j2
