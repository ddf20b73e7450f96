# Sourced by the scripts in tools/ that cd to the repository (usage.md "Scripts in tools/": run from
# anywhere): a relative path the user gives is theirs, not the repository's. Set CALLER=$PWD before the cd.

# An argument naming an existing path relative to CALLER (itself, or after '=' in --flag=path), made
# absolute; anything else (a flag, an absolute path, a value naming no file) as given.
abs_arg() {
  local a=$1
  case "$a" in
    --*=*) local v=${a#*=}; [ "${v#/}" != "$v" ] || [ ! -e "$CALLER/$v" ] || a="${a%%=*}=$CALLER/$v" ;;
    -*|/*) ;;
    *) [ ! -e "$CALLER/$a" ] || a="$CALLER/$a" ;;
  esac
  printf '%s' "$a"
}
