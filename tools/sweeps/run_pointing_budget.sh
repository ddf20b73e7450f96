#!/usr/bin/env bash
# The shipped pointing budget: runs tools/sweeps/pointing_budget.yaml in closed
# loop (gimbalsim.sweep), then stamps its report (machine, commit, date) into
# docs/results/pointing_budget.md with its CDF plots beside it.
#
#   bash tools/sweeps/run_pointing_budget.sh [SPEC] [sweep options, e.g. --workers 2]
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
SPEC="${1:-tools/sweeps/pointing_budget.yaml}"
shift || true
COMMAND="bash tools/sweeps/run_pointing_budget.sh$(printf ' %q' "$SPEC" "$@")"
OUT=out/pointing_budget
mkdir -p out
rm -rf "$OUT"
PYTHONPATH="$ROOT/build/python" /usr/bin/python3 -m gimbalsim.sweep "$SPEC" --out "$OUT" --no-progress "$@"
RESULTS=docs/results
for png in "$OUT"/plots/*_cdf.png; do
  cp "$png" "$RESULTS/pointing_budget_$(basename "$png")"
done
# the report's plots/NAME links become the copies' names beside the page
sed 's#](plots/#](pointing_budget_#' "$OUT/report.md" > "$OUT/page_body.md"
/usr/bin/python3 tools/results_page.py --page "$RESULTS/pointing_budget.md" \
  --title "Closed-loop pointing budget" --command "$COMMAND" --body "$OUT/page_body.md" \
  --summary "ECSS indices per phase over a bearing's tolerance, with order-statistics intervals" \
  --t0 "$T0" --load0 "$LOAD0"
