#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/, every fuzz_* target: clang++-14,
# -fsanitize=fuzzer,address,undefined, in a build directory of their own) and
# runs each for SECONDS (default 60) from its seed corpus
# tests/fuzz/corpus/<target>/. New inputs go to OUT/corpus/<target>/ (kept
# between runs, so long runs build on each other), crashes to
# OUT/crashes/<target>-*. Then fuzz_spec, the Python mutation fuzzer of the
# sweep and tuning spec readers (tests/fuzz/fuzz_spec.py, no atheris here),
# against the package of the normal build PYBUILD (default build/, its target
# gimbalsim_python built first). Prints executions and crashes per target;
# exit 1 when any target crashed.
#
#   bash tools/fuzz.sh [SECONDS] [--build-dir DIR] [--py-build DIR] [--out DIR] [--only REGEX]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
SECONDS_EACH=60
BUILD=build-fuzz
PYBUILD=build
OUT=out/fuzz
ONLY=.
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) BUILD=$2; shift 2 ;;
    --py-build) PYBUILD=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    [0-9]*) SECONDS_EACH=$1; shift ;;
    *) echo "fuzz.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
bash tools/bootstrap.sh
mkdir -p "$OUT/crashes"
status=0
summary=""
if ls tests/fuzz/fuzz_*.cpp | xargs -n1 basename | sed 's/\.cpp$//' | grep -Eq -- "$ONLY"; then
  CXX=clang++-14 cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGIMBALSIM_FUZZ=ON -DGIMBALSIM_TESTS=OFF >/dev/null
  cmake --build "$BUILD" -j2 --target fuzz_all
fi
for bin in "$BUILD"/bin/fuzz_*; do
  [ -e "$bin" ] || continue
  t=$(basename "$bin")
  echo "$t" | grep -Eq -- "$ONLY" || continue
  seeds=tests/fuzz/corpus/$t
  [ -d "$seeds" ] || { echo "fuzz.sh: $t has no seed corpus $seeds" >&2; status=1; continue; }
  mkdir -p "$OUT/corpus/$t"
  log="$OUT/$t.log"
  echo "fuzz.sh: $t for ${SECONDS_EACH} s" >&2
  rc=0
  "$bin" -max_total_time="$SECONDS_EACH" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$OUT/crashes/$t-" "$OUT/corpus/$t" "$seeds" >"$log" 2>&1 || rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  corpus=$(find "$OUT/corpus/$t" -type f | wc -l)
  crash=0
  if [ "$rc" -ne 0 ]; then
    crash=1
    status=1
    echo "fuzz.sh: $t FAILED (exit $rc); see $log and $OUT/crashes/" >&2
    grep -E "ERROR|SUMMARY|deadly signal|Test unit written" "$log" | head -5 >&2 || true
  fi
  summary+=$(printf '%-28s %6s s %12s execs %3s crash %6s corpus files' "$t" "$SECONDS_EACH" "$execs" "$crash" "$corpus")$'\n'
done
# The spec readers are Python: an in-process mutation fuzzer with the same summary line.
t=fuzz_spec
if echo "$t" | grep -Eq -- "$ONLY"; then
  [ -f "$PYBUILD/CMakeCache.txt" ] || cmake -S . -B "$PYBUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$PYBUILD" -j2 --target gimbalsim_python
  mkdir -p "$OUT/corpus/$t"
  echo "fuzz.sh: $t for ${SECONDS_EACH} s" >&2
  rc=0
  line=$(PYTHONPATH="$PYBUILD/python" /usr/bin/python3 tests/fuzz/fuzz_spec.py --seconds "$SECONDS_EACH" \
    --corpus "$OUT/corpus/$t" --corpus tests/fuzz/corpus/$t --crashes "$OUT/crashes" 2>"$OUT/$t.log" | tail -1) || rc=$?
  if [ "$rc" -ne 0 ]; then
    status=1
    echo "fuzz.sh: $t FAILED (exit $rc); see $OUT/$t.log and $OUT/crashes/" >&2
    grep -E "Error|crash|timeout|oom" "$OUT/$t.log" | head -5 >&2 || true
  fi
  summary+="$line"$'\n'
fi
printf '%s' "$summary"
exit $status
