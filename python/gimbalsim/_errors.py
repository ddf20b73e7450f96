"""The package's exceptions (SceneError and SimulationStopped are raised by
the C++ core with their fields set) and the one mapping of an exception to
the exit code of the project's exit-code table (docs/usage.md "Exit codes",
the C++ programs' enum Exit in base/program/include/gimbalsim/program/
program.hpp), which the mains of gimbalsim.sweep, gimbalsim.tune and the
sweep's --replay run through (guarded_main)."""
import signal
import sys

from ._console import console_stream
from ._early_signals import STOP_SIGNALS
from ._output import OutputError

# The exit-code table, the same numbers as program.hpp's enum Exit (a test compares them).
EXIT_OK = 0
EXIT_INTERNAL = 1        # a bug, memory exhausted: an exception no row below names (Python's traceback)
EXIT_REFUSED = 2         # a spec, scene, configuration or argument refused: nothing run
EXIT_STOPPED = 3         # the run stopped (numerical trouble; a tuning study with no trial completed)
EXIT_OUTPUT = 4          # an output could not be written; nothing under its name
EXIT_NO_PEER = 6         # no peer: the scheduler named by --scheduler did not answer, or no worker joined it
EXIT_NOT_REPRODUCED = 8  # a replayed sample did not reproduce its recorded row (the columns named)


def signal_exit(signum):
    """Stopped by signal N: 128 + N (130 SIGINT, 143 SIGTERM, 129 SIGHUP)."""
    return 128 + signum


class SceneError(ValueError):
    """A scene (or controller configuration) was refused.

    ``problems`` lists every problem found, each a dict with ``text`` (the
    message as the command line prints it), ``key``, ``file``, ``line``,
    ``column`` (1-based; None when not a file position) and ``set_index``
    (1-based index among the overrides; None when not an override); a problem
    with an override also has ``source``, the label its text starts with
    (``overrides['key']``, or ``spec.yaml:LINE`` from a spec, which then fills
    ``file`` and ``line``).
    ``key``, ``file``, ``line`` and ``column`` are the first problem's.
    """

    def __init__(self, message, problems=()):
        super().__init__(message)
        self.problems = list(problems)
        first = self.problems[0] if self.problems else {}
        self.key = first.get("key")
        self.file = first.get("file")
        self.line = first.get("line")
        self.column = first.get("column")
        self.set_index = first.get("set_index")

    @property
    def keys(self):
        """Every key named by a problem, in order."""
        return [p["key"] for p in self.problems if p.get("key")]


class SimulationStopped(RuntimeError):
    """A step hit numerical trouble. ``key`` is the scene key of the limit
    (e.g. ``sim.max_substeps``; "" when no setting names it), ``status`` the
    step status in words, ``time`` [s] where it stopped. Simulator.run adds
    ``steps_done`` and ``outputs`` (the good rows)."""

    def __init__(self, message, key="", status="", time=float("nan")):
        super().__init__(message)
        self.key = key
        self.status = status
        self.time = time


class SpecError(ValueError):
    """A spec was refused. ``key`` is the spec's key (dotted, e.g.
    ``parameters.friction.mu``), ``file``, ``line`` and ``column`` (1-based)
    where it is."""

    def __init__(self, message, key=None, file=None, line=None, column=None):
        where = f"{file}:{line}:{column}: " if file and line else (f"{file}: " if file else "")
        what = f"key '{key}': " if key else ""
        super().__init__(f"{where}{what}{message}")
        self.key, self.file, self.line, self.column = key, file, line, column


class NotReproduced(Exception):
    """A replayed sample whose row differs from the recorded one; the message
    names the columns (exit EXIT_NOT_REPRODUCED)."""


class NoCluster(Exception):
    """The scheduler named by --scheduler did not answer, or no worker joined
    it; the message names the address and the time waited (exit EXIT_NO_PEER)."""


class Interrupted(BaseException):
    """SIGINT, SIGTERM or SIGHUP: ``signum``; the program exits 128 + signum."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


# The one mapping: the first row whose class the exception is an instance of gives its code.
_TABLE = ((SpecError, EXIT_REFUSED), (SceneError, EXIT_REFUSED), (SimulationStopped, EXIT_STOPPED),
          (OutputError, EXIT_OUTPUT), (NotReproduced, EXIT_NOT_REPRODUCED), (NoCluster, EXIT_NO_PEER))


def exit_code(e):
    """The exit code of an exception that ends a program, or None when it is
    none of the table's (a bug: it goes on, a traceback and exit 1)."""
    if isinstance(e, Interrupted):
        return signal_exit(e.signum)
    return next((code for cls, code in _TABLE if isinstance(e, cls)), None)


def guarded_main(program, body, notes=None):
    """body()'s exit code; an exception of the table that escapes it is one
    line on stderr and its code: "<program>: error: <e>" (the exit-code
    table's form, as the C++ programs'), or "<program>: interrupted
    (<SIGNAL>)" for a signal, followed by notes[cls](e) for the first class
    of notes (a dict) the exception is an instance of (how to go on).
    A stderr whose reader is gone (`2>&1 | head -1`) stops no program: its
    lines are dropped from then on (_console.ReaderGoneStream)."""
    stderr = sys.stderr
    sys.stderr = console_stream(stderr, 2)
    try:
        return body()
    except BaseException as e:
        code = exit_code(e)
        if code is None:
            raise
        line = f"{program}: interrupted ({e})" if isinstance(e, Interrupted) else f"{program}: error: {e}"
        note = next((how for cls, how in (notes or {}).items() if isinstance(e, cls)), None)
        print(line + (note(e) if note else ""), file=sys.stderr)
        return code
    finally:
        sys.stderr = stderr


def exit_program(program, main):
    """Runs `python3 -m gimbalsim.X`'s main() and exits with its code; a stop signal after it is ignored: the
    interpreter's finalization puts the default action back on the signals it handled, and a SIGTERM landing
    there ended a finished sweep with 143 and no line (pass 71). One landing after main()'s own handling, before
    that, is said as guarded_main says it."""
    try:
        code = main()
    except Interrupted as e:
        print(f"{program}: interrupted ({e})", file=sys.stderr)
        code = signal_exit(e.signum)
    for signum in STOP_SIGNALS:
        signal.signal(signum, signal.SIG_IGN)
    sys.exit(code)


def not_a_program(module):
    """Exit 2 for a library module run as a program (`python3 -m gimbalsim.indices --bogus` took any argument,
    did nothing and exited 0, pass 39): the programs are the sweep, the tuner and the allocator."""
    name = f"gimbalsim.{module}" if module else "gimbalsim"
    print(f"python3 -m {name}: error: a library {'module' if module else 'package'}, not a program "
          "(docs/python.md): run python3 -m gimbalsim.sweep, gimbalsim.tune or gimbalsim.allocate", file=sys.stderr)
    sys.exit(EXIT_REFUSED)
