# Sourced by the scripts of tools/: build_dir SCRIPT [reads] sets BUILD, the
# build folder the script takes its programs and Python package from. The one
# way to name another one is GIMBALSIM_BUILD=DIR: read where the user stands
# (as every path they give, so call it before the script's cd) and, for a
# script that builds, already configured: a script configures only its own
# build/ (a missing name was configured inside the checkout, pass 80). A
# script that only reads a named build ("reads") checks what it reads itself.
# Unset: the checkout's build/; set but empty: refused (exit 2), as an empty flag value is.
build_dir() {
  local script="$1" mode="${2:-builds}"
  if [ "${GIMBALSIM_BUILD+set}" = set ] && [ -z "$GIMBALSIM_BUILD" ]; then  # a name left out is no folder
    echo "$script: GIMBALSIM_BUILD=: an empty value; name a build folder, or unset it for $ROOT/build;" \
      "nothing run" >&2
    exit 2
  fi
  if [ -z "${GIMBALSIM_BUILD:-}" ]; then
    BUILD=$ROOT/build
    return
  fi
  BUILD=$(realpath -ms -- "$GIMBALSIM_BUILD")  # the name as given, made absolute, links kept
  if [ "$mode" = builds ] && [ ! -f "$BUILD/CMakeCache.txt" ]; then
    echo "$script: GIMBALSIM_BUILD=$GIMBALSIM_BUILD: $BUILD is not a configured build (no CMakeCache.txt);" \
      "configure it (cmake -S $ROOT -B $BUILD) or leave GIMBALSIM_BUILD unset for $ROOT/build; nothing run" >&2
    exit 2
  fi
}
