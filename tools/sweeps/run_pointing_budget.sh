#!/usr/bin/env bash
# The pointing budget. Without SPEC: the shipped budget,
# tools/sweeps/pointing_budget.yaml, run in closed loop (gimbalsim.sweep) into
# out/pointing_budget/, its report stamped (machine, commit, date) into
# docs/results/pointing_budget.md with its CDF plots beside it. With --spatial:
# the budget with the bearing that tilts, pointing_budget_spatial.yaml (encoders
# only) and pointing_budget_spatial_tracker.yaml (the loop at the antenna), into
# out/<spec name>/ each and one page, docs/results/pointing_budget_spatial.md. With --allocation:
# the inverse question, the largest clearance of that bearing meeting 1e-4 rad (gimbalsim.allocate),
# allocation_clearance_encoders.yaml and allocation_clearance.yaml, into out/<spec name>/ each and
# docs/results/allocation.md with each allocation's plot beside it.
# With SPEC (any spec, the shipped ones too): that budget, into
# out/pointing_budget-<spec name>/ (or --out DIR); the project's pages are never touched.
#
#   bash tools/sweeps/run_pointing_budget.sh [--spatial | --allocation] [options]  # a shipped page
#   bash tools/sweeps/run_pointing_budget.sh MY_SPEC [--out DIR] [sweep options, e.g. --workers 2]
#
# The package is the one in ${GIMBALSIM_BUILD:-build}/python (cmake --build build --target gimbalsim_python).
# Options after SPEC go to python3 -m gimbalsim.sweep (gimbalsim.allocate with --allocation; its --help
# lists them); --help (-h) prints this and --version the module's version, before anything runs. A refused
# spec or a failed run leaves the previous results as they were: they are replaced only by a new folder the
# run completed. An interrupted shipped page's run keeps its samples in out/<spec name>.new/: the same command
# with --resume finishes it. One run at a time writes docs/results/ (a second is refused, exit 2). The page
# and its plots change together or not at all (exit 4 leaves them as they were). --check checks, runs nothing.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/children.sh"  # stop_children
# The shipped pages: page name, its title and summary, then each spec with its section's heading (none for one).
PAGE=pointing_budget TITLE="Closed-loop pointing budget"
SUMMARY="ECSS indices per phase over a bearing's tolerance, with order-statistics intervals"
SPECS=(tools/sweeps/pointing_budget.yaml) HEADINGS=("")
# What each spec's run is: the module, the files of a whole run (the last one its report), what an
# interrupted run has kept once it exists, and the exit codes that are answers (allocate: 3 is "no bracket").
MODULE=sweep WHOLE=(results.csv summary.json report.md) STARTED=(results.partial.csv results.csv) ANSWERS=" 0 "
FLAG=
case "${1:-}" in
  --spatial)
    FLAG=$1 WHAT="spatial budgets"
    PAGE=pointing_budget_spatial TITLE="Closed-loop pointing budget with the bearing that tilts"
    SUMMARY="ECSS indices per phase over a tilting bearing's tolerance, encoders only and with the antenna's sensors"
    SPECS=(tools/sweeps/pointing_budget_spatial.yaml tools/sweeps/pointing_budget_spatial_tracker.yaml) ;;
  --allocation)
    FLAG=$1 WHAT="allocations"
    PAGE=allocation TITLE="Tolerance allocation: the largest clearance of the bearing that tilts"
    SUMMARY="the largest elevation-bearing clearance for APE while tracking <= 1e-4 rad at 99.73 % (95 %),"
    SUMMARY+=" encoders only and with the antenna's sensors"
    SPECS=(tools/sweeps/allocation_clearance_encoders.yaml tools/sweeps/allocation_clearance.yaml)
    MODULE=allocate WHOLE=(allocation.json allocation.csv allocation.md) STARTED=(allocation_spec.json)
    ANSWERS=" 0 3 " ;;
esac
if [ -n "$FLAG" ]; then
  shift
  HEADINGS=("The loop on the encoders only" "The loop at the antenna (tracker and gyro on the antenna)")
  if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then  # a spec where the module's options start
    echo "run_pointing_budget.sh: $FLAG runs the shipped $WHAT; a spec ($1) runs alone:" \
      "run_pointing_budget.sh $1" >&2
    exit 2
  fi
fi
REPORT=${WHOLE[2]}
T0=$(date +%s.%N) LOAD0=$(cat /proc/loadavg)
# --help and --version are the script's, answered before anything (they went to the sweep, which wrote
# nothing, and the previous results were removed all the same).
info=
for a in "$@"; do case "$a" in -h | --help | --version) info=$a; break ;; esac; done
if [ "$info" != "" ] && [ "$info" != --version ]; then
  script_usage "${BASH_SOURCE[0]}" 2 24
  exit 0
fi
SPEC=  # none: a shipped budget and its page
if [ "$PAGE" = pointing_budget ] && [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  SPEC=$1
  shift
fi
# A spec after an option (--check c1.yaml) went to the shipped budget's sweeps: "unrecognized arguments" (pass 90)
if [ -z "$SPEC" ]; then
  for a in "$@"; do
    case "$a" in
      -*) ;;
      *) [ ! -f "$a" ] || {  # (pass 93: a spec not named .yaml went to the sweeps too)
        echo "run_pointing_budget.sh: $a: a spec goes first, before the options: run_pointing_budget.sh $a" \
          "[options]; nothing run" >&2
        exit 2
      } ;;
    esac
  done
fi
ARGS=("$@")
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_pointing_budget.sh reads
PACKAGE=$BUILD/python
[ -f "$PACKAGE/gimbalsim/__init__.py" ] || {
  echo "run_pointing_budget.sh: no gimbalsim package in $PACKAGE: cmake --build build -j2 --target gimbalsim_python" >&2
  exit 2
}
if [ "$info" = --version ]; then
  exec env PYTHONPATH="$PACKAGE" /usr/bin/python3 -m "gimbalsim.$MODULE" --version
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
  trap stop_children EXIT  # a signal to the script alone: the sweep ends too, its journal whole
  PYTHONPATH="$PACKAGE" /usr/bin/python3 -m gimbalsim.sweep "$SPEC" ${OUT:+--out "$OUT"} --no-progress \
    "${ARGS[@]+"${ARGS[@]}"}" || rc=$?
  checked=0  # --check: nothing written, so no out/ left either
  for a in "${ARGS[@]+"${ARGS[@]}"}"; do [ "$a" != --check ] || checked=1; done
  { [ "$rc" -eq 0 ] && [ "$checked" = 0 ]; } || [ "$made_out" = 0 ] || rmdir out 2>/dev/null || true
  exit "$rc"
fi

for a in "${ARGS[@]+"${ARGS[@]}"}"; do
  if [ "$a" = "--out" ] || [ "${a#--out=}" != "$a" ]; then
    echo "run_pointing_budget.sh: without a SPEC this regenerates the project's page from out/<spec name>/;" \
         "to write elsewhere, name the spec: run_pointing_budget.sh ${SPECS[0]} --out DIR" >&2
    exit 2
  fi
done
cd "$ROOT"
RESULTS=docs/results
# Everything checked before any budget runs, so a refusal costs nothing (exit 2): every spec (the second
# was refused only after the first budget's run), the page and this page's plots (a link there was found
# only after both budgets had replaced the previous results).
# SHOWN: the options given less --resume and --check. The page's command regenerates it with them, and the
# checks below take them (a --resume of the check's own folder, which never exists, would refuse every run).
SHOWN=() resume=0 check=0
for a in "${ARGS[@]+"${ARGS[@]}"}"; do
  case "$a" in --resume) resume=1 ;; --check) check=1 ;; *) SHOWN+=("$a") ;; esac
done
for spec in "${SPECS[@]}"; do
  # (a name in the checkout, whose out/ may not exist yet: --check writes nothing)
  PYTHONPATH="$PACKAGE" /usr/bin/python3 -m "gimbalsim.$MODULE" "$spec" --out "$ROOT/budget-check-$$" --check \
    "${SHOWN[@]+"${SHOWN[@]}"}"
done
own_plots() {  # this page's plots now in docs/results (by index: pointing_budget_* would match another page's)
  local spec index png
  for spec in "${SPECS[@]}"; do
    if [ "$MODULE" = allocate ]; then  # one plot per allocation, <spec name>.png
      png="$RESULTS/$(basename "${spec%.*}").png"
      [ ! -e "$png" ] && [ ! -L "$png" ] || echo "$png"
      continue
    fi
    for index in ape rpe pde knowledge; do
      for png in "$RESULTS/$(basename "${spec%.*}")_${index}_"*; do
        case "$png" in *_cdf.png) [ ! -e "$png" ] && [ ! -L "$png" ] || echo "$png" ;; esac
      done
    done
  done
}
plot_links() {  # the sed script that turns a report's plot links into the copies' names beside the page
  if [ "$MODULE" = allocate ]; then echo "s#](allocation.png)#]($1.png)#"; else echo "s#](plots/#]($1_#"; fi
}
check_page_names() {  # the page, the index and this page's plots: regular files or nothing, never a link
  local name
  for name in "$RESULTS/$PAGE.md" "$RESULTS/README.md" $(own_plots); do
    if [ -L "$name" ] || { [ -e "$name" ] && [ ! -f "$name" ]; }; then
      echo "run_pointing_budget.sh: $name: a symbolic link or not a regular file where the page writes;" \
           "$1: remove it" >&2
      return 1
    fi
  done
}
check_page_names "nothing run" || exit 2
# and the writer's own rules for the page and its index (a hand-written README.md there is never replaced)
/usr/bin/python3 tools/pages/results_page.py --check --page "$RESULTS/$PAGE.md"
if [ ! -d "$RESULTS" ]; then
  echo "run_pointing_budget.sh: $ROOT/$RESULTS: no such folder, where the page goes; nothing run" >&2
  exit 2
fi
# One run of this script at a time: two would share out/<spec name>.new/ and this page's plots. Its lock is
# on the script itself; the page writer locks docs/results only while it writes a page and the index, so
# other pages can be made while a budget runs.
exec 9<"$ROOT/tools/sweeps/run_pointing_budget.sh"
if ! flock -n 9; then
  echo "run_pointing_budget.sh: another run_pointing_budget.sh is writing $ROOT/$RESULTS; nothing run:" \
       "wait for it to end" >&2
  exit 2
fi
COMMAND="bash tools/sweeps/run_pointing_budget.sh${FLAG:+ $FLAG}"
[ "${#SHOWN[@]}" = 0 ] || COMMAND+=$(printf ' %q' "${SHOWN[@]}")  # (printf with no words prints '')
# Each budget into a fresh folder first: the previous results go only once every budget of the page has
# its own (a refused spec or a failed run leaves them all as they were, and an out/ made for it goes again).
# An interrupted run's new folders are kept for --resume, which this script passes to each sweep; without
# it such a folder is refused, not overwritten.
NEWS=() OLDS=()
for spec in "${SPECS[@]}"; do
  name=$(basename "${spec%.*}")
  NEWS+=("out/$name.new") OLDS+=("out/$name.old-$$")
  if [ "$resume" = 0 ] && { [ -e "out/$name.new" ] || [ -L "out/$name.new" ]; }; then
    echo "run_pointing_budget.sh: out/$name.new holds an interrupted budget; nothing run: give the same" \
         "command with --resume to finish it, or remove that folder to start over" >&2
    exit 2
  fi
done
if [ "$check" = 1 ]; then
  echo "run_pointing_budget.sh: the specs, the page and its plots checked; nothing run" >&2
  exit 0
fi
made_out=0
if [ ! -d out ]; then mkdir out && made_out=1; fi
BODY=$(mktemp)  # the page's body, private (a name under out/ could be a link planted since)
BACKUP=""       # the previous page's plots while the new ones go in
keep=0          # 1 while the budgets run: an interruption keeps their folders for --resume
restore() {
  local i kept=0
  stop_children  # a sweep still running (the script alone was signalled): its journal whole before the folders
  if [ "$keep" = 1 ]; then  # any budget's work (a journal, or a finished budget beside an interrupted one)
    for i in "${!SPECS[@]}"; do
      for f in "${STARTED[@]}"; do [ ! -e "${NEWS[$i]}/$f" ] || kept=1; done
    done
  fi
  for i in "${!SPECS[@]}"; do
    local out
    out="out/$(basename "${SPECS[$i]%.*}")"
    if [ "$kept" = 1 ]; then
      [ ! -d "${NEWS[$i]}" ] || echo "run_pointing_budget.sh: ${NEWS[$i]} kept; the previous results left as" \
        "they were: give the same command with --resume to finish (or remove it to start over)" >&2
    else
      rm -rf "${NEWS[$i]}"
    fi
    [ -e "$out" ] || [ ! -d "${OLDS[$i]}" ] || mv "${OLDS[$i]}" "$out"
  done
  if [ -n "$BACKUP" ]; then  # the page was not written: its previous plots back, the new ones out
    local png
    for png in $(own_plots); do rm -f "$png"; done
    for png in "$BACKUP"/*; do [ ! -e "$png" ] || mv "$png" "$RESULTS/"; done
    rmdir "$BACKUP"
  fi
  rm -f "$BODY"
  [ "$made_out" = 0 ] || rmdir out 2>/dev/null || true
}
trap restore EXIT
keep=1
for i in "${!SPECS[@]}"; do
  rc=0
  PYTHONPATH="$PACKAGE" /usr/bin/python3 -m "gimbalsim.$MODULE" "${SPECS[$i]}" --out "${NEWS[$i]}" --no-progress \
    "${ARGS[@]+"${ARGS[@]}"}" || rc=$?
  case "$ANSWERS" in *" $rc "*) ;; *) exit "$rc" ;; esac
  # The previous results go only for a whole new folder: the sweep's results, summary and report, no journal
  # left (an option that makes the sweep answer and write nothing must not cost them).
  for f in "${WHOLE[@]}"; do
    new=${NEWS[$i]}
    if [ -L "$new" ] || [ ! -d "$new" ] || [ -L "$new/$f" ] || [ ! -f "$new/$f" ] || [ -e "$new/results.partial.csv" ]; then
      echo "run_pointing_budget.sh: gimbalsim.$MODULE ended well but left no whole budget in $new" \
           "(no $f, or its journal); the previous results left as they were" >&2
      keep=0
      exit 1
    fi
  done
done
keep=0
[ "${#SPECS[@]}" = 1 ] || printf '%s\n\n' "The same units (each spec's seed and bearing tolerance), \
once per set of sensors the loop reads; each spec states its tolerance in its comments." >> "$BODY"
for i in "${!SPECS[@]}"; do
  name=$(basename "${SPECS[$i]%.*}")
  # the report's plots/NAME links become the copies' names beside the page; under a section, its
  # headings one level down
  if [ -n "${HEADINGS[$i]}" ]; then
    printf '## %s\n\nSpec: `%s`\n\n' "${HEADINGS[$i]}" "${SPECS[$i]}" >> "$BODY"
    sed -e "$(plot_links "$name")" -e 's/^#\(#* \)/##\1/' "${NEWS[$i]}/$REPORT" >> "$BODY"
  else
    sed "$(plot_links "$name")" "${NEWS[$i]}/$REPORT" >> "$BODY"
  fi
  printf '\n' >> "$BODY"
done
# The page and its plots together or not at all: the previous plots wait aside until the page is
# written (restore puts them back otherwise), names checked again (a link planted while the budgets ran).
check_page_names "the previous results left as they were" || exit 4
BACKUP=$(mktemp -d "$RESULTS/.page_backup.XXXXXX")
for png in $(own_plots); do mv "$png" "$BACKUP/"; done
for i in "${!SPECS[@]}"; do
  name=$(basename "${SPECS[$i]%.*}")
  if [ "$MODULE" = allocate ]; then
    cp --remove-destination "${NEWS[$i]}/allocation.png" "$RESULTS/$name.png"
    continue
  fi
  for png in "${NEWS[$i]}"/plots/*_cdf.png; do
    [ -e "$png" ] || continue
    cp --remove-destination "$png" "$RESULTS/${name}_$(basename "$png")"  # a link made since: replaced, not followed
  done
done
keep=1  # interrupted from here on, the budgets stay for --resume (which reads them back)
rc=0
/usr/bin/python3 tools/pages/results_page.py --page "$RESULTS/$PAGE.md" \
  --title "$TITLE" --command "$COMMAND" --body "$BODY" --summary "$SUMMARY" --t0 "$T0" --load0 "$LOAD0" || rc=$?
[ "$rc" = 0 ] || exit "$([ "$rc" -gt 128 ] && echo "$rc" || echo 4)"  # a signal's code, else 4: not written
rm -rf "$BACKUP"
BACKUP=""
# Swapped, not removed first: the previous results come back if the new ones cannot be moved into place.
for i in "${!SPECS[@]}"; do
  out="out/$(basename "${SPECS[$i]%.*}")"
  if [ -e "$out" ] || [ -L "$out" ]; then mv "$out" "${OLDS[$i]}"; fi
  if ! mv "${NEWS[$i]}" "$out"; then
    echo "run_pointing_budget.sh: could not move ${NEWS[$i]} into $out; the previous results left as they were" >&2
    exit 4
  fi
done
keep=0
for old in "${OLDS[@]}"; do rm -rf "$old"; done
