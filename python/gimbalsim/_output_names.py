"""Where a tool's outputs go: a folder holding another tool's outputs is refused,
and so is a link or the wrong kind of file under any name a run will write,
before anything runs (docs/usage.md "Output files")."""
import os
import stat

from ._output import OutputRefused, _kind, _text


# The names that show a folder holds a tool's outputs: a tool writing into another's folder would mix their files.
TOOL_FILES = {"sweep": ("a sweep", ("results.csv", "results.partial.csv", "design.json")),
              "study": ("a tuning study", ("study.db", "trials.csv")),
              "allocation": ("an allocation", ("allocation_spec.json", "allocation.json", "values"))}


def check_output_names(out, tool, files=(), folders=(), refuse=OutputRefused):
    """Refuses (raises refuse naming the path), before anything runs, as found
    at the end the run's work would be lost: a folder out holding another
    tool's outputs (TOOL_FILES; tool: this run's key there), and under any
    of the run's output names an existing symbolic link or anything but its
    kind (files: regular files; folders, listed outer first: folders)."""
    out = _text(out)
    for other, (what, names) in TOOL_FILES.items():
        held = [n for n in names if os.path.lexists(os.path.join(out, n))]
        if other != tool and held:
            raise refuse(f"{out} holds {what} ({', '.join(held)}): give the {tool} another --out")
    for path, folder in [(_text(p), True) for p in folders] + [(_text(p), False) for p in files]:
        try:
            st = os.lstat(path)
        except (FileNotFoundError, NotADirectoryError):  # made when written (a file on the way: its folder's refusal)
            continue
        want = "a folder" if folder else "a file"
        if stat.S_ISLNK(st.st_mode):
            raise refuse(f"{path}: a symbolic link where this run writes {want} of its outputs; never written "
                         "through one: remove it, or use another --out")
        if not (stat.S_ISDIR(st.st_mode) if folder else stat.S_ISREG(st.st_mode)):
            raise refuse(f"{path}: not {'a folder' if folder else 'a regular file'} ({_kind(st.st_mode)}) where this "
                         f"run writes {want} of its outputs: remove it, or use another --out")
