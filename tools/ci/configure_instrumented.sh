#!/usr/bin/env bash
# Configures the instrumented build in DIR (default build-fuzz): clang++-14,
# AddressSanitizer + UndefinedBehaviorSanitizer (any finding fatal), libFuzzer's
# coverage, eigen_assert and Eigen's malloc guard on, at -O1. The fuzz targets
# (tools/ci/fuzz.sh) and the sanitizer CI subset (tools/ci/run_sanitizers.sh) share
# it, so the instrumented tree is compiled once.
#   bash tools/ci/configure_instrumented.sh [DIR]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
case "${1:-}" in
  -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
  -*) echo "configure_instrumented.sh: unknown option '$1' (usage: [DIR])" >&2; exit 2 ;;
esac
dir=${1:-build-fuzz}
cmake -S . -B "$dir" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" -DGIMBALSIM_CHECKED=ON -DGIMBALSIM_FUZZ=ON \
  -DGIMBALSIM_SANITIZE=address,undefined -DGIMBALSIM_TESTS=ON -DGIMBALSIM_PYTHON=OFF >/dev/null
