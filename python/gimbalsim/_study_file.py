"""A study's folder and the tuner's study file (out/study.db) before Optuna
opens it: one sweep or tuner per folder (a lock held for the process's life),
and a --resume only of this folder's own study, checked read-only (read-write only to let SQLite roll back
what a killed writer left)."""
import contextlib
import fcntl
import os
import sqlite3

from ._errors import SpecError

_HELD = []  # the lock files of the studies this process holds, open until it ends


def hold(out):
    """One sweep or tuner per folder: an exclusive lock on the folder itself
    (no lock file left among the outputs) for the life of the process; a
    second one on the same folder is refused (exit 2) before it reads or writes."""
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise SpecError(f"{out}: another sweep or tuner is running in this folder; wait for it to end (then "
                        f"--resume), or use another --out") from None
    _HELD.append(fd)


def check_resumable(db, out, study_name):
    """--resume needs this folder's own study, read before anything writes
    to it: a missing, empty, linked or foreign file would become a new study
    (Optuna creates its tables in any SQLite file) and trials.csv be rewritten."""
    if db.is_symlink() or (db.exists() and not db.is_file()):
        raise SpecError(f"{db}: not a regular file (a link or a folder): a study is never written through one")
    if not db.exists() or db.stat().st_size == 0:
        raise SpecError(f"{db}: {'empty' if db.exists() else 'missing'}: no study of {out} to resume; run without "
                        f"--resume into another --out")
    # A tuner killed mid-write leaves a hot rollback journal beside the file; SQLite restores the study from
    # it on the next open, which needs write access: read-only, every --resume was refused (pass 43).
    journal = db.with_name(db.name + "-journal")
    mode = "rw" if journal.is_file() and not journal.is_symlink() else "ro"
    try:
        with contextlib.closing(sqlite3.connect(f"file:{db.resolve()}?mode={mode}", uri=True)) as c:
            names = [r[0] for r in c.execute("SELECT study_name FROM studies")]
    except sqlite3.Error as e:
        raise SpecError(f"{db}: cannot open it as a study ({e}); use another --out") from None
    if study_name not in names:
        raise SpecError(f"{db}: not a study of {study_name} (it holds {names or 'no study'}); use another --out")
