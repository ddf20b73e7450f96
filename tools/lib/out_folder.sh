# Sourced by the scripts of tools/: out_folder SCRIPT DIR makes the script's
# own output folder (out/<tool>/), or refuses (exit 2, nothing run) when a
# file is in its way, as a program refuses an output it cannot write; mkdir's
# bare "Not a directory" was exit 1, which usage.md calls a bug.
# out_folder_undo RC, from the script's EXIT trap, removes again (if empty) the
# folders out_folder made when the run ended refused: a refused run costs nothing.
OUT_FOLDER_MADE=()  # the folders out_folder made, innermost first

out_folder() {
  local script="$1" dir="$2" p="$2"
  while [ "$p" != "." ] && [ "$p" != "/" ]; do
    if { [ -e "$p" ] || [ -L "$p" ]; } && [ ! -d "$p" ]; then
      echo "$script: $p is not a folder (a file, or a link to nothing, where $dir goes): move it away; nothing run" >&2
      exit 2
    fi
    [ -d "$p" ] || OUT_FOLDER_MADE+=("$p")
    p=$(dirname "$p")
  done
  mkdir -p "$dir"
}

# Exit 0 and 3 (a plant stopped) wrote their outputs into the folders; any other code keeps none of them.
out_folder_undo() {
  [ "$1" -eq 0 ] || [ "$1" -eq 3 ] || rmdir ${OUT_FOLDER_MADE[@]+"${OUT_FOLDER_MADE[@]}"} 2>/dev/null || true
}
