"""save_output.py [--check] SOURCE DEST [-- ARG...]: a script's console log (tee'd
into a temporary SOURCE, outside every output folder) written to DEST by the
one writer's rules (output_file.py): never through a link, never over an
input, whole or not at all (a temporary and a rename: a hard link to DEST
keeps its content). The ARGs are the script's own arguments: each that names
a file (itself, after '=' in --flag=path, an item of a comma list, or glued
to a short option or a cluster of them, -fpath) is one of the run's inputs, so
a log named as a scene or a configuration is refused (exit 2), never
written over it. --check runs the same checks and writes nothing: a script
runs it before its program, so a log that would be refused costs no run and
no output. `| tee "$OUT/x.log"` opened the name before the program had
checked anything: a refused run emptied a previous log, a link's target or
a hard-linked scene."""
import argparse
import io
import os
import pathlib
import re
import stat
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import output_file  # noqa: E402  (the tools' writer, by path)


def _paths_in(arg):
    """What in one argument may name a file: itself, the value after '=' and each item of a comma list in it
    (--scenes=a.yaml,x.yaml, key=path), and a path glued to a short option or a cluster of them (-sx.yaml,
    -vsx.yaml: passes 102, 104)."""
    value = arg.partition("=")[2]
    glued = [arg[k:] for k in range(2, len(arg)) if re.fullmatch(r"-[A-Za-z]+", arg[:k])] if arg[:1] == "-" else []
    return [arg, value, *value.split(","), *arg.split(","), *glued]


def main():
    ap = argparse.ArgumentParser(allow_abbrev=False, description=__doc__.split("\n\n")[0])
    output_file.standard_flags(ap)
    ap.add_argument("source", help="the temporary log to copy")
    ap.add_argument("dest", help="the log's name in the output folder")
    ap.add_argument("--check", action="store_true",
                    help="only check DEST (before the program runs: a refused log costs no run); SOURCE unread")
    ap.add_argument("--as", dest="caller", default="save_output.py", metavar="SCRIPT",
                    help="the script whose log this is: its name heads every refusal (the user ran it, not this)")
    ap.add_argument("args", nargs="*", help="the script's arguments, after --: each naming a file is an input")
    a = ap.parse_args()
    inputs = [p for arg in a.args for p in _paths_in(arg) if p and os.path.isfile(p)]

    def save():
        # (passes 116, 118) the log itself is an input too, --check alike: DEST naming SOURCE was renamed over it
        source = [a.source] if a.source and os.path.isfile(a.source) else []
        output_file.check_before_writing([a.dest], inputs + source, ["DEST"])
        if a.check:
            return 0
        # (pass 90) a FIFO blocked, /dev/zero was read until memory ran out, "" was read as a folder
        if not a.source:
            raise output_file.Refused("SOURCE: an empty path; name the log to copy")
        try:
            source = open(a.source, "rb", opener=lambda p, f: os.open(p, f | os.O_NONBLOCK))
        except OSError as e:
            raise output_file.Refused(f"{a.source}: cannot read the log: {e.strerror}") from None
        with source, io.TextIOWrapper(source, encoding="utf-8", errors="replace") as text:
            if not stat.S_ISREG(os.fstat(source.fileno()).st_mode):
                raise output_file.Refused(f"{a.source}: not a regular file: a log is one")
            with output_file.open_output(a.dest, "w", inputs) as out:  # (pass 92) a chunk at a time, not whole
                for chunk in iter(lambda: text.read(1 << 20), ""):
                    out.write(chunk)
    return output_file.run_script(a.caller, save)


if __name__ == "__main__":
    sys.exit(main())
