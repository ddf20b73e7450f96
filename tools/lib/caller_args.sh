# Sourced by the scripts in tools/ that cd to the repository (usage.md "Scripts in tools/": run from
# anywhere): a relative path the user gives is theirs, not the repository's. Set CALLER=$PWD before the cd.

# An argument (itself, or after '=' in --flag=path) that names a path relative to CALLER, made absolute:
# one that exists there, or that looks like a path (a '/' in it, or a file's extension), so a name missing
# where the user stands is never read from the repository instead. Anything else (a flag, an absolute
# path, a number, a key=value, a scene's name) as given: a number stays one even where a file of that name
# exists (--threads 1 beside a file "1"; write ./1 for the file).
_caller_path() {
  [ "${1#/}" = "$1" ] || return 1  # absolute
  [[ "$1" =~ ^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$ ]] && return 1  # a number
  [ -e "$CALLER/$1" ] && return 0
  case "$1" in
    *=*) return 1 ;;  # a key=value
    */* | *.yaml | *.yml | *.csv | *.json | *.md | *.png | *.svg | *.pdf | *.txt | *.log) return 0 ;;
  esac
  return 1
}
abs_arg() {
  local a=$1
  case "$a" in
    --*=*) local v=${a#*=}; ! _caller_path "$v" || a="${a%%=*}=$CALLER/$v" ;;
    -*) ;;
    *) ! _caller_path "$a" || a="$CALLER/$a" ;;
  esac
  printf '%s' "$a"
}
