#!/bin/bash
# Closed-loop pointing error against bearing clearance (elevation, azimuth,
# both; planar and spatial; perfect, realistic and antenna-tracker sensors): builds
# gimbalsim_pointing_study (configuring build/ if needed), runs it and plots.
# Arguments go to the tool (e.g. --clearances 0.2e-3,0.5e-3 --duration 6
# --set KEY=VALUE --scene-set KEY=VALUE --out DIR; an --ideal-scene replaces the
# script's). GIMBALSIM_BUILD=DIR takes that
# build, already configured, instead of build/ (read where you stand).
# --results also writes docs/results/closed_loop_clearance.md
# (tools/pointing_study/pointing_page.py).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/out_folder.sh"  # the script's own out/ folder, or a refusal
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_pointing_study.sh
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/pointing_study/run_pointing_study.sh$(printf ' %q' "$@")"
OUT="out/pointing_study" RESULTS=0 NAMED=0
args=()
for a in "$@"; do
  if [ "$a" = --results ]; then RESULTS=1; else args+=("$a"); fi
done
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[i]}" in
    --out) OUT="${args[i + 1]:-}" NAMED=1 ;;
    --out=*) OUT="${args[i]#--out=}" NAMED=1 ;;
  esac
done
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" -j2 --target gimbalsim_pointing_study
# --help and --version are the program's answer alone: no run, no log saved over the previous one, no plot.
for a in ${args[@]+"${args[@]}"}; do
  case "$a" in -h | --help | --version) exec "$BUILD/bin/gimbalsim_pointing_study" "$a" ;; esac
done
status=0
# The console log is tee'd outside --out and saved into it by the writer's rules once the study has written
# its own outputs (tools/pages/save_output.py): --out is the study's to check and to make, never the script's.
LOG=$(mktemp)
if [ "$NAMED" = 0 ]; then  # the script's own default folder; a named one must exist (usage.md "Output files")
  out_folder run_pointing_study.sh "$OUT"
fi
trap 'rm -f "$LOG"; out_folder_undo' EXIT  # a refused run leaves no folder it made
# The log's and the figures' names are checked before the study runs: a refused one costs no run and no output
# (pass 80: a link under a figure's name was refused only after the study had replaced its CSVs, and taken for a
# study with nothing to plot).
PLOT=("$ROOT/tools/pointing_study/plot_pointing_study.py" "$OUT")
if [ -d "$OUT" ]; then
  for name in study.log pointing_error_vs_time.png pointing_error_vs_clearance.png; do  # (pass 81: a figure
    # hard-linked to an input scene was written over) every argument naming a file is an input
    /usr/bin/python3 "$ROOT/tools/pages/save_output.py" --as run_pointing_study.sh \
      --check "$LOG" "$OUT/$name" -- ${args[@]+"${args[@]}"}
  done
fi
# The page's rules before the study: a page refused at the end would cost the run and the previous outputs.
[ "$RESULTS" = 0 ] || /usr/bin/python3 "$ROOT/tools/pages/results_page.py" --check \
  --page "$ROOT/docs/results/closed_loop_clearance.md"
# Clearance in the elevation joint, the azimuth joint, both; planar and spatial;
# perfect, realistic and tracker sensors. An --out, --ideal-scene, --clearance-scene or --sensors
# among the arguments replaces these: the defaults are given only when none is (the study refuses a
# flag of one value given twice, and --clearance-scene lists add up).
defaults=()
[ "$NAMED" = 1 ] || defaults+=(--out "$OUT")
case " ${args[*]-} " in
  *" --sensors"*) ;;
  *) defaults+=(--sensors all) ;;
esac
scenes=(--ideal-scene "$ROOT/tools/scenes/paper_ideal.yaml")
case " ${args[*]-} " in
  *" --ideal-scene"*) scenes=() ;;  # given twice, CLI11 refused "At Most 1 required"
esac
case " ${args[*]-} " in
  *" --clearance-scene"*) ;;
  *) for s in paper_clearance paper_planar1 paper_both_planar paper_spatial2 paper_spatial1 paper_both_spatial; do
       scenes+=(--clearance-scene "$ROOT/tools/scenes/$s.yaml")
     done ;;
esac
"$BUILD/bin/gimbalsim_pointing_study" ${defaults[@]+"${defaults[@]}"} \
  ${scenes[@]+"${scenes[@]}"} ${args[@]+"${args[@]}"} | console_tee "$LOG" || status=$?
# Exit 3: a plant stopped; the results of the other runs are still written and plotted.
if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then exit "$status"; fi
/usr/bin/python3 "$ROOT/tools/pages/save_output.py" --as run_pointing_study.sh \
  "$LOG" "$OUT/study.log" -- ${args[@]+"${args[@]}"}
plotted=0
/usr/bin/python3 "${PLOT[@]}" || plotted=$?
# A study with no figure while tracking (every run stopped, or each ended before it) leaves the plot nothing
# to draw: it refuses (2), and the script ends as the study did, not as a refusal after everything ran. The
# previous study's figures would stand beside these results as theirs: removed (their names were checked).
# A figure's name that the plot refuses now (one came during the study) is exit 4, as an output not written.
if [ "$plotted" -ne 0 ]; then
  if [ "$plotted" -ne 2 ]; then exit "$plotted"; fi
  if ! /usr/bin/python3 "${PLOT[@]}" --check 2>/dev/null; then
    echo "run_pointing_study.sh: the figures were not written (the plot refused their names, above); the" \
      "study's outputs and log are in $OUT" >&2
    exit 4
  fi
  for fig in pointing_error_vs_time.png pointing_error_vs_clearance.png; do
    if [ -f "$OUT/$fig" ] && [ ! -L "$OUT/$fig" ]; then
      rm -f -- "$OUT/$fig" && echo "run_pointing_study.sh: removed the previous study's $OUT/$fig" >&2
    fi
  done
  echo "run_pointing_study.sh: no plot (the study ran, exit $status); its outputs and log are in $OUT" >&2
fi
if [ "$RESULTS" = 1 ]; then
  # As the plot: a study with no figure while tracking gets no page (the committed one is kept, said by the page
  # script), and the script ends as the study did; its page checks were made before the study ran.
  if [ "$plotted" -eq 2 ]; then
    echo "run_pointing_study.sh: no page either: docs/results/closed_loop_clearance.md is kept as it was" >&2
  else
    /usr/bin/python3 "$ROOT/tools/pointing_study/pointing_page.py" --dir "$(realpath "$OUT")" --command "$COMMAND" \
       --t0 "$T0" --load0 "$LOAD0"
  fi
fi
exit "$status"
