"""How the Python tools write a file: the package's one writer,
python/gimbalsim/_output.py (the rules of the C++ io::OutputFile,
base/io/include/gimbalsim/io/output_file.hpp), loaded from the source
tree by its path, so a plotting script needs neither the built extension
nor PYTHONPATH. Everything it offers is re-exported here: open_output,
write_text, write_bytes, write_csv, savefig, check_outputs, OutputError
(an OSError naming the file), and csv_number (the CSV convention's numbers).
It also says how a script ends (run_script, Refused, check_before_writing)
and how it reads what it is given (plain_number, underflowed, check_header,
check_as_written, check_figure_format, read_input)."""
import argparse
import contextlib
import errno
import fcntl
import importlib.util
import os
import pathlib
import re
import signal
import stat
import sys


def _standalone(name, file):
    """python/gimbalsim/<file> loaded by path as `name`: not gimbalsim.<module>, whose import would load the
    package and its extension."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, pathlib.Path(__file__).resolve().parents[2] / "python" /
                                                      "gimbalsim" / file)
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]


_cells = _standalone("gimbalsim_csv_cells", "_csv_cells.py")  # the CSV convention's cells, which the writer reads
_writer = _standalone("gimbalsim_output_writer", "_output.py")
_console = _standalone("gimbalsim_console", "_console.py")
_number = _standalone("gimbalsim_number", "_number.py")  # the one reading of a number given as text
_signals = _standalone("gimbalsim_early_signals", "_early_signals.py")  # STOP_SIGNALS
_flags = _standalone("gimbalsim_flags", "_flags.py")  # a flag of one value: once, never empty
_console.keep_console()  # imported by a script: a reader gone stops nothing, its --help included

OutputError = _writer.OutputError
check_outputs = _writer.check_outputs
csv_number = _cells.csv_number
underflowed = _number.underflowed
flag_decimal = _number.flag_decimal  # (x, None) or (None, why), as the programs read a real flag
plain_decimal = _number.plain_decimal
plain_whole = _number.plain_whole
has_leading_zero = _number.has_leading_zero
DECIMAL_PATTERN = _number.DECIMAL_PATTERN  # a plain decimal, as a regular expression's text

open_output = _writer.open_output
write_text = _writer.write_text
write_bytes = _writer.write_bytes
write_csv = _writer.write_csv
savefig = _writer.savefig
program_on_path = _writer.program_on_path  # the rule, for the shell scripts' own outputs (run_hil_bench.sh)

# ---- how a script of tools/ ends: the exit-code table of docs/usage.md ----

EXIT_REFUSED, EXIT_OUTPUT = 2, 4


class Refused(Exception):
    """Bad arguments or a bad input file: the script names it and exits 2
    before it writes anything."""


def _not_empty(path, name=None):
    """An empty output path is refused as such first (usage.md "Output files"): a
    later check would blame what it made of it ('.' as a format, the folder '')."""
    if path == "" or (isinstance(path, bytes) and not path):
        raise Refused(f"{name or 'an output path'}: an empty value")


def check_before_writing(outputs, inputs=(), names=()):
    """check_outputs as a refusal (exit 2): a script checks every output it
    will write, and the folder each goes in, before it reads or plots. names:
    the flags the outputs came from, in order, to name an empty one (None, an
    output not asked for, is skipped)."""
    outputs, names = list(outputs), list(names)  # a generator is read twice here
    for k, out in enumerate(outputs):
        _not_empty(out, names[k] if k < len(names) else None)
    try:
        check_outputs(outputs, inputs)
    except OutputError as e:
        raise Refused(str(e)) from None


class _Stopped(Exception):
    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def _stop(signum, frame):
    raise _Stopped(signum)  # unwinds through the writers, which remove their temporaries


def run_script(program, main, whole_set=False):
    """main()'s exit code (None counts as 0); Refused is one line on stderr and
    exit 2, OutputError (a write that failed, nothing left under its name)
    one line and exit 4, SIGINT, SIGTERM or SIGHUP one line and 128 + the signal.
    whole_set: the outputs are one set (a page's figures): written together at
    the end, so a failure or a stop leaves every name as it was. Anything
    else is a bug: a traceback and exit 1. A console whose reader is gone
    drops its lines (_console.ReaderGoneStream)."""
    for signum in _signals.STOP_SIGNALS:
        signal.signal(signum, _stop)
    _console.keep_console()  # (as at import: a test may have put its own streams since)
    code, outputs = None, None
    try:
        with _writer.output_set() if whole_set else contextlib.nullcontext() as outputs:
            return main() or 0
    except Refused as e:
        print(f"{program}: error: {e}", file=sys.stderr)
        code = EXIT_REFUSED
    except OutputError as e:
        print(f"{program}: error: {e}", file=sys.stderr)
        code = EXIT_OUTPUT
    except _Stopped as e:
        # a signal held back while the set was renamed into place lands after it: the set is kept then
        committed = outputs is not None and outputs.committed
        kept = ("; the outputs were all written" if committed else "; nothing kept") if whole_set else ""
        print(f"{program}: interrupted ({e}){kept}", file=sys.stderr)
        code = 128 + e.signum
    return code


def plain_number(text, where):
    """A CSV cell as the project writes numbers: a plain finite decimal (not
    ' 1', 'inf' or '0x10'); Refused naming `where` (file:line: column) otherwise."""
    x = _number.plain_decimal(text)
    if x is None:
        raise Refused(f"{where}: not a finite decimal number: {text!r}")
    return x


class _Version(argparse.Action):
    """--version, read when asked: a script copied without the repository still parses its arguments."""
    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0, help="print the script's name and version and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        try:
            text = (pathlib.Path(__file__).resolve().parents[2] / "CMakeLists.txt").read_text()
        except OSError:
            text = ""
        found = re.search(r"project\(gimbalsim VERSION ([0-9][0-9.]*)", text)
        print(f"{parser.prog} {found.group(1) if found else 'unknown'}")  # on stdout, as argparse's own
        parser.exit(0)


def standard_flags(parser):
    """What every script's parser keeps, called first: --version ("<script> <version>" on stdout and exit 0,
    as every program and module answers: docs/usage.md "Exit codes"; pass 44: the tools/ scripts refused it),
    the version the top CMakeLists.txt's project() VERSION; and a flag of one value given once, never empty
    (python/gimbalsim/_flags.py, as the package's programs)."""
    _flags.one_value_each(parser)
    parser.add_argument("--version", action=_Version)


def default_build():
    """The build folder a script uses when not told: GIMBALSIM_BUILD, read where the user stands, as the shell
    scripts read it (tools/lib/build_dir.sh; pass 83: the Python scripts ignored it), else the checkout's build/."""
    named = os.environ.get("GIMBALSIM_BUILD")
    if named == "":  # set but empty: refused as the shell scripts refuse it, an empty flag value alike
        print(f"{os.path.basename(sys.argv[0])}: error: GIMBALSIM_BUILD=: an empty value; name a build folder, "
              "or unset it for the checkout's build/; nothing run", file=sys.stderr)
        sys.exit(2)
    return os.path.abspath(named) if named else str(pathlib.Path(__file__).resolve().parents[2] / "build")


def add_build(parser, holding="bin/"):
    """--build DIR: the build folder the script takes its programs (or package) from, as an absolute path.
    A relative DIR is read where the user stands, as every path a script is given (docs/usage.md "Scripts in
    tools/"; pass 66: it was read against the source tree); absent, default_build()."""
    def folder(text):  # (pass 119) --build= was read as the current folder, and its programs run
        if not text:
            raise argparse.ArgumentTypeError("an empty value: name the build folder")
        return os.path.abspath(text)
    parser.add_argument("--build", type=folder, default=default_build(),
                        help=f"build directory holding {holding} (default: GIMBALSIM_BUILD, else the checkout's "
                             "build/; a relative one is read where you stand)")


def import_package(build):
    """The gimbalsim package of the build folder, imported (a script that uses it takes it from --build, never
    from whatever PYTHONPATH holds); Refused naming the command that builds it when it is not there."""
    python = pathlib.Path(build) / "python"
    if not (python / "gimbalsim" / "__init__.py").is_file():
        raise Refused(f"no gimbalsim package in {python}: cmake --build {build} -j2 --target gimbalsim_python")
    sys.path.insert(0, str(python))
    os.environ["PYTHONPATH"] = os.pathsep.join(filter(None, [str(python), os.environ.get("PYTHONPATH", "")]))
    try:
        return importlib.import_module("gimbalsim")
    except ImportError as e:  # its Python files without the extension: the package says what to build
        raise Refused(str(e)) from None


def arg_whole(lo, hi):
    """An argparse type: a whole number in [lo, hi] written as one (no space,
    '_' or exponent), as the programs read their integer flags."""
    def read(text):
        n = _number.plain_whole(text)
        if n is None or not lo <= n <= hi:
            raise argparse.ArgumentTypeError(f"must be a whole number in [{lo}, {hi}], got {text!r}")
        return n
    return read


def arg_list(one):
    """An argparse type: a comma-separated list, each item as the type `one` reads it; an empty item
    ('1000,,2000') is refused, not dropped, and so is an item given twice."""
    def read(text):
        if "" in text.split(","):
            raise argparse.ArgumentTypeError(f"an empty item in {text!r} (two commas in a row, or one at an end?)")
        values = [one(item) for item in text.split(",")]
        twice = next((v for i, v in enumerate(values) if v in values[:i]), None)
        if twice is not None:  # (pass 88) --rates 1000,1000 ran the rate twice, as no program takes a list
            raise argparse.ArgumentTypeError(f"{twice!r} given twice in {text!r}")
        return values
    return read


def arg_whole_list(lo, hi):
    """An argparse type: a comma-separated list of whole numbers, each as arg_whole(lo, hi) reads it (arg_list)."""
    return arg_list(arg_whole(lo, hi))


def arg_cpu(text):
    """An argparse type: -1 (no pinning) or a CPU this process may run on, as firmware_sim --cpu reads it (pass 88:
    --cpu 99 on a 2-core machine ran until a program refused it, exit 1 or 0)."""
    n = _number.plain_whole(text)
    allowed = sorted(os.sched_getaffinity(0))
    if n is None or (n != -1 and n not in allowed):
        raise argparse.ArgumentTypeError(f"must be -1 (no pinning) or a CPU this process may run on "
                                         f"({', '.join(map(str, allowed))}), got {text!r}")
    return n


def arg_decimal(lo, hi):
    """An argparse type: a plain finite decimal in [lo, hi], as the programs
    read their real flags (' 1', 'inf', '0x1' refused, and '1e-400', which
    would read as 0)."""
    def read(text):
        x, why = _number.flag_decimal(text)
        if why:
            raise argparse.ArgumentTypeError(why)
        if not lo <= x <= hi:
            raise argparse.ArgumentTypeError(f"must be in [{lo:g}, {hi:g}], got {text}")
        return x
    return read


@contextlib.contextmanager
def one_at_a_time(lock, what):
    """Holds an exclusive lock on the file `lock` (made, and removed at the
    end) for the block; Refused naming `what` when another process holds it."""
    try:  # never through a link: a run writes no file outside its own names (pass 34: it made the link's target)
        fd = os.open(lock, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW | os.O_NONBLOCK, 0o644)
    except OSError as e:
        raise Refused(f"{lock}: {'a symbolic link' if e.errno == errno.ELOOP else e.strerror}; the lock of {what} "
                      "is never made through one: remove it") from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):  # (pass 35) a pipe was taken as the lock, and removed at the end
        os.close(fd)
        raise Refused(f"{lock}: not a regular file (a pipe, a device); the lock of {what} is a file the run makes: "
                      "remove it")
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        # the lock held must still be the file under the name: one its holder removed while this run opened it
        # would be a lock nobody else sees
        if not os.path.samestat(os.fstat(fd), os.stat(lock)):
            raise BlockingIOError
    except (BlockingIOError, FileNotFoundError):
        os.close(fd)
        raise Refused(f"{what}: another run is writing it; wait for it to end, or give another") from None
    try:
        yield
    finally:
        pathlib.Path(lock).unlink(missing_ok=True)
        os.close(fd)


def read_input(path, what, limit=1 << 24, stdin=False, binary=False):
    """The UTF-8 text of the input file path (`what`: the flag that named it; stdin: '-' is the standard input,
    under the same rules). Refused (exit 2) naming it when it is missing or unreadable, no regular file (a FIFO
    would block, /dev/zero never end: pass 45), over `limit` bytes, or not UTF-8. A link to a regular file is read:
    an input is never written."""
    _not_empty(path, what)
    if stdin and path == "-":
        raw = sys.stdin.buffer.read(limit + 1)
        if len(raw) > limit:
            raise Refused(f"{what} -: more than the {limit} bytes this input may hold")
        try:
            return raw.decode("utf-8")
        except UnicodeDecodeError as e:
            raise Refused(f"{what} -: not UTF-8 text (byte {e.start})") from None
    try:
        with _open_input(path, what, limit) as f:
            raw = f.read(limit + 1)
        return raw if binary else raw.decode("utf-8")
    except OSError as e:
        raise Refused(f"{what} {path}: cannot be read ({e.strerror or e})") from None
    except UnicodeDecodeError as e:
        raise Refused(f"{what} {path}: not UTF-8 text (byte {e.start})") from None


def count_lines(path, what, limit):
    """The number of line ends in the input file path, read by read_input's rules a MiB at a time (a per-tick
    CSV counted, not held)."""
    _not_empty(path, what)
    try:
        with _open_input(path, what, limit) as f:
            return sum(chunk.count(b"\n") for chunk in iter(lambda: f.read(1 << 20), b""))
    except OSError as e:
        raise Refused(f"{what} {path}: cannot be read ({e.strerror or e})") from None


def _open_input(path, what, limit):
    """path opened for reading in binary, refused when it is no regular file or is over limit bytes."""
    st = os.stat(path)
    if not stat.S_ISREG(st.st_mode):
        raise Refused(f"{what} {path}: not a regular file ({_writer._kind(st.st_mode)}); give a file")
    if st.st_size > limit:
        raise Refused(f"{what} {path}: {st.st_size} bytes, more than the {limit} this input may hold")
    return open(path, "rb")


def check_header(header, path):
    """A CSV header names each column once (which of two would a plot take?)."""
    seen = set()
    for name in header:
        if name in seen:
            raise Refused(f"{path}:1: column {name} appears twice")
        seen.add(name)


def check_as_written(raw, path, not_as_written):
    """A CSV's bytes as the project writes them (no byte-order mark, LF line ends, the last one too):
    Refused naming the line and `not_as_written` ("not as X writes ..."), since a
    mark would hide the first column's name and a CR would end every last cell."""
    if raw.startswith(b"\xef\xbb\xbf"):
        raise Refused(f"{path}:1: starts with a byte-order mark: {not_as_written}")
    cr = raw.find(b"\r")
    if cr >= 0:
        line = raw.count(b"\n", 0, cr) + 1
        what = "ends in CR (CRLF line ends)" if raw[cr + 1:cr + 2] in (b"\n", b"") else "has a carriage return (CR)"
        raise Refused(f"{path}:{line}: {what}: {not_as_written}")
    if raw and not raw.endswith(b"\n"):  # a file cut while written: its last number may be cut too (pass 69)
        line = raw.count(b"\n") + 1
        raise Refused(f"{path}:{line}: the last line has no line end (a file cut while written?): {not_as_written}")


def check_figure_format(path):
    """The extension of a figure's name is a format matplotlib writes (.png, .pdf, .svg, ...)."""
    _not_empty(path)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    fmt = os.path.splitext(str(path))[1].lstrip(".").lower()
    supported = FigureCanvasAgg(Figure()).get_supported_filetypes()
    if fmt not in supported:
        raise Refused(f"{path}: '.{fmt}' is not a figure format (one of {', '.join('.' + f for f in sorted(supported))})")


if __name__ == "__main__":  # (pass 79) run alone it took any arguments, did nothing and exited 0
    print("output_file.py: error: a module of the tools' Python scripts, not a program: "
          "run the script that writes the file", file=sys.stderr)
    sys.exit(2)
