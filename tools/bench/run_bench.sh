#!/usr/bin/env bash
# Runs gimbalsim_bench with repetitions and prints one line per benchmark:
# median and minimum CPU time per call [ns] (plus the per-call counters).
#   tools/bench/run_bench.sh [--benchmark_filter=REGEX] [other benchmark flags]
# Environment: BENCH (binary, default build/bin/gimbalsim_bench), REPS (default 5),
# OUT (keep the JSON there).
set -euo pipefail
BIN=${BENCH:-build/bin/gimbalsim_bench}
REPS=${REPS:-5}
OUT=${OUT:-$(mktemp /tmp/gimbalsim_bench.XXXXXX.json)}
"$BIN" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
  --benchmark_out="$OUT" --benchmark_out_format=json "$@" >/dev/null
python3 - "$OUT" <<'PY'
import json, sys
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
