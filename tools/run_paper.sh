#!/usr/bin/env bash
# The main job: reproduce the paper's section-4 figures (You, Pan, Zhao 2010)
# on a fresh Debian machine, from any working directory.
#
#   bash tools/run_paper.sh [key=value ...]
#
# 1. installs the apt packages (tools/bootstrap.sh, idempotent; needs root or sudo
#    the first time),
# 2. configures (once) and builds the Release build in build/,
# 3. simulates tools/scenes/paper_ideal.yaml, paper_clearance.yaml and
#    paper_spatial2.yaml (joint 2 spatial: the journal may tilt) into
#    out/paper/{ideal,clearance,spatial}.csv and .json,
# 4. plots figures 6-19 into out/paper/plots/ (tools/paper/plot_paper.py, with
#    /usr/bin/python3, Debian's matplotlib).
#
# Every extra argument is a scene override passed as `--set key=value` to ALL
# simulations (list the keys with `build/bin/gimbalsim keys`), e.g.
#   bash tools/run_paper.sh sim.duration=1                 # 1 s instead of 5 s
#   bash tools/run_paper.sh sim.duration=2 friction.mu=0.1
#
# GIMBALSIM_BUILD=DIR uses that build folder, already configured, instead of build/
# (read where you stand; CI: the tests' build-tests/, whose gimbalsim the test
# command has just built).
#
# --results also writes docs/results/paper.md (headline figures; header by
# tools/pages/results_page.py) and three of the figures, small, into docs/results/
# (paper_pointing.png, paper_joint2_force.png, paper_eccentricity.png).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/out_folder.sh"  # the script's own out/ folder, or a refusal
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_paper.sh
cd "$ROOT"

T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
COMMAND="bash tools/run_paper.sh$(printf ' %q' "$@")"
SETS=() RESULTS=0
for kv in "$@"; do
  case "$kv" in
    --results) RESULTS=1 ;;
    -h|--help) echo "usage: bash tools/run_paper.sh [--results] [key=value ...]   (e.g. sim.duration=1)"
               echo "  the paper's scene with joint 2 ideal, planar and spatial clearance, plots in out/paper/plots/;"
               echo "  key=value overrides a scene key in every run; --results writes docs/results/paper.md"
               exit 0 ;;
    *=*) SETS+=(--set "$kv") ;;
    *) echo "run_paper.sh: expected key=value scene overrides, got '$kv'" >&2
       echo "usage: bash tools/run_paper.sh [--results] [key=value ...]   (e.g. sim.duration=1)" >&2
       exit 2 ;;
  esac
done

echo "== [1/4] packages (tools/bootstrap.sh)"
bash tools/bootstrap.sh

echo "== [2/4] Release build in $BUILD/"
if [ -f "$BUILD/CMakeCache.txt" ]; then
  echo "$BUILD/ already configured: not reconfiguring"
else
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$BUILD" -j2 --target gimbalsim

SIM=$BUILD/bin/gimbalsim
OUT=out/paper
if [ -L "$OUT" ]; then out_folder run_paper.sh "$OUT"; fi  # refused: a link where the runs go
out_folder run_paper.sh "$OUT/plots"
trap 'out_folder_undo' EXIT  # a refused simulation leaves no folder it made
# A link or a folder under an output's name (pass 71: a folder there cost the whole run, then exit 4; a link was
# replaced without a word): refused as the programs refuse theirs, exit $1, saying what that leaves ($2).
# An output that is the same file as an input scene (a hard link) is refused too, as the programs refuse theirs
# (pass 76: plot_summary.txt was replaced without a word).
RUNS=(ideal:paper_ideal clearance:paper_clearance spatial:paper_spatial2)  # output name:scene
refuse_names_in_the_way() {
  local code=$1 leaves=$2 name why run
  shift 2
  for name in "$@"; do
    why=
    if [ -L "$name" ]; then why="a symbolic link; not written through"
    elif [ -d "$name" ]; then why="a folder where an output goes"
    else
      for run in "${RUNS[@]}"; do
        [ ! "$name" -ef "tools/scenes/${run#*:}.yaml" ] || why="the same file as the input tools/scenes/${run#*:}.yaml"
      done
    fi
    [ -n "$why" ] || continue
    echo "run_paper.sh: $name is $why: move it away; $leaves" >&2
    exit "$code"
  done
}
# Every output's name before anything runs, and again before the moves (one may have come meanwhile).
refuse_names_in_the_way 2 "nothing run" "$OUT"/{ideal,clearance,spatial}.{csv,json} "$OUT/plot_summary.txt" \
  "$OUT"/plots/*
# The page's rules before the study: a page refused at the end would cost the run and the previous outputs.
[ "$RESULTS" = 0 ] || /usr/bin/python3 tools/pages/results_page.py --check --page docs/results/paper.md

echo "== [3/4] simulations${SETS[*]:+ (overrides: ${SETS[*]})}"
# Every scene takes the overrides before the first runs (pass 68: one the third scene refused came after the
# first two runs had replaced theirs, and the exit said "nothing run").
for run in "${RUNS[@]}"; do  # (what it says is said again by the run itself: shown only for a refusal)
  said=$("$SIM" simulate "tools/scenes/${run#*:}.yaml" ${SETS[@]+"${SETS[@]}"} \
    --out "$OUT/${run%%:*}.csv" --summary "$OUT/${run%%:*}.json" --check 2>&1 >/dev/null) || {
    rc=$?; echo "$said" >&2; exit "$rc"; }
done
# The three runs and their plots replace the previous ones together: a run that stops, or plots refused
# (pass 69: structure.joint2=ideal ran, then the plot refused the runs it had already put in place), leaves
# the previous set as it was.
STAGE=$(mktemp -d "$OUT/.runs.XXXXXX")
trap 'rm -rf "$STAGE"; out_folder_undo' EXIT
# A stop signal waits for the program running to end its outputs (bash runs a trap once its foreground child
# is done) before the exit removes the staging folder: it said "rename failed" on the way out (pass 71).
stop_traps() {  # $1: what a stop leaves, said (pass 72: the last line was "wrote 14 figures", exit 143)
  local sig code
  for sig in INT:130 TERM:143 HUP:129; do
    code=${sig#*:}
    trap "echo \"run_paper.sh: interrupted (SIG${sig%:*}); $1\" >&2; exit $code" "${sig%:*}"
  done
}
stop_traps "the previous outputs are kept"
for run in "${RUNS[@]}"; do
  "$SIM" simulate "tools/scenes/${run#*:}.yaml" ${SETS[@]+"${SETS[@]}"} \
    --out "$STAGE/${run%%:*}.csv" --summary "$STAGE/${run%%:*}.json"
done

echo "== [4/4] plots"
LOG=$(mktemp) && trap 'rm -f "$LOG"; rm -rf "$STAGE"; out_folder_undo' EXIT
mkdir "$STAGE/plots"
/usr/bin/python3 tools/paper/plot_paper.py \
  --ideal "$STAGE/ideal.csv" --clearance "$STAGE/clearance.csv" \
  --ideal-summary "$STAGE/ideal.json" --clearance-summary "$STAGE/clearance.json" \
  --spatial "$STAGE/spatial.csv" --spatial-summary "$STAGE/spatial.json" \
  --out "$STAGE/plots" | sed -u "s#$STAGE/#$OUT/#g" | console_tee "$LOG"  # the names the files will have
/usr/bin/python3 tools/pages/save_output.py --as run_paper.sh \
  "$LOG" "$STAGE/plot_summary.txt" -- "$@"  # the writer's rules, not tee's
# The staged files, each moved to the same name under $OUT; every name checked before the first move, and the
# stop signals held during the moves: all or none.
staged=(plot_summary.txt)
for run in "${RUNS[@]}"; do staged+=("${run%%:*}.csv" "${run%%:*}.json"); done
for f in "$STAGE"/plots/*; do staged+=("plots/${f##*/}"); done
refuse_names_in_the_way 4 "the previous outputs are kept" "${staged[@]/#/$OUT/}"
trap '' INT TERM HUP
for rel in "${staged[@]}"; do mv -fT "$STAGE/$rel" "$OUT/$rel"; done
stop_traps "the new outputs are all in place"

echo
echo "Outputs (under $ROOT):"
echo "  runs     : $OUT/ideal.csv $OUT/clearance.csv $OUT/spatial.csv"
echo "  summaries: $OUT/ideal.json $OUT/clearance.json $OUT/spatial.json"
echo "  figures  : $OUT/plots/fig06_eccentricity.png ... fig19_joint_kinds.png"
echo "  pointing : $OUT/plots/pointing_error.csv"
if [ "$RESULTS" = 1 ]; then
  /usr/bin/python3 tools/paper/paper_page.py --dir "$OUT" --command "$COMMAND" --t0 "$T0" --load0 "$LOAD0"
fi
