#!/usr/bin/env bash
# The pointing budget. Without SPEC: the shipped budget,
# tools/sweeps/pointing_budget.yaml, run in closed loop (gimbalsim.sweep) into
# out/pointing_budget/, its report stamped (machine, commit, date) into
# docs/results/pointing_budget.md with its CDF plots beside it. With SPEC (any
# spec, the shipped one too): that budget, into out/pointing_budget-<spec
# name>/ (or --out DIR); the project's pages are never touched.
#
#   bash tools/sweeps/run_pointing_budget.sh                        # the shipped page
#   bash tools/sweeps/run_pointing_budget.sh MY_SPEC [--out DIR] [sweep options, e.g. --workers 2]
#
# The package is the one in ${GIMBALSIM_BUILD:-build}/python (cmake --build build --target gimbalsim_python).
# Options after SPEC go to python3 -m gimbalsim.sweep (its --help lists them); --help (-h) prints this
# and --version the sweep's version, before anything runs. A refused spec or a failed run leaves the
# previous results as they were: they are replaced only by a new folder the sweep completed.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SHIPPED=tools/sweeps/pointing_budget.yaml
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
# --help and --version are the script's, answered before anything (they went to the sweep, which wrote
# nothing, and the previous results were removed all the same).
info=
for a in "$@"; do case "$a" in -h | --help | --version) info=$a; break ;; esac; done
if [ "$info" != "" ] && [ "$info" != --version ]; then
  sed -n '2,15p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
  exit 0
fi
SPEC=  # none: the shipped budget and its page
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  SPEC=$1
  shift
fi
ARGS=("$@")
# A GIMBALSIM_BUILD the user names is read where the user stands, as every path they give; the default is the checkout's.
if [ -n "${GIMBALSIM_BUILD:-}" ]; then
  PACKAGE="$(realpath -m "$GIMBALSIM_BUILD")/python"
else
  PACKAGE="$ROOT/build/python"
fi
[ -f "$PACKAGE/gimbalsim/__init__.py" ] || {
  echo "run_pointing_budget.sh: no gimbalsim package in $PACKAGE: cmake --build build -j2 --target gimbalsim_python" >&2
  exit 2
}
if [ "$info" = --version ]; then
  exec env PYTHONPATH="$PACKAGE" /usr/bin/python3 -m gimbalsim.sweep --version
fi

if [ -n "$SPEC" ]; then
  # A user's spec: its own output folder (a --out among the options wins), nothing else written.
  OUT="out/pointing_budget-$(basename "${SPEC%.*}")"
  for a in "${ARGS[@]+"${ARGS[@]}"}"; do case "$a" in --out | --out=*) OUT= ;; esac; done
  # The script's own default folder is made, as a program's under out/ is, and taken back when the sweep
  # refuses the spec or fails with it still empty (a refused run leaves nothing).
  made_out=0
  if [ -n "$OUT" ] && [ ! -d out ]; then mkdir out && made_out=1; fi
  rc=0
  PYTHONPATH="$PACKAGE" /usr/bin/python3 -m gimbalsim.sweep "$SPEC" ${OUT:+--out "$OUT"} --no-progress \
    "${ARGS[@]+"${ARGS[@]}"}" || rc=$?
  [ "$rc" -eq 0 ] || [ "$made_out" = 0 ] || rmdir out 2>/dev/null || true
  exit "$rc"
fi

for a in "${ARGS[@]+"${ARGS[@]}"}"; do
  if [ "$a" = "--out" ] || [ "${a#--out=}" != "$a" ]; then
    echo "run_pointing_budget.sh: without a SPEC this regenerates the project's page from out/pointing_budget/;" \
         "to write elsewhere, name the spec: run_pointing_budget.sh $SHIPPED --out DIR" >&2
    exit 2
  fi
done
cd "$ROOT"
COMMAND="bash tools/sweeps/run_pointing_budget.sh$(printf ' %q' "${ARGS[@]+"${ARGS[@]}"}")"
OUT=out/pointing_budget
made_out=0
if [ ! -d out ]; then mkdir out && made_out=1; fi
# Into a fresh folder first: the previous results go only once this run has
# its own (a refused spec or a failed run leaves them as they were, and an
# out/ made for it goes again).
NEW="$OUT.new-$$" OLD="$OUT.old-$$"
trap 'rm -rf "$NEW"; [ -e "$OUT" ] || [ ! -d "$OLD" ] || mv "$OLD" "$OUT"; [ "$made_out" = 0 ] || rmdir out 2>/dev/null || true' EXIT
PYTHONPATH="$PACKAGE" /usr/bin/python3 -m gimbalsim.sweep "$SHIPPED" --out "$NEW" --no-progress "${ARGS[@]+"${ARGS[@]}"}"
# The previous results go only for a whole new folder: the sweep's results, summary and report, no journal
# left (an option that makes the sweep answer and write nothing must not cost them).
for f in results.csv summary.json report.md; do
  if [ -L "$NEW" ] || [ ! -d "$NEW" ] || [ -L "$NEW/$f" ] || [ ! -f "$NEW/$f" ] || [ -e "$NEW/results.partial.csv" ]; then
    echo "run_pointing_budget.sh: the sweep ended well but left no whole budget in $NEW (no $f, or its journal);" \
         "$OUT left as it was" >&2
    exit 1
  fi
done
# Swapped, not removed first: the previous results come back if the new ones cannot be moved into place.
if [ -e "$OUT" ] || [ -L "$OUT" ]; then mv "$OUT" "$OLD"; fi
if ! mv "$NEW" "$OUT"; then
  if [ -e "$OLD" ]; then mv "$OLD" "$OUT"; fi
  echo "run_pointing_budget.sh: could not move $NEW into $OUT; $OUT left as it was" >&2
  exit 4
fi
rm -rf "$OLD"
RESULTS=docs/results
rm -f "$RESULTS"/pointing_budget_*_cdf.png  # the page shows this run's figures only, none left from an older one
for png in "$OUT"/plots/*_cdf.png; do
  cp "$png" "$RESULTS/pointing_budget_$(basename "$png")"
done
# the report's plots/NAME links become the copies' names beside the page
sed 's#](plots/#](pointing_budget_#' "$OUT/report.md" > "$OUT/page_body.md"
/usr/bin/python3 tools/pages/results_page.py --page "$RESULTS/pointing_budget.md" \
  --title "Closed-loop pointing budget" --command "$COMMAND" --body "$OUT/page_body.md" \
  --summary "ECSS indices per phase over a bearing's tolerance, with order-statistics intervals" \
  --t0 "$T0" --load0 "$LOAD0"
