# Sourced by the scripts of tools/: out_folder SCRIPT DIR makes the script's
# own output folder (out/<tool>/), or refuses (exit 2, nothing run) when a
# file is in its way, as a program refuses an output it cannot write; mkdir's
# bare "Not a directory" was exit 1, which usage.md calls a bug.
# out_folder_undo, from the script's EXIT trap, removes again the folders
# out_folder made that are still empty: a refused run costs nothing.
OUT_FOLDER_MADE=()  # the folders out_folder made, innermost first

out_folder() {
  local script="$1" dir="$2" p="$2"
  # The folder itself as a link: every output would be written through it, elsewhere (pass 71), as a program
  # refuses an --out that is a link.
  if [ -L "$dir" ]; then
    echo "$script: $dir is a symbolic link; not written through: name the folder itself; nothing run" >&2
    exit 2
  fi
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

# A folder holding a run's outputs is not empty, and rmdir leaves it (pass 39: run_stress.sh left out/stress).
out_folder_undo() {
  local d
  for d in ${OUT_FOLDER_MADE[@]+"${OUT_FOLDER_MADE[@]}"}; do rmdir "$d" 2>/dev/null || true; done
}
