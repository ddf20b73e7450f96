# Sourced by the scripts of tools/ that run programs: stop_children, first thing in the script's EXIT trap. A
# signal to the script alone ended it while its program ran on, orphaned, writing into the outputs the script
# then cleaned up (pass 72). Every program the script started that still runs gets SIGTERM and is waited for
# (up to 30 s), so its outputs are whole, or its journal kept, before the script's own cleanup. The children
# are read from /proc (procps may be absent on a fresh machine).
children_of() {
  local f k v
  for f in /proc/[0-9]*/status; do
    while IFS=$'\t' read -r k v; do
      if [ "$k" = "PPid:" ]; then
        f=${f#/proc/}
        # (a $(children_of $$) runs in a subshell, itself a child: not counted)
        [ "$v" != "$1" ] || [ "${f%/status}" = "$BASHPID" ] || echo "${f%/status}"
        break
      fi
    done 2>/dev/null < "$f" || true
  done
}

stop_children() {
  local pids i
  pids=$(children_of $$)
  [ -n "$pids" ] || return 0
  kill -TERM $pids 2>/dev/null || true
  for i in $(seq 600); do
    [ -n "$(children_of $$)" ] || return 0
    sleep 0.05
  done
}
