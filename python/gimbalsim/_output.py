"""The Python side's writer of files, with the rules of the C++ one (io::OutputFile,
base/io/include/gimbalsim/io/output_file.hpp; docs/usage.md "Output files"): every file the package and tools/*.py
write goes through here (Run.to_csv through the C++ writer itself).

- the path is checked first: an existing symbolic link or non-regular file (a folder, a device, a FIFO) under the
  name is refused, so is a missing folder, and so is an output that is the same file as one of the run's inputs
  (st_dev/st_ino of the file or, before it exists, of its folder plus its name, so a hard link or another spelling
  counts);
- the content goes into a temporary of our own beside the name, ".<name>.<pid>.<n>.tmp" (O_EXCL | O_NOFOLLOW:
  never an existing file or a link's target), is flushed and synced (fsync), then renamed onto the name
  (os.replace) and the folder synced: a file under the name is whole, even after a power cut;
- on any failure the temporary is removed and whatever was under the name stays as it was; the failure is one
  OutputError naming the path and the cause (exit 4 in the exit-code table, _errors.py); a path refused by the
  first rule, before a byte was written, is its kind OutputRefused.

Only the standard library: tools/pages/output_file.py loads this file from the source tree, without the built
package.
"""
import contextlib
import csv
import errno
import io
import itertools
import json
import os
import re
import signal
import sys
import stat
import types

try:
    from ._csv_cells import csv_text
except ImportError:  # loaded by path (tools/pages/output_file.py), which has loaded the cells' file first
    from gimbalsim_csv_cells import csv_text

__all__ = ["OutputError", "OutputRefused", "output_failed", "what_to_do", "check_outputs",
           "open_output", "output_set", "write_text", "write_bytes", "write_csv", "savefig", "figure_bytes",
           "open_append", "append_synced"]


class OutputError(OSError):
    """An output refused or not written; str() names the file and the cause.
    An OSError, as every failed write of the package was before (and as the
    C++ core's Run.to_csv raises)."""


class OutputRefused(OutputError):
    """An output refused by the rules before a byte was written (a link, a
    special file, an input or a missing folder under its name): freeing
    space does not help, moving the file away does."""


def output_failed(message, cause):
    """An OutputError of message, keeping the errno of the OSError cause: what to do next depends on it."""
    e = OutputError(message)
    e.errno = cause.errno
    return e


def make_folder(path):
    """A run's own folder, made where missing (the folder it goes in was checked); True when this call made
    it (what a failed start takes back). One that cannot be made is an OutputError (exit 4) with its cause."""
    try:
        path.mkdir()
        return True
    except FileExistsError:
        if path.is_dir():  # there already, or made meanwhile: taken
            return False
        raise output_failed(f"cannot make the folder {path}: a file stands there", FileExistsError()) from None
    except OSError as e:
        raise output_failed(f"cannot make the folder {path}: {e.strerror}", e) from None


def what_to_do(e):
    """The advice before "run again" for an OutputError or OSError e: more space helps only a full disk or quota
    (a folder that cannot be made in /proc was told to "free the space")."""
    no_space = getattr(e, "errno", None) in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG)
    return "free the space and " if no_space else "fix the cause and "


_counter = itertools.count()  # the <n> of the temporaries' names (next() is atomic under the GIL)
TEMPORARY = re.compile(r"\.(.+)\.([0-9]+)\.([0-9]+)\.tmp")  # a temporary's name, ".<name>.<pid>.<n>.tmp"


def _text(path):
    path = os.fspath(path)
    return os.fsdecode(path) if isinstance(path, bytes) else path


def _folder(path):
    return os.path.dirname(path) or "."


def _kind(mode):
    return ("a folder" if stat.S_ISDIR(mode) else "a file" if stat.S_ISREG(mode) else
            "a FIFO" if stat.S_ISFIFO(mode) else "a socket" if stat.S_ISSOCK(mode) else
            "a device" if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) else "not a file")


def _identity(path):
    """(device, inode, "") of the file, or (device, inode, name) of its folder
    before it exists; None when neither can be read."""
    try:
        st = os.stat(path)
        return st.st_dev, st.st_ino, ""
    except OSError:
        pass
    try:
        st = os.stat(_folder(path))
    except OSError:
        return None
    return st.st_dev, st.st_ino, os.path.basename(path)


def _check_one(path):
    if not path:
        raise OutputRefused("output path is empty")
    if "\0" in path:
        raise OutputRefused(f"{path!r}: holds a NUL byte; refused")
    name = os.path.basename(path)
    if name in ("", ".", ".."):
        raise OutputRefused(f"{path}: not a file name")
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise OutputRefused(f"{path}: {e.strerror or e}") from None
    if st is not None and stat.S_ISLNK(st.st_mode):
        raise OutputRefused(f"{path}: is a symbolic link; not written through (give its target)")
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise OutputRefused(f"{path}: exists and is not a regular file ({_kind(st.st_mode)}); not written")
    if st is not None and st.st_mode & 0o111 and (where := program_on_path(path, st)):
        raise OutputRefused(f"{path}: an executable file {where} (a program anything run by name may be); not "
                            "overwritten")
    if not os.path.isdir(_folder(path)):
        raise OutputRefused(f"{path}: its directory {_folder(path)} does not exist")


def program_on_path(path, st):
    """Where anything run by name finds the executable file path as a program ("in F, a folder on PATH", or "run
    as F/name on PATH": a link or a hard link there), or None. (pass 103, 107) the scripts' lists of the programs
    they run by name always missed one; (pass 108) a link in a PATH folder made a file elsewhere a program."""
    here = _identity(_folder(path) + "/.")
    for entry in [e or "." for e in os.environ.get("PATH", "").split(":")]:
        if here is not None and _identity(entry + "/.") == here:
            return f"in {entry}, a folder on PATH"
        with contextlib.suppress(OSError), os.scandir(entry) as names:
            for e in names:
                with contextlib.suppress(OSError):
                    if not e.is_dir() and os.stat(e.path)[1:3] == (st.st_ino, st.st_dev):
                        return f"run as {e.path} on PATH"
    return None


def check_outputs(outputs, inputs=()):
    """Refuses, before anything is written, outputs that break the rules:
    each on its own, then each against the outputs before it and against
    every input (same file: device and inode). Paths as str or os.PathLike;
    empty ones (None, "") are skipped. Raises OutputError."""
    seen, running = [], None
    for out in outputs:
        if running is None:  # once, and only when there is an output to check
            running = _running_program()
        if out is None or out == "":
            continue
        out = _text(out)
        _check_one(out)
        me = _identity(out)
        for other, theirs in seen:
            if theirs == me:
                raise OutputRefused(f"{out}: the same file as another output ({other})")
        # The running program is an input of every run (pass 84: a program's --out replaced it).
        named = [(_identity(_text(i)), f"the input {_text(i)}") for i in inputs if i is not None and i != ""]
        for theirs, what in named + running:
            if me is not None and theirs == me:
                raise OutputRefused(f"{out}: the same file as {what}; not overwritten")
        seen.append((out, me))


def _running_program():
    """The files the running process is: the interpreter, argv[0] when a file (not "-c" or ""), every module
    loaded (pass 90: a log written over output_file.py, which the tool had loaded, broke every later run)."""
    files = [sys.executable] if sys.executable else []
    files += [sys.argv[0]] if sys.argv and sys.argv[0] and os.path.isfile(sys.argv[0]) else []
    files += [f for m in list(sys.modules.values()) for a in ("__file__", "__cached__")  # .pyc too (pass 92)
              if isinstance(f := getattr(m, a, None), str)]
    for f in files:  # a module's file is stat'ed once: a sweep checks outputs thousands of times
        if f not in _RUNNING:
            _RUNNING[f] = (_identity(f), f"this program ({f})")
    return [_RUNNING[f] for f in dict.fromkeys(files)]


_RUNNING = {}  # path -> (identity, what), _running_program's


def _create_temporary(path, binary):
    """A fresh file of our own beside path, opened with open() (so it can be
    watched like any write): O_EXCL | O_NOFOLLOW, mode 0666 less the umask."""
    folder, name = _folder(path), os.path.basename(path)
    flags = os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
    opener = lambda p, f: os.open(p, f | flags, 0o666)  # noqa: E731
    for _ in range(100):
        tmp = os.path.join(folder, f".{name}.{os.getpid()}.{next(_counter)}.tmp")
        try:
            return tmp, open(tmp, "wb" if binary else "w", opener=opener,
                             **({} if binary else {"encoding": "utf-8", "newline": ""}))
        except FileExistsError:
            continue
        except OSError as e:
            raise output_failed(f"{path}: cannot create a temporary in {folder}: {e.strerror or e}", e) from None
    raise OutputError(f"{path}: cannot create a temporary (100 names taken)")


def _remove(tmp):
    with contextlib.suppress(OSError):
        os.unlink(tmp)


def _sync_folder(path):
    """fsync of the folder, so the rename survives a power cut (a file system
    that cannot sync a folder, EINVAL, has nothing to sync)."""
    fd = os.open(_folder(path), os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    try:
        os.fsync(fd)
    except OSError as e:
        if e.errno != errno.EINVAL:
            raise
    finally:
        os.close(fd)


_sets = []  # the open output_set() blocks, innermost last
_HELD = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}  # _early_signals.STOP_SIGNALS, held while a set is renamed


@contextlib.contextmanager
def output_set():
    """Outputs that appear together or not at all (a report, its plots, its summary): each file open_output writes
    in the block stays in its temporary; at the end all are renamed into place, the stop signals held back; an
    exception removes them, the files under the names stay as they were (pass 69: SIGTERM amid a page's figures
    left some names gone, the rest old). Yields the set (.committed: all in place); one inside another joins it."""
    _sets.append(this := types.SimpleNamespace(pending=[], committed=False))  # pending: (temporary, name) pairs
    try:
        yield this
    except BaseException:
        for tmp, _ in this.pending:
            _remove(tmp)
        raise
    finally:
        _sets.remove(this)
    if _sets:
        _sets[-1].pending += this.pending
        return
    held = signal.pthread_sigmask(signal.SIG_BLOCK, _HELD)
    try:
        for k, (tmp, path) in enumerate(this.pending):
            try:
                os.replace(tmp, path)
                _sync_folder(path)
            except OSError as e:
                for rest, _ in this.pending[k:]:
                    _remove(rest)
                raise output_failed(f"{path}: rename failed: {e.strerror or e}", e) from None
        this.committed = True
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


@contextlib.contextmanager
def open_output(path, mode="w", inputs=()):
    """Yields the open temporary of path (mode "w": text, UTF-8, newlines as
    written; "wb": bytes) to write into; on leaving without an exception it
    is flushed, synced, closed and renamed onto path, else removed (the
    exception goes on; a failed write of the body becomes OutputError).
    inputs: the run's input files, which path may not be."""
    if mode not in ("w", "wb"):
        raise ValueError(f"open_output: mode {mode!r} (\"w\" or \"wb\")")
    path = _text(path)
    if path == "":  # check_outputs skips an empty optional output; here one is being written
        raise OutputRefused("output path is empty")
    check_outputs([path], inputs)
    tmp, f = _create_temporary(path, mode == "wb")
    stage = "write failed"
    try:
        try:
            yield f
            f.flush()
            stage = "sync failed"
            os.fsync(f.fileno())
            stage = "close failed"
        finally:
            f.close()
        if _sets:  # one of a set: renamed with the others when the set ends
            _sets[-1].pending.append((tmp, path))
            tmp = None
            return
        stage = "rename failed"
        os.replace(tmp, path)
        tmp = None
        stage = "sync of its folder failed (the file is whole)"
        _sync_folder(path)
    except OutputError:
        raise
    except OSError as e:
        raise output_failed(f"{path}: {stage}: {e.strerror or e}", e) from None
    finally:
        if tmp is not None:
            _remove(tmp)


def write_text(path, text, inputs=()):
    """text (str) under path, whole or not at all."""
    with open_output(path, "w", inputs) as f:
        f.write(text)


def json_text(obj):
    """obj as the project's JSON: strict (a NaN or an infinity raises here, as
    a bug, instead of writing the non-JSON NaN or Infinity; a figure that
    has no value is null with its reason)."""
    return json.dumps(obj, indent=2, allow_nan=False) + "\n"


def write_bytes(path, data, inputs=()):
    """data (bytes) under path, whole or not at all."""
    with open_output(path, "wb", inputs) as f:
        f.write(data)


def write_csv(path, rows, inputs=()):
    """rows (lists of cells, the header first) as CSV text: "," between
    cells, "\\n" after each row (the project's CSV convention, docs/usage.md)."""
    with open_output(path, "w", inputs) as f:
        csv.writer(f, lineterminator="\n", quoting=csv.QUOTE_NONE).writerows(
            [[csv_text(c) for c in row] for row in rows])


def savefig(fig, path, inputs=(), close=False, **kwargs):
    """A matplotlib figure under path (fig.savefig into the temporary; the
    format from path's extension unless format= says); close=True closes the
    figure afterwards, written or not (a study's many figures stay few in memory)."""
    kwargs.setdefault("format", os.path.splitext(_text(path))[1].lstrip(".").lower() or None)
    try:
        with open_output(path, "wb", inputs) as f:
            fig.savefig(f, **kwargs)
    finally:
        if close:
            import matplotlib.pyplot as plt  # only a caller that plots loads it
            plt.close(fig)


# ---- an append-only log (the sweep's journal), which is never renamed: appended and synced ----

def figure_bytes(fig, fmt, **kwargs):
    """A matplotlib figure as the bytes of format fmt, written nowhere: a
    caller that must write it together with another output renders it first."""
    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, **kwargs)
    return buf.getvalue()


def open_append(path):
    """A file descriptor appending to the existing regular file path
    (O_NOFOLLOW: a link under the name is refused, not written through)."""
    path = _text(path)
    try:
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as e:
        if e.errno == errno.ELOOP:
            raise OutputRefused(f"{path}: cannot open it to append: is a symbolic link; not written through") from None
        raise output_failed(f"{path}: cannot open it to append: {e.strerror or e}", e) from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise OutputRefused(f"{path}: exists and is not a regular file; not written")
    return fd


def append_synced(fd, data, path):
    """data (bytes) appended whole to fd, unbuffered, then synced; a failure
    is an OutputError naming path (what was appended before stays)."""
    try:
        while data:
            data = data[os.write(fd, data):]
        os.fsync(fd)
    except OSError as e:
        raise output_failed(f"{_text(path)}: write failed: {e.strerror or e}", e) from None
