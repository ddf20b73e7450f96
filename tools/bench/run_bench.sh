#!/usr/bin/env bash
# Runs gimbalsim_bench with repetitions and prints one line per benchmark:
# median and minimum CPU time per call [ns] (plus the per-call counters).
#   tools/bench/run_bench.sh [--results] [--benchmark_filter=REGEX] [other benchmark flags]
# Environment: BENCH (binary, default BUILD/bin/gimbalsim_bench, BUILD the repository's build/ or
# GIMBALSIM_BUILD=DIR, configured, read where you stand), REPS (default 5),
# OUT (keep the JSON there, written by the writer's rules; else a temporary, removed at the end).
# --results: also measures MuJoCo's RK4 against ours (gimbalsim_workprec on
# paper_ideal_valid_inertia, MUJOCO_REPEATS runs per point, default 5) and
# writes docs/results/speed.md (tools/bench/speed_page.py).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/bench/run_bench.sh$(printf ' %q' "$@")"
for v in REPS MUJOCO_REPEATS; do [ -n "${!v:-}" ] && COMMAND="$v=${!v} $COMMAND"; done
refuse() { echo "run_bench.sh: $1; nothing run" >&2; exit 2; }
for v in BENCH REPS OUT MUJOCO_REPEATS; do  # set but empty is no value (OUT= kept no JSON, REPS= ran 5)
  [ "${!v+set}" != set ] || [ -n "${!v}" ] || refuse "$v=: an empty value (unset it for the default)"
done
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_bench.sh
BIN=${BENCH:-$BUILD/bin/gimbalsim_bench}
# BENCH and OUT are read where the user stands; the benchmarks read the repository's scenes (tools/scenes/)
case "$BIN" in /*) ;; *) BIN="$PWD/$BIN" ;; esac
RESULTS=0 ARGS=() LIST=""
for a in "$@"; do
  case "$a" in
    -h | --help) script_usage "${BASH_SOURCE[0]}" 2 10; exit 0 ;;
    --version) script_version run_bench.sh; exit 0 ;;
    --results) RESULTS=1 ;;
    # the JSON is the script's to write (OUT=FILE), by the writer's rules; a listing is the bench's answer alone
    --benchmark_out | --benchmark_out=* | --benchmark_out_format*)
      refuse "$a: the script writes the JSON; give OUT=FILE" ;;
    --benchmark_repetitions* | --benchmark_report_aggregates_only*) refuse "$a: the script sets it; give REPS=N" ;;
    # nothing after '=' is refused, as the programs refuse it (--benchmark_filter= ran every benchmark)
    --*=) refuse "$a: an empty value after the '='" ;;
    # (pass 97) a listing took the other flags unchecked, and =false ran the whole suite once, OUT unwritten
    --benchmark_list_tests | --benchmark_list_tests=true) LIST=$a ;;
    *) ARGS+=("$a") ;;
  esac
done
[ -f "$BIN" ] && [ -x "$BIN" ] ||
  refuse "BENCH=$BIN: no such program (build it: cmake --build $BUILD --target gimbalsim_bench)"
if [ -n "$LIST" ]; then  # the bench's answer alone: what it would run, by the same flags
  for v in REPS OUT; do [ -z "${!v:-}" ] || refuse "$v=${!v}: a listing runs nothing and writes no JSON"; done
  cd "$ROOT"; exec "$BIN" "$LIST" ${ARGS[@]+"${ARGS[@]}"}
fi
REPS=${REPS:-5}
# a whole number as the programs read one: a sign allowed, no leading zero (C reads 010 as octal 8)
[[ "$REPS" =~ ^[+]?[1-9][0-9]{0,3}$ ]] && [ "${REPS#+}" -ge 2 ] && [ "${REPS#+}" -le 1000 ] ||
  refuse "REPS=$REPS: must be a whole number in [2, 1000] (a median and a minimum over repetitions)"
REPS=${REPS#+}
KEEP=${OUT:-}
case "$KEEP" in "" | /*) ;; *) KEEP="$PWD/$KEEP" ;; esac
# OUT by the writer's rules, checked before the run: never through a link, never over an input (the program,
# the scenes the benchmarks load, a file named in a flag), whole or not at all
# (pass 101) and the scripts it runs: OUT over itself or tools/lib/console.sh replaced them with the JSON
INPUTS=("$BIN" "$ROOT"/tools/scenes/*.yaml ${ARGS[@]+"${ARGS[@]}"} "${BASH_SOURCE[0]}" "$ROOT"/tools/lib/*.sh
  "$ROOT"/tools/bench/*.py "$ROOT"/tools/pages/*.py "$BASH" /usr/bin/python3)
# (pass 103, 107) every program it runs by name (OUT=/usr/bin/mktemp, realpath): the writer refuses an executable
# file in a folder on PATH
[ -z "$KEEP" ] || /usr/bin/python3 "$ROOT/tools/pages/save_output.py" --as run_bench.sh \
  --check /dev/null "$KEEP" -- "${INPUTS[@]}" || exit $?
# The page's rules before the measurements: a page refused at the end would cost the run.
[ "$RESULTS" = 0 ] || /usr/bin/python3 "$ROOT/tools/pages/results_page.py" --check --page "$ROOT/docs/results/speed.md" ||
  exit $?
TEMPORARY=()  # removed whatever ends the script
trap 'rm -f ${TEMPORARY[@]+"${TEMPORARY[@]}"}' EXIT
OUT=$(mktemp /tmp/gimbalsim_bench.XXXXXX.json) && TEMPORARY+=("$OUT")
cd "$ROOT"
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
  --benchmark_out="$OUT" --benchmark_out_format=json ${ARGS[@]+"${ARGS[@]}"} >/dev/null
/usr/bin/python3 - "$OUT" "$ROOT" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2] + "/tools/pages")
import output_file  # (its import keeps the console: a reader gone drops the table, stops nothing)
try:
    runs = json.load(open(sys.argv[1]))["benchmarks"]
except (OSError, ValueError, KeyError):
    runs = []  # a filter that matched nothing leaves the file empty
if not any(r.get("run_type") == "aggregate" for r in runs):
    print("run_bench.sh: no benchmark ran (--benchmark_filter matched none): no result", file=sys.stderr)
    sys.exit(2)
rows = {}
for r in runs:
    if r.get("run_type") != "aggregate":
        continue
    row = rows.setdefault(r["run_name"], {})
    row[r["aggregate_name"]] = r["cpu_time"]
    if r["aggregate_name"] == "median":
        row["counters"] = {k: r[k] for k in ("substeps", "impacts") if k in r}
print(f"{'benchmark':48s} {'median ns':>12s} {'min ns':>12s}")
for name, row in rows.items():
    extra = " ".join(f"{k}={v:g}" for k, v in row.get("counters", {}).items())
    print(f"{name:48s} {row.get('median', float('nan')):12.1f} {row.get('min', float('nan')):12.1f} {extra}")
PY
[ -z "$KEEP" ] || /usr/bin/python3 tools/pages/save_output.py --as run_bench.sh \
  "$OUT" "$KEEP" -- "${INPUTS[@]}"  # the writer's rules
[ "$RESULTS" = 1 ] || exit 0
NO_MJ="this build has no MuJoCo peer: Debian's libmujoco-dev and libqhull-dev were not installed when $BUILD"
MJ=(--no-mujoco "$NO_MJ was configured (apt-get install libmujoco-dev libqhull-dev, then reconfigure)")
if grep -q '^mujoco_DIR:PATH=/' "$BUILD/CMakeCache.txt" 2>/dev/null; then  # found at configure time
  mkdir -p out/speed/mujoco
  LOG=$(mktemp) && TEMPORARY+=("$LOG")
  "$BUILD/bin/gimbalsim_workprec" --scenes paper_ideal_valid_inertia --policy plain --steps 1e-2,5e-3,2e-3,1e-3 \
    --repeats "${MUJOCO_REPEATS:-5}" --out out/speed/mujoco | console_tee "$LOG"
  /usr/bin/python3 tools/pages/save_output.py --as run_bench.sh \
    "$LOG" out/speed/mujoco/workprec.log  # the writer's rules, not tee's
  MJ=(--mujoco-dir out/speed/mujoco)
fi
/usr/bin/python3 tools/bench/speed_page.py --bench-json "$OUT" "${MJ[@]}" --command "$COMMAND" --t0 "$T0" --load0 "$LOAD0"
