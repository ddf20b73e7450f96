"""The console of the programs and scripts: a stream whose reader may go
away. Standalone (no package import) so that tools/pages/output_file.py
loads it by path, as it loads the writer (_output.py)."""
import errno
import os
import sys


def keep_console():
    """A program's console for its whole life (its __main__: argparse's
    --help and refusals included): sys.stdout and sys.stderr as
    ReaderGoneStream, so that a reader gone stops nothing."""
    _open_if_closed(0)  # stdin too: the first file opened would take descriptor 0
    sys.stdout, sys.stderr = console_stream(sys.stdout, 1), console_stream(sys.stderr, 2)


def console_stream(stream, fd):
    """stream (sys.stdout: fd 1, sys.stderr: fd 2) as a ReaderGoneStream. A
    descriptor closed at start (`>&-`; Python then has None) gets /dev/null:
    else the first file opened would take it, and a child's console lines
    (a Dask worker's, a sweep's) would be written into that file."""
    if isinstance(stream, ReaderGoneStream):
        return stream
    if stream is None:
        _open_if_closed(fd)
        # the console's own descriptor (now /dev/null), not an output file: no writer's rules to go through
        stream = os.fdopen(fd, "w", closefd=False, encoding="utf-8", errors="backslashreplace")
    return ReaderGoneStream(stream)


def _open_if_closed(fd):
    try:
        os.fstat(fd)
    except OSError as e:
        if e.errno != errno.EBADF:
            raise
        null = os.open(os.devnull, os.O_RDWR)
        if null != fd:
            os.dup2(null, fd)
            os.close(null)
        os.set_inheritable(fd, True)


class ReaderGoneStream:
    """A console stream (stderr, stdout) as the programs write it: once a
    write or flush finds its pipe closed (EPIPE: `2>&1 | head -1`), or the
    device full or failing (`>/dev/full`), every later line is dropped,
    silently: exit 1 is a bug's code, a console is no output file, and a
    run's work is worth more than its messages (the C++ programs ignore
    SIGPIPE for the same reason)."""

    def __init__(self, stream):
        self._stream, self._closed = stream, False

    def _guard(self, op, *args):
        if self._closed:
            return None
        try:
            return op(*args)
        except OSError as e:
            # a reader gone, a full or failing device, a closed descriptor: a console, not an output
            if e.errno not in (errno.EPIPE, errno.ENOSPC, errno.EIO, errno.EBADF):
                raise
            self._closed = True
            _to_devnull(self._stream)
            return None

    def write(self, text):
        written = self._guard(self._stream.write, text)
        return len(text) if written is None else written

    def flush(self):
        self._guard(self._stream.flush)

    def __getattr__(self, name):  # fileno, isatty, encoding...: the stream's own
        return getattr(self._stream, name)


def _to_devnull(stream):
    """The stream's descriptor onto /dev/null: what its buffer still holds,
    flushed by Python at exit, then goes nowhere instead of printing
    "Exception ignored ... BrokenPipeError" (and what the C++ core writes there too)."""
    try:
        fd = stream.fileno()
        null = os.open(os.devnull, os.O_WRONLY)
    except (AttributeError, OSError, ValueError):  # no descriptor (a test's stream): nothing buffered below it
        return
    try:
        os.dup2(null, fd)
    finally:
        os.close(null)
