#!/bin/bash
# Closed-loop pointing error against the elevation-joint clearance: builds
# gimbalsim_pointing_study (configuring build/ if needed), runs it and plots.
# Arguments go to the tool (e.g. --clearances 0.2e-3,0.5e-3 --duration 6
# --set KEY=VALUE --scene-set KEY=VALUE --out DIR). BUILD_DIR overrides build/.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${BUILD_DIR:-$ROOT/build}"
OUT="out/pointing_study"
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[i]}" in
    --out) OUT="${args[i + 1]:-}" ;;
    --out=*) OUT="${args[i]#--out=}" ;;
  esac
done
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" -j2 --target gimbalsim_pointing_study
status=0
# The default --out first: a --out among the arguments comes later and counts.
"$BUILD/bin/gimbalsim_pointing_study" --out "$OUT" "$@" || status=$?
# Exit 3: a plant stopped; the results of the other runs are still written and plotted.
if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then exit "$status"; fi
/usr/bin/python3 "$ROOT/tools/pointing_study/plot_pointing_study.py" "$OUT"
exit "$status"
