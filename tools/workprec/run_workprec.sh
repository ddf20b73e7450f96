#!/usr/bin/env bash
# Work-precision sweep end to end: builds gimbalsim_workprec (Release, build/;
# GIMBALSIM_BUILD=DIR takes that build, configured, read where you stand),
# runs it (arguments are passed through, e.g. --quick, --scenes paper_ideal,
# --repeats 5), writes out/workprec/workprec.csv and its log, and plots
# out/workprec/workprec.png with /usr/bin/python3 (Debian's matplotlib).
# --results also writes docs/results/workprec.md (tools/workprec/workprec_page.py).
#
#   bash tools/workprec/run_workprec.sh            # full sweep: several minutes
#   bash tools/workprec/run_workprec.sh --quick    # seconds
#   bash tools/workprec/run_workprec.sh --results  # full sweep and its results page
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/out_folder.sh"  # the script's own out/ folder, or a refusal
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_workprec.sh
CALLER=$PWD  # the user's folder: a relative path they give is theirs, not the repository's
cd "$ROOT"
source "$ROOT/tools/lib/caller_args.sh"  # abs_arg
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/workprec/run_workprec.sh$(printf ' %q' "$@")"
RESULTS=0 ARGS=()
for a in "$@"; do
  if [ "$a" = --results ]; then RESULTS=1; else ARGS+=("$(abs_arg "$a")"); fi
done
bash tools/bootstrap.sh
[ -f "$BUILD/CMakeCache.txt" ] || cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j2 --target gimbalsim_workprec >/dev/null
# --help and --version are the program's answer alone: no run, no log saved over the previous one, no plot.
for a in ${ARGS[@]+"${ARGS[@]}"}; do
  case "$a" in -h | --help | --version) exec "$BUILD/bin/gimbalsim_workprec" "$a" ;; esac
done
out_folder run_workprec.sh out/workprec
LOG=$(mktemp) && trap 'rm -f "$LOG"; out_folder_undo' EXIT  # the console log, saved by the writer's rules (not tee's)
# The log's and the figure's names before the sweep (pass 81: a link under workprec.png was refused by the plot
# after the sweep had replaced workprec.csv and its log): a refused name costs no run and no output.
for name in workprec.log workprec.png; do
  /usr/bin/python3 tools/pages/save_output.py --as run_workprec.sh \
    --check "$LOG" "out/workprec/$name" -- ${ARGS[@]+"${ARGS[@]}"}
done
# The page's rules before the study: a page refused at the end would cost the run and the previous outputs.
[ "$RESULTS" = 0 ] || /usr/bin/python3 tools/pages/results_page.py --check --page docs/results/workprec.md
status=0
"$BUILD/bin/gimbalsim_workprec" --out out/workprec ${ARGS[@]+"${ARGS[@]}"} | console_tee "$LOG" || status=$?
# Exit 3 (a scene without a reference): its CSV is written, so are its log and figure (pass 86: the script
# ended there, the new CSV beside the previous run's log and figure).
if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then exit "$status"; fi
/usr/bin/python3 tools/pages/save_output.py --as run_workprec.sh \
  "$LOG" out/workprec/workprec.log -- ${ARGS[@]+"${ARGS[@]}"}
plotted=0
/usr/bin/python3 tools/workprec/plot_workprec.py out/workprec/workprec.csv --out out/workprec/workprec.png || plotted=$?
if [ "$plotted" -ne 0 ]; then
  [ "$plotted" -eq 2 ] && [ "$status" -eq 3 ] || exit "$plotted"
  # No point to plot: the previous figure would stand beside these results as theirs (its name was checked).
  if [ -f out/workprec/workprec.png ] && [ ! -L out/workprec/workprec.png ]; then
    rm -f out/workprec/workprec.png && echo "run_workprec.sh: removed the previous run's out/workprec/workprec.png" >&2
  fi
  echo "run_workprec.sh: no plot (the sweep ran, exit $status); its CSV and log are in out/workprec" >&2
fi
if [ "$RESULTS" = 1 ] && [ "$plotted" -eq 0 ]; then
  /usr/bin/python3 tools/workprec/workprec_page.py --dir out/workprec --command "$COMMAND" --t0 "$T0" --load0 "$LOAD0"
elif [ "$RESULTS" = 1 ]; then
  echo "run_workprec.sh: no page either: docs/results/workprec.md is kept as it was" >&2
fi
exit "$status"
