#!/usr/bin/env bash
# Runs gimbalsim_bench with repetitions and prints one line per benchmark:
# median and minimum CPU time per call [ns] (plus the per-call counters).
#   tools/bench/run_bench.sh [--results] [--benchmark_filter=REGEX] [other benchmark flags]
# Environment: BENCH (binary, default the repository's build/bin/gimbalsim_bench), REPS (default 5),
# OUT (keep the JSON there; else a temporary, removed at the end).
# --results: also measures MuJoCo's RK4 against ours (gimbalsim_workprec on
# paper_ideal_valid_inertia, MUJOCO_REPEATS runs per point, default 5) and
# writes docs/results/speed.md (tools/bench/speed_page.py).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/bench/run_bench.sh$(printf ' %q' "$@")"
for v in REPS MUJOCO_REPEATS; do [ -n "${!v:-}" ] && COMMAND="$v=${!v} $COMMAND"; done
RESULTS=0 ARGS=()
for a in "$@"; do
  if [ "$a" = --results ]; then RESULTS=1; else ARGS+=("$a"); fi
done
BIN=${BENCH:-$ROOT/build/bin/gimbalsim_bench}  # the repository's build wherever the user stands
REPS=${REPS:-5}
TEMPORARY=()  # removed whatever ends the script
trap 'rm -f ${TEMPORARY[@]+"${TEMPORARY[@]}"}' EXIT
if [ -z "${OUT:-}" ]; then OUT=$(mktemp /tmp/gimbalsim_bench.XXXXXX.json) && TEMPORARY+=("$OUT"); fi
# BENCH and OUT are read where the user stands; the benchmarks read the repository's scenes (tools/scenes/)
case "$BIN" in /*) ;; *) BIN="$PWD/$BIN" ;; esac
case "$OUT" in /*) ;; *) OUT="$PWD/$OUT" ;; esac
cd "$ROOT"
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
  --benchmark_out="$OUT" --benchmark_out_format=json ${ARGS[@]+"${ARGS[@]}"} >/dev/null
/usr/bin/python3 - "$OUT" "$ROOT" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2] + "/tools/pages")
import output_file  # noqa: F401  (its import keeps the console: a reader gone drops the table, stops nothing)
runs = json.load(open(sys.argv[1]))["benchmarks"]
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
[ "$RESULTS" = 1 ] || exit 0
MJ=(--no-mujoco "this build has no MuJoCo peer: Debian's libmujoco-dev and libqhull-dev were not installed when build/ was configured (apt-get install libmujoco-dev libqhull-dev, then reconfigure)")
if grep -q '^mujoco_DIR:PATH=/' build/CMakeCache.txt 2>/dev/null; then  # found at configure time
  mkdir -p out/speed/mujoco
  LOG=$(mktemp) && TEMPORARY+=("$LOG")
  build/bin/gimbalsim_workprec --scenes paper_ideal_valid_inertia --policy plain --steps 1e-2,5e-3,2e-3,1e-3 \
    --repeats "${MUJOCO_REPEATS:-5}" --out out/speed/mujoco | console_tee "$LOG"
  /usr/bin/python3 tools/pages/save_output.py "$LOG" out/speed/mujoco/workprec.log  # the writer's rules, not tee's
  MJ=(--mujoco-dir out/speed/mujoco)
fi
/usr/bin/python3 tools/bench/speed_page.py --bench-json "$OUT" "${MJ[@]}" --command "$COMMAND" --t0 "$T0" --load0 "$LOAD0"
