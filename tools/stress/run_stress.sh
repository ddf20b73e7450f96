#!/usr/bin/env bash
# The numerical stability stress grid end to end: builds gimbalsim_stress
# (Release, build/; GIMBALSIM_BUILD=DIR takes that build, configured, read
# where you stand), runs it with the arguments given (e.g. --long-run,
# --duration 0.5, --threads 1), writes out/stress/stress.csv and, with
# --results, the page docs/results/stress.md (header by tools/pages/results_page.py).
#
#   bash tools/stress/run_stress.sh [--results] [gimbalsim_stress options but --csv, --page-body, --case]
#   bash tools/stress/run_stress.sh --results --long-run     # the committed page
#
# Exit status: gimbalsim_stress's (1 when a run is silently wrong or stopped
# unclearly; the page is still written and lists them).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/out_folder.sh"  # the script's own out/ folder, or a refusal
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_stress.sh
CALLER=$PWD  # the user's folder: a relative path they give is theirs, not the repository's
cd "$ROOT"
source "$ROOT/tools/lib/caller_args.sh"  # abs_arg
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/stress/run_stress.sh$(printf ' %q' "$@")"
RESULTS=0 ARGS=()
for a in "$@"; do
  case "$a" in
    --results) RESULTS=1 ;;
    # the grid's outputs are the script's: a second --csv was CLI11's "At Most 1 required", and --case
    # (one scene, nothing written) was always refused for the --csv the script adds
    --csv | --csv=* | --page-body | --page-body=*)
      echo "run_stress.sh: $a: the script writes out/stress/stress.csv and the page body; for other outputs run" \
        "build/bin/gimbalsim_stress itself; nothing run" >&2; exit 2 ;;
    --case | --case=*)
      echo "run_stress.sh: $a: one scene writes nothing; run build/bin/gimbalsim_stress --case ... itself;" \
        "nothing run" >&2; exit 2 ;;
    *) ARGS+=("$(abs_arg "$a")") ;;
  esac
done
[ -f "$BUILD/CMakeCache.txt" ] || cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j2 --target gimbalsim_stress >/dev/null
# --help and --version are the program's answer alone: no run, no log saved over the previous one.
for a in ${ARGS[@]+"${ARGS[@]}"}; do
  case "$a" in -h | --help | --version) exec "$BUILD/bin/gimbalsim_stress" "$a" ;; esac
done
out_folder run_stress.sh out/stress
status=0
LOG=$(mktemp) && trap 'rm -f "$LOG"; out_folder_undo' EXIT  # the console log, saved by the writer's rules (not tee's)
/usr/bin/python3 tools/pages/save_output.py --as run_stress.sh \
  --check "$LOG" out/stress/stress.log -- ${ARGS[@]+"${ARGS[@]}"}
# The page's rules before the study: a page refused at the end would cost the run and the previous outputs.
[ "$RESULTS" = 0 ] || /usr/bin/python3 tools/pages/results_page.py --check --page docs/results/stress.md
"$BUILD/bin/gimbalsim_stress" --csv out/stress/stress.csv --page-body out/stress/page_body.md ${ARGS[@]+"${ARGS[@]}"} \
  | console_tee "$LOG" || status=$?
if [ "$status" -eq 0 ] || [ "$status" -eq 1 ]; then  # a grid that ran (1: some case failed), never a refusal
  /usr/bin/python3 tools/pages/save_output.py --as run_stress.sh "$LOG" out/stress/stress.log -- ${ARGS[@]+"${ARGS[@]}"}
fi
if [ "$RESULTS" = 1 ] && [ -f out/stress/page_body.md ] && { [ "$status" -eq 0 ] || [ "$status" -eq 1 ]; }; then
  summary=$(grep -m1 -o '^\*\*[^*]*\*\*' out/stress/page_body.md | tr -d '*')
  /usr/bin/python3 tools/pages/results_page.py --page docs/results/stress.md --title "Numerical stability stress grid" \
    --summary "$summary." --command "$COMMAND" --body out/stress/page_body.md --t0 "$T0" --load0 "$LOAD0"
fi
exit "$status"
