#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz/, every fuzz_* target) in the
# instrumented build (tools/ci/configure_instrumented.sh: clang++-14, ASan, UBSan,
# coverage; build-fuzz/, shared with the sanitizer CI subset) and runs each
# for SECONDS (default 60), as many at once as the machine has cores, from its seed corpus
# tests/fuzz/corpus/<target>/. New inputs go to OUT/corpus/<target>/ (kept
# between runs, so long runs build on each other), crashes to
# OUT/crashes/<target>-*. Then fuzz_spec, the Python mutation fuzzer of the
# sweep and tuning spec readers (tests/fuzz/fuzz_spec.py, no atheris here),
# against the package of the normal build PYBUILD (default build/, its target
# gimbalsim_python built first). Prints executions and crashes per target;
# exit 1 when any target crashed.
#
#   bash tools/ci/fuzz.sh [SECONDS] [--build-dir DIR] [--py-build DIR] [--out DIR] [--only REGEX]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
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
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1'" >&2; exit 2 ;;
  esac
done
bash tools/bootstrap.sh
mkdir -p "$OUT/crashes"
status=0
summary=""
if ls tests/fuzz/fuzz_*.cpp | xargs -n1 basename | sed 's/\.cpp$//' | grep -Eq -- "$ONLY"; then
  bash tools/ci/configure_instrumented.sh "$BUILD"
  cmake --build "$BUILD" -j2 --target fuzz_all
fi
# One target: its run, then its summary line in OUT/<target>.summary and its
# exit code in OUT/<target>.rc (0, or 1 if it crashed).
fuzzOne() {
  local bin=$1 t rc=0 execs corpus crash=0
  t=$(basename "$bin")
  mkdir -p "$OUT/corpus/$t"
  local log="$OUT/$t.log"
  echo "fuzz.sh: $t for ${SECONDS_EACH} s" >&2
  "$bin" -max_total_time="$SECONDS_EACH" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$OUT/crashes/$t-" "$OUT/corpus/$t" "tests/fuzz/corpus/$t" >"$log" 2>&1 || rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  corpus=$(find "$OUT/corpus/$t" -type f | wc -l)
  if [ "$rc" -ne 0 ]; then
    crash=1
    echo "fuzz.sh: $t FAILED (exit $rc); see $log and $OUT/crashes/" >&2
    # The check that failed, the finding and the input (Base64), so a CI log alone reproduces it.
    grep -aE "fuzz check failed|  problem:|ERROR|SUMMARY|Test unit written|^Base64:" "$log" | head -8 >&2 || true
  fi
  printf '%-28s %6s s %12s execs %3s crash %6s corpus files\n' "$t" "$SECONDS_EACH" "$execs" "$crash" "$corpus" \
    >"$OUT/$t.summary"
  echo "$crash" >"$OUT/$t.rc"
}
# Each target is one process on one core: run as many at once as there are cores.
jobs_max=$(nproc)
names=()
for bin in "$BUILD"/bin/fuzz_*; do
  [ -e "$bin" ] || continue
  t=$(basename "$bin")
  echo "$t" | grep -Eq -- "$ONLY" || continue
  [ -d "tests/fuzz/corpus/$t" ] || { echo "fuzz.sh: $t has no seed corpus tests/fuzz/corpus/$t" >&2; status=1; continue; }
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  rm -f "$OUT/$t.summary" "$OUT/$t.rc"
  fuzzOne "$bin" &
  names+=("$t")
done
wait
for t in ${names[@]+"${names[@]}"}; do
  [ "$(cat "$OUT/$t.rc" 2>/dev/null)" = 0 ] || status=1
  summary+=$(cat "$OUT/$t.summary" 2>/dev/null || echo "$t: no summary (the run did not finish)")$'\n'
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
