# Sourced by the scripts in tools/ first thing: a console whose reader is gone (`2>&1 | head -1`) stops no
# script, as it stops no program (docs/usage.md "Exit codes"). SIGPIPE is ignored here and so in every
# program the script runs (the C++ programs and Python ignore it too); the script's own lines that cannot
# be written are dropped; `tee -p` (console_tee) keeps writing the log when its console goes.
trap '' PIPE
# A descriptor closed at start (`>&-`) gets /dev/null, as in the programs: else a tool reading
# /dev/stdout fails (awk) and the first file a child opens takes it.
[ -L /proc/self/fd/0 ] || exec 0</dev/null
[ -L /proc/self/fd/1 ] || exec 1>/dev/null
[ -L /proc/self/fd/2 ] || exec 2>/dev/null
echo() { builtin echo "$@" 2>/dev/null || true; }
printf() { builtin printf "$@" 2>/dev/null || true; }
# tee writes the log; the console gets its copy through a pipe whose reader drops what it cannot write (a
# full device, a closed descriptor), so tee's status speaks for the log alone and a run's code stays its own.
console_tee() { tee -p "$@" | { cat 2>/dev/null || true; }; }
# The script's header comment (lines $2-$3 of file $1) as its usage (--help), dropped if nobody reads it.
script_usage() { { sed -n "$2,$3p" "$1" | sed 's/^# \{0,1\}//'; } 2>/dev/null || true; }
# A script's --version answer: "<script> <version>", the top CMakeLists.txt's project() VERSION, as the programs
# print theirs (docs/usage.md "Exit codes"; pass 44: the wrappers refused --version).
script_version() {
  local top
  top="$(dirname "${BASH_SOURCE[0]}")/../../CMakeLists.txt"
  echo "$1 $(sed -n 's/^project(gimbalsim VERSION \([0-9.]*\).*/\1/p' "$top")"
}
