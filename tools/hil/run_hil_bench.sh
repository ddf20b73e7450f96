#!/usr/bin/env bash
# One-script hardware-in-the-loop bench: firmware_sim + pointing_controller
# (+ a recorder with --log) over LCM udpm (ttl=0) inside a private network
# namespace, in lockstep (default) or real time; writes the truth CSV, the
# controller's log, firmware_sim's summary, the LCM log and its CSVs, and a
# plot into the output directory (default out/bench/).
#
#   bash tools/hil/run_hil_bench.sh [--realtime | --lockstep] [--duration S] [--scene FILE] [--config FILE]
#                               [--rate HZ] [--port PORT] [--log] [--out DIR] [--no-plot] [-- FIRMWARE_SIM_ARGS...]
#
# Namespace: `unshare -n` (root), else `unshare -rn` (user namespace); if
# neither works it runs in the host's network with ttl=0 (nothing leaves the
# host) and says so. Not to be confused with tools/bench/run_bench.sh (the
# dynamics micro-benchmarks). The run writes into a fresh folder inside the
# output directory and moves its files into place only when both processes
# ended well, or the plant stopped (exit 3: the run up to the stop, and the
# script ends with 3): a refused or failed run changes nothing there. GIMBALSIM_BUILD
# names the build directory (default build).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
source "$ROOT/tools/lib/console.sh"  # a console whose reader is gone stops nothing
source "$ROOT/tools/lib/children.sh"  # stop_children

MODE=lockstep DURATION=8 SCENE="$ROOT/tools/scenes/paper_clearance.yaml" CONFIG="$ROOT/controllers/config/default.yaml"
RATE=1000 LOG=0 OUT="$ROOT/out/bench" OUT_GIVEN=0 PLOT=1 PORT=7667 EXTRA=()
usage() { script_usage "$0" 2 18; exit "${1:-0}"; }
# value FLAG ARGS...: the flag's value, refused (exit 2) naming FLAG when missing or empty (not set -u's exit 1),
# and when it is another flag: `--out --no-plot` lost the flag, then dirname took '--no-plot' as its option
# (exit 1). A value that starts with one - is a value (`--out -res` is the folder -res, `--duration -1` a
# number refused as such); one that starts with -- is taken for a flag: a folder of that name is ./--name.
# A flag of one value given twice is refused, as the programs refuse theirs: the last one was taken silently
# (pass 76: `--duration 5 --duration 8`), and so was the last of --realtime and --lockstep.
GIVEN=" "
once() {
  case "$GIVEN" in *" $1 "*) echo "run_hil_bench.sh: $1: given twice; it takes one value" >&2; exit 2 ;; esac
  GIVEN="$GIVEN$1 "
}
value() {
  once "$1"
  [ $# -ge 2 ] || { echo "run_hil_bench.sh: $1: needs a value" >&2; exit 2; }
  [ -n "$2" ] || { echo "run_hil_bench.sh: $1: an empty value" >&2; exit 2; }
  case "$2" in --*) echo "run_hil_bench.sh: $1: needs a value, got the flag $2 (a file or folder of that name: ./$2)" >&2
                    exit 2 ;; esac
}
while [ $# -gt 0 ]; do
  case "$1" in
    --realtime) once --realtime/--lockstep; MODE=realtime ;;
    --lockstep) once --realtime/--lockstep; MODE=lockstep ;;
    --duration) value "$@"; DURATION="$2"; shift ;;
    --scene) value "$@"; SCENE="$2"; shift ;;
    --config) value "$@"; CONFIG="$2"; shift ;;
    --rate) value "$@"; RATE="$2"; shift ;;
    --log) LOG=1 ;;
    --out) value "$@"; OUT="$2"; OUT_GIVEN=1; shift ;;
    --no-plot) PLOT=0 ;;
    --port) value "$@"; PORT="$2"; shift ;;
    -h|--help) usage 0 ;;
    --version) script_version run_hil_bench.sh; exit 0 ;;
    --) shift; EXTRA=("$@"); break ;;
    *) echo "run_hil_bench.sh: unknown argument '$1'" >&2; usage 2 ;;
  esac
  shift
done
# A path that starts with - is a name, not an option, for every program it is handed to (dirname, cd, mkdir,
# pointing_controller's positional config): written ./-name from here on, in messages too.
for v in SCENE CONFIG OUT; do case "${!v}" in -*) printf -v "$v" '%s' "./${!v}" ;; esac; done
# Numbers are checked here, as given: the period 1/--rate and the URL derived from them would be blamed otherwise.
number() {  # number FLAG VALUE LO HI: a plain decimal number in [LO, HI], else refused naming FLAG
  # read as the programs read it (a sign allowed; 1e-400, which would read as 0, refused: usage.md "Exit codes")
  [[ "$2" =~ ^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$ ]] ||
    { echo "run_hil_bench.sh: $1: '$2' is not a plain decimal number" >&2; exit 2; }
  # 010: awk reads 10, the programs refuse it (C would read octal 8): refused here, before anything starts
  [[ ! "$2" =~ ^[-+]?0[0-9] ]] ||
    { echo "run_hil_bench.sh: $1: '$2' is not a number written without a leading zero" >&2; exit 2; }
  ! awk -v x="$2" -v m="${2%%[eE]*}" 'BEGIN { v = x + 0; if (v < 0) v = -v
      exit !((v == 0 && m ~ /[1-9]/) || (v > 0 && v < 2.2250738585072014e-308)) }' ||
    { echo "run_hil_bench.sh: $1: '$2' is too small for a double (it would be read as 0 or lose its digits)" >&2
      exit 2; }
  awk -v x="$2" -v lo="$3" -v hi="$4" 'BEGIN { exit !(x + 0 >= lo + 0 && x + 0 <= hi + 0) }' ||
    { echo "run_hil_bench.sh: $1: must be in [$3, $4], got $2" >&2; exit 2; }
}
number --rate "$RATE" 0.001 1e+06  # firmware_sim's range; the controller's control.period = 1/--rate then fits too
number --duration "$DURATION" 0 1e+09
# 0 would run until a signal, and a run a signal ends keeps nothing: refused (the programs run open-ended by hand)
awk -v x="$DURATION" 'BEGIN { exit !(x + 0 > 0) }' ||
  { echo "run_hil_bench.sh: --duration: must be above 0, got $DURATION (0 runs until a signal, and a run a" \
         "signal ends keeps nothing; for an open-ended bench run the two programs: docs/bench.md \"Two terminals\")" >&2
    exit 2; }
# no leading zero: LCM reads 07815 as octal (port 7) where the programs' receivers read 7815
[[ "$PORT" =~ ^[1-9][0-9]*$ ]] && [ "${#PORT}" -le 5 ] && [ "$PORT" -ge 1 ] && [ "$PORT" -le 65535 ] ||
  { echo "run_hil_bench.sh: --port: must be a whole number in [1, 65535] without a leading zero, got '$PORT'" >&2
    exit 2; }
PERIOD=$(awk -v r="$RATE" 'BEGIN { printf "%.17g", 1.0 / r }')
# A GIMBALSIM_BUILD the user names is never built; the default is the checkout's build/, built when a program
# is missing.
source "$ROOT/tools/lib/build_dir.sh"  # BUILD: GIMBALSIM_BUILD where the user stands, or build/
build_dir run_hil_bench.sh reads
BIN="$BUILD/bin"
# Every file a run may leave in --out (bench_*.csv: gimbalsim_log2csv's, one per channel).
OUTPUTS=(truth.csv controller.csv controller.txt firmware.txt bench.lcmlog bench.png)
URL="udpm://239.255.76.67:${PORT}?ttl=0"

if [ "${GIMBALSIM_BENCH_INSIDE:-0}" != 1 ]; then
  for f in "$SCENE" "$CONFIG"; do [ -f "$f" ] || { echo "run_hil_bench.sh: no such file: $f" >&2; exit 2; }; done
  for t in firmware_sim pointing_controller gimbalsim_log2csv gimbalsim_record; do
    if [ ! -x "$BIN/$t" ]; then
      [ -z "${GIMBALSIM_BUILD:-}" ] || { echo "run_hil_bench.sh: GIMBALSIM_BUILD=$GIMBALSIM_BUILD: no $BIN/$t" >&2; exit 2; }
      cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
      cmake --build "$BUILD" -j2 --target firmware_sim pointing_controller gimbalsim_log2csv gimbalsim_record
      break
    fi
  done
  # The controller's configuration is checked before anything runs: a refusal in the run would show only
  # as firmware_sim's "no controller answered" (exit 6) after --start-timeout.
  c=0
  msg=$("$BIN/pointing_controller" "$CONFIG" --set control.period="$PERIOD" --duration "$DURATION" --print-config \
        2>&1 >/dev/null) || c=$?
  if [ "$c" != 0 ]; then
    printf '%s\n' "$msg" >&2
    echo "run_hil_bench.sh: pointing_controller refused --config $CONFIG with control.period = 1/--rate = 1/$RATE s," \
         "--duration $DURATION (exit $c, its message above); nothing run" >&2
    exit "$c"
  fi
  # Its own folder is made (the default out/bench included), never the ones above it (usage.md "Output files").
  parent="$(dirname -- "$OUT")"
  [ "$OUT_GIVEN" = 0 ] || [ -d "$parent" ] || { echo "run_hil_bench.sh: --out $OUT: the folder it goes in, $parent, does not exist (create it first)" >&2; exit 2; }
  # --out itself: a folder, never a link to one or a file (usage.md "Output files")
  if [ -L "$OUT" ] || { [ -e "$OUT" ] && [ ! -d "$OUT" ]; }; then
    echo "run_hil_bench.sh: --out $OUT: a link or not a folder; name a folder" >&2; exit 2
  fi
  # A link or a folder under an output's name is refused before anything runs (usage.md "Output files").
  for f in "${OUTPUTS[@]}" "$OUT"/bench_*.csv; do
    f="$OUT/${f#"$OUT"/}"
    if [ -L "$f" ] || { [ -e "$f" ] && [ ! -f "$f" ]; }; then
      echo "run_hil_bench.sh: $f: a link or not a regular file under an output's name; move it out" >&2; exit 2
    fi
  done
  # Arguments after -- are the user's: a flag the script sets itself is refused up front (firmware_sim's
  # "At Most 1" came only after the controller had started), naming what to use instead (docs/bench.md).
  inputs=("--scene" "$SCENE" "--config" "$CONFIG")
  # (pass 97) and the programs and scripts it runs: a --tick-log over pointing_controller replaced it with a CSV
  for t in firmware_sim pointing_controller gimbalsim_log2csv gimbalsim_record; do
    inputs+=("the program" "$BIN/$t")
  done
  inputs+=("the script" "${BASH_SOURCE[0]}" "the script" "$ROOT/tools/hil/plot_bench.py")
  for f in "$ROOT"/tools/lib/*.sh; do inputs+=("the script" "$f"); done  # (pass 99) the libraries it sources
  inputs+=("the interpreter" /usr/bin/python3 "the interpreter" "$BASH")  # (pass 101) plot_bench's, its own
  outs=()   # the outputs the user names after -- (label, absolute path): the --tick-log
  files=()  # every file flag after -- (flag, as given, absolute path)
  for ((i = 0; i < ${#EXTRA[@]}; i++)); do
    a=${EXTRA[i]%%=*} v='' eq=0
    [ "$a" = "${EXTRA[i]}" ] || { v=${EXTRA[i]#*=} eq=1; }
    case "$a" in
      --profile) use="it is --config's file (the controller's config defines the pointing error for both); use --config" ;;
      --truth-csv) use="it is truth.csv in --out; use --out" ;;
      --lcm-url) use="the run's udpm URL with ttl=0; use --port" ;;
      # (pass 88) a prefix for firmware_sim alone split the pair: the controller never heard it
      --channel-prefix) use="both processes must share it, and the run's own --port keeps benches apart; use --port" ;;
      --rate | --duration) use="use $a before --" ;;
      --lockstep) use="lockstep is the default; --realtime before -- for real time" ;;
      *) use= ;;
    esac
    [ -z "$use" ] || { echo "run_hil_bench.sh: $a after --: the script sets it for firmware_sim: $use; nothing run" >&2; exit 2; }
    # The files firmware_sim reads or writes are the user's paths, read where the user stands (the run
    # itself is in a folder inside --out): made absolute here, and an input is checked before anything runs.
    # A value that starts with -- is a flag, as before -- (firmware_sim's parser reads it so too); one that
    # starts with a single - is a name, made absolute like every other.
    case "$a" in --faults | --tick-log) ;; *) continue ;; esac
    if [ "$eq" = 0 ]; then
      [ $((i + 1)) -lt ${#EXTRA[@]} ] || { echo "run_hil_bench.sh: $a after --: needs a value" >&2; exit 2; }
      i=$((i + 1)) v=${EXTRA[i]}
      case "$v" in --*) echo "run_hil_bench.sh: $a after --: needs a value, got the flag $v (a file of that name: ./$v)" >&2
                        exit 2 ;; esac
    fi
    [ -n "$v" ] || { echo "run_hil_bench.sh: $a after --: an empty value" >&2; exit 2; }
    given=$v
    case "$v" in /*) ;; *) v="$PWD/$v" ;; esac
    if [ "$eq" = 1 ]; then EXTRA[i]="$a=$v"; else EXTRA[i]=$v; fi
    # firmware_sim takes each once ("At Most 1" only in the run, after the controller had started)
    for ((j = 0; j < ${#files[@]}; j += 3)); do
      [ "${files[j]}" != "$a" ] || { echo "run_hil_bench.sh: $a after --: given twice (${files[j + 1]}, $given);" \
                                           "firmware_sim takes one; nothing run" >&2; exit 2; }
    done
    files+=("$a" "$given" "$v")
    if [ "$a" = --tick-log ]; then outs+=("$a $given (after --)" "$v"); continue; fi
    why=
    if [ ! -e "$v" ]; then why="no such file"; elif [ ! -f "$v" ]; then why="not a regular file"
    elif [ ! -r "$v" ]; then why="not readable"; fi
    [ -z "$why" ] || { echo "run_hil_bench.sh: $a $given (after --): $why; nothing run" >&2; exit 2; }
    inputs+=("$a (after --)" "$v")
  done
  # An output that is one of the inputs (same device and inode: a hard link or ./truth.csv counts) is refused
  # before anything runs (usage.md "Output files"): the scene, the config, and a --faults file after --.
  # (passes 103, 107, 111) an executable file anything run by name finds (in a folder on PATH, or named by a link
  # or a hard link in one) is no output, as the writer refuses it: "in F, a folder on PATH" or "run as F/N on PATH"
  program_on_path() {  # the writer's rule itself (pass 113: a copy of it here missed a dot-named link)
    [ -f "$1" ] && [ -x "$1" ] || return 1
    /usr/bin/python3 -c 'import os, sys; sys.path.insert(0, sys.argv[1]); import output_file
where = output_file.program_on_path(sys.argv[2], os.stat(sys.argv[2])); print(where or ""); sys.exit(not where)' \
      "$ROOT/tools/pages" "$1"
  }
  for f in "${OUTPUTS[@]}" "$OUT"/bench_*.csv; do
    f="$OUT/${f#"$OUT"/}"
    [ -e "$f" ] || continue
    if where=$(program_on_path "$f"); then
      echo "run_hil_bench.sh: $f: an output that is an executable file $where (a program anything run by name" \
           "may be); nothing run" >&2
      exit 2
    fi
    for ((i = 0; i < ${#inputs[@]}; i += 2)); do
      if [ "$f" -ef "${inputs[i + 1]}" ]; then
        echo "run_hil_bench.sh: $f: an output that is the input ${inputs[i]} ${inputs[i + 1]} (same file); nothing run" >&2
        exit 2
      fi
    done
  done
  # An output named after -- (the --tick-log: firmware_sim writes it itself, at the end of the run, where the
  # user said) is compared with every output the script writes, with --out itself and with every input,
  # resolved (realpath -m: links in the path, ./ and .. count; a file need not exist yet) or the same file (-ef:
  # a hard link counts); a second one, the same file or not, was refused above as given twice, naming both.
  # A --tick-log ob3/truth.csv was written, then replaced by the truth CSV (exit 0); a bench_*.csv in --out
  # is a name the script's log2csv writes and whose previous files a run removes.
  same() { [ "$(realpath -m -- "$1")" = "$(realpath -m -- "$2")" ] || [ "$1" -ef "$2" ]; }
  mine=("the output folder --out" "$OUT")
  for f in "${OUTPUTS[@]}"; do mine+=("the output $f in --out" "$OUT/$f"); done
  out_r=$(realpath -m -- "$OUT")
  for ((k = 0; k < ${#outs[@]}; k += 2)); do
    o=${outs[k + 1]} clash=
    for ((j = 0; j < ${#mine[@]}; j += 2)); do
      ! same "$o" "${mine[j + 1]}" || { clash="the same file as ${mine[j]} (${mine[j + 1]})"; break; }
    done
    o_r=$(realpath -m -- "$o")
    if [ -z "$clash" ] && [ "$(dirname -- "$o_r")" = "$out_r" ]; then
      case "$(basename -- "$o_r")" in
        bench_*.csv) clash="the name of an output in --out ($OUT/bench_*.csv: the LCM log's CSVs with --log;"
                     clash+=" a run removes the previous run's)" ;;
      esac
    fi
    for ((j = 0; j < ${#inputs[@]} && ${#clash} == 0; j += 2)); do
      ! same "$o" "${inputs[j + 1]}" || clash="the same file as the input ${inputs[j]} ${inputs[j + 1]}; not overwritten"
    done
    # (pass 103, 107) and every program it runs by name (/usr/bin/dash as sh, unshare, rmdir)
    if [ -z "$clash" ] && where=$(program_on_path "$o"); then
      clash="an executable file $where (a program anything run by name may be); not overwritten"
    fi
    [ -z "$clash" ] || { echo "run_hil_bench.sh: ${outs[k]}: $clash; nothing run" >&2; exit 2; }
  done
  # A folder made for this run goes again if the run does not end well (a refused run leaves nothing).
  # A folder that cannot be made is an output not written (exit 4), said as such (set -e ended it with 1).
  cannot_make() {
    echo "run_hil_bench.sh: --out $OUT: cannot make $1 (the system's reason above); nothing run" >&2
    exit 4
  }
  [ "$OUT_GIVEN" = 1 ] || mkdir -p "$parent" || cannot_make "$parent"  # the default out/bench: out/ is the project's
  if [ ! -d "$OUT" ]; then
    mkdir "$OUT" || cannot_make it
    export GIMBALSIM_BENCH_MADE_OUT=1
  fi
  OUT="$(cd "$OUT" && pwd)"
  export GIMBALSIM_BUILD="$BUILD"
  SCENE="$(realpath -- "$SCENE")" CONFIG="$(realpath -- "$CONFIG")"
  export GIMBALSIM_BENCH_INSIDE=1
  args=(--duration "$DURATION" --scene "$SCENE" --config "$CONFIG" --rate "$RATE" --out "$OUT" --port "$PORT")
  [ "$MODE" = realtime ] && args+=(--realtime)
  [ "$LOG" = 1 ] && args+=(--log)
  [ "$PLOT" = 0 ] && args+=(--no-plot)
  setup='ip link set lo up && ip route add 224.0.0.0/4 dev lo'
  for ns in "unshare -n" "unshare -rn"; do
    if $ns sh -c "$setup" >/dev/null 2>&1; then
      echo "run_hil_bench.sh: private network namespace ($ns), $URL"
      exec $ns sh -c "$setup && exec bash \"\$0\" \"\$@\"" "$0" "${args[@]}" -- "${EXTRA[@]}"
    fi
  done
  echo "run_hil_bench.sh: warning: no private network namespace here (unshare -n and -rn refused);" \
       "running in the host network with ttl=0 on port $PORT (another bench on this port would mix in)" >&2
  exec bash "$0" "${args[@]}" -- "${EXTRA[@]}"
fi

# ---- inside the namespace: the run's files go to RUN, moved into OUT when it ended well
# A run's folder is named by its script's pid: one whose script is dead (killed, SIGKILL or a machine that
# stopped, where no trap runs) is the next run's to remove (pass 76: they stayed, hundreds of MB each).
for stale in "$OUT"/.run.*.*; do
  pid=${stale#"$OUT"/.run.} pid=${pid%%.*}
  case "$pid" in '' | *[!0-9]*) continue ;; esac
  [ -d "$stale" ] && [ ! -L "$stale" ] && [ ! -d "/proc/$pid" ] || continue  # (kill -0 fails for another user's)
  rm -rf -- "$stale"
done
RUN="$(mktemp -d "$OUT/.run.$$.XXXXXX")" ||
  { echo "run_hil_bench.sh: --out $OUT: cannot write in it (the system's reason above); nothing run" >&2
    [ "${GIMBALSIM_BENCH_MADE_OUT:-0}" != 1 ] || rmdir "$OUT" 2>/dev/null || true
    exit 4; }
cd "$RUN"
ended_well=0
cleanup() {
  stop_children  # firmware_sim, the controller, the recorder: ended, their outputs whole, before RUN goes
  rm -rf "$RUN"
  [ "$ended_well" = 1 ] || [ "${GIMBALSIM_BENCH_MADE_OUT:-0}" != 1 ] || rmdir "$OUT" 2>/dev/null || true
}
trap cleanup EXIT
failed() {  # failed MESSAGE CODE: the run's own logs on stderr, OUT as it was
  for f in firmware.txt controller.txt; do [ ! -s "$f" ] || { echo "--- $f"; cat "$f" 2>/dev/null || true; } >&2; done
  echo "run_hil_bench.sh: $1; nothing in $OUT was changed" >&2
  exit "$2"
}
if [ "$LOG" = 1 ]; then
  # gimbalsim_record, not lcm-logger: LCM 1.3.1's lcm-logger drops messages
  # in fast lockstep on a loaded machine (30-message queue); same log format.
  "$BIN/gimbalsim_record" --lcm-url "$URL" bench.lcmlog &
  LOGGER=$!
  sleep 0.3
fi
# The same --duration as the plant: both end by themselves (docs/bench.md "Two terminals").
"$BIN/pointing_controller" "$CONFIG" --set control.period="$PERIOD" --lcm-url "$URL" --duration "$DURATION" --idle-exit 10 \
    --log-csv controller.csv 2>controller.txt &
CTL=$!
sleep 0.2
fw=("$BIN/firmware_sim" "$SCENE" --rate "$RATE" --duration "$DURATION" --profile "$CONFIG" --truth-csv truth.csv
    --lcm-url "$URL")
[ "$MODE" = lockstep ] && fw+=(--lockstep)
set +e
"${fw[@]}" "${EXTRA[@]}" 2>&1 | console_tee firmware.txt
rc=${PIPESTATUS[0]}
set -e
# A plant that failed ends the run now: the controller would wait its --idle-exit for a status that never comes.
[ "$rc" -eq 0 ] || kill "$CTL" 2>/dev/null || true
ctl_rc=0
wait "$CTL" 2>/dev/null || ctl_rc=$?
if [ "$LOG" = 1 ]; then
  # The recorder may have ended already (its log could not be written: exit 4); its own code ends the run.
  sleep 0.2; kill -INT "$LOGGER" 2>/dev/null || true
  log_rc=0; wait "$LOGGER" 2>/dev/null || log_rc=$?
  [ "$log_rc" -eq 0 ] || [ "$log_rc" -eq 130 ] || failed "gimbalsim_record exited with $log_rc" "$log_rc"
  log_rc=0; "$BIN/gimbalsim_log2csv" bench.lcmlog --out-dir "$RUN" || log_rc=$?
  [ "$log_rc" -eq 0 ] || failed "gimbalsim_log2csv exited with $log_rc" "$log_rc"
fi
# A plant that stopped (exit 3) wrote its truth up to the stop: kept, as every script keeps such a run
# (usage.md "Scripts in tools/"); the controller it left waiting was stopped by us (SIGTERM: 143, its log whole)
# or saw the stop in its statuses (3).
[ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || failed "firmware_sim exited with $rc" "$rc"
[ "$ctl_rc" -eq 0 ] || { [ "$rc" -eq 3 ] && { [ "$ctl_rc" -eq 143 ] || [ "$ctl_rc" -eq 3 ]; }; } ||
  failed "pointing_controller exited with $ctl_rc" "$ctl_rc"
if [ "$PLOT" = 1 ]; then
  /usr/bin/python3 "$ROOT/tools/hil/plot_bench.py" truth.csv --out bench.png \
      --title "$(basename "$SCENE") $MODE, $RATE Hz, $DURATION s" || failed "the plot could not be made" 4
fi
# The previous run's files go (a bench.png or bench_*.csv this run did not make would mislead), then this one's come.
(cd "$OUT" && rm -f "${OUTPUTS[@]}" bench_*.csv)
shopt -s nullglob
for f in *; do mv -f -- "$f" "$OUT/$f"; done
ended_well=1
[ "$rc" -eq 0 ] || echo "run_hil_bench.sh: the plant stopped (firmware_sim exit 3, its message above): the" \
  "outputs hold the run up to the stop" >&2
echo "run_hil_bench.sh: results in $OUT (truth.csv, controller.csv, firmware.txt$([ "$LOG" = 1 ] && echo ", bench.lcmlog, bench_*.csv")$([ "$PLOT" = 1 ] && echo ", bench.png"))"
exit "$rc"
