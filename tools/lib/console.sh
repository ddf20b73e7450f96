# Sourced by the scripts in tools/ first thing: a console whose reader is gone (`2>&1 | head -1`) stops no
# script, as it stops no program (docs/usage.md "Exit codes"). SIGPIPE is ignored here and so in every
# program the script runs (the C++ programs and Python ignore it too); the script's own lines that cannot
# be written are dropped; `tee -p` (console_tee) keeps writing the log when its console goes.
trap '' PIPE
echo() { builtin echo "$@" 2>/dev/null || true; }
printf() { builtin printf "$@" 2>/dev/null || true; }
console_tee() { tee -p "$@"; }
# The script's header comment (lines $2-$3 of file $1) as its usage (--help), dropped if nobody reads it.
script_usage() { { sed -n "$2,$3p" "$1" | sed 's/^# \{0,1\}//'; } 2>/dev/null || true; }
