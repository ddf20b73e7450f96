#!/bin/bash
# The controller's own floor against the bearing: builds and runs
# gimbalsim_controller_floor (ideal joint and clearances 0.1-0.8 mm, perfect
# sensors; "before" = the default controller with the inertia law's
# feed-forward: constant reduced inertias, no lead) into out/controller_floor/;
# --results also writes docs/results/controller_floor.md with the stamped header
# (tools/pages/results_page.py). Other arguments go to the tool (an --ideal-scene or
# --clearance-scene among them replaces the script's). GIMBALSIM_BUILD=DIR takes that build, already
# configured, instead of build/ (read where you stand).
#
#   bash tools/pointing_study/run_controller_floor.sh --results   # the committed page
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/out_folder.sh"  # the script's own out/ folder, or a refusal
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_controller_floor.sh
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/pointing_study/run_controller_floor.sh$(printf ' %q' "$@")"
# The page only when asked: a trial with other arguments never replaces the project's page.
RESULTS=0 ARGS=()
for a in "$@"; do
  case "$a" in
    --results) RESULTS=1 ;;
    # the script writes the Markdown body itself: a second --markdown was CLI11's "At Most 1 required"
    --markdown | --markdown=*)
      echo "run_controller_floor.sh: $a: the script writes out/controller_floor/body.md; for another Markdown" \
        "file run build/bin/gimbalsim_controller_floor itself; nothing run" >&2; exit 2 ;;
    *) ARGS+=("$a") ;;
  esac
done
set -- ${ARGS[@]+"${ARGS[@]}"}
OUT="out/controller_floor"
# The paper's scenes unless the user names others (given twice, CLI11 refused "At Most 1 required")
IDEAL=(--ideal-scene "$ROOT/tools/scenes/paper_ideal.yaml")
CLEARANCE=(--clearance-scene "$ROOT/tools/scenes/paper_clearance.yaml")
for a in "$@"; do
  case "$a" in
    --ideal-scene | --ideal-scene=*) IDEAL=() ;;
    --clearance-scene | --clearance-scene=*) CLEARANCE=() ;;
  esac
done
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$BUILD" -j2 --target gimbalsim_controller_floor
# --help and --version are the program's answer alone: no run, no log saved over the previous one.
for a in "$@"; do
  case "$a" in -h | --help | --version) exec "$BUILD/bin/gimbalsim_controller_floor" "$a" ;; esac
done
out_folder run_controller_floor.sh "$OUT"
LOG=$(mktemp)  # the console log, saved into $OUT by the writer's rules
trap 'rm -f "$LOG"; out_folder_undo' EXIT  # a refused run leaves no folder it made
/usr/bin/python3 "$ROOT/tools/pages/save_output.py" --as run_controller_floor.sh \
  --check "$LOG" "$OUT/floor.log" -- "$@"  # before any run
# The page's rules before the study: a page refused at the end would cost the run and the previous outputs.
[ "$RESULTS" = 0 ] || /usr/bin/python3 "$ROOT/tools/pages/results_page.py" --check \
  --page "$ROOT/docs/results/controller_floor.md"
status=0
"$BUILD/bin/gimbalsim_controller_floor" ${IDEAL[@]+"${IDEAL[@]}"} ${CLEARANCE[@]+"${CLEARANCE[@]}"} \
  --before-set pointing.accel_feedforward=inertial --before-set pointing.feedforward_lead=0 \
  --markdown "$OUT/body.md" "$@" | console_tee "$LOG" || status=$?
# Exit 3: a plant stopped; the program wrote its outputs, and the log goes beside them (as the study's script).
if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then exit "$status"; fi
/usr/bin/python3 "$ROOT/tools/pages/save_output.py" --as run_controller_floor.sh "$LOG" "$OUT/floor.log" -- "$@"
[ "$RESULTS" = 1 ] || exit "$status"
/usr/bin/python3 "$ROOT/tools/pages/results_page.py" --page "$ROOT/docs/results/controller_floor.md" \
  --title "Controller floor against the bearing" \
  --summary "$(grep '^ideal / ' "$OUT/floor.log" | tail -1)" \
  --command "$COMMAND" --body "$OUT/body.md" --t0 "$T0" --load0 "$LOAD0"
exit "$status"
