"""A study's folder and the tuner's study file (out/study.db): one sweep or
tuner per folder (a lock held for the process's life), a --resume only of
this folder's own study, checked read-only before Optuna opens it
(read-write only to let SQLite roll back what a killed writer left), the
opening itself (open_study), and forgetting a new study that recorded
nothing (forget_unrecorded_study)."""
import contextlib
import errno
import fcntl
import os
import sqlite3
import sys

from ._errors import SpecError
from ._output import TEMPORARY, make_folder, output_failed, what_to_do

STUDY_FILE = "study.db"
STUDY_NAME = "gimbalsim.tune"
TRIALS = "trials.csv"  # the tuner's record of its trials, one row each

_HELD = []  # the lock files of the studies this process holds, open until it ends


def hold(out, keep=True):
    """One sweep or tuner per folder: an exclusive lock on the folder itself
    (no lock file left among the outputs) for the life of the process; a
    second one on the same folder is refused (exit 2) before it reads or writes.
    keep False (--check): the same refusal, the lock let go at once and a folder
    not made yet held by no one (pass 87: --check --resume said nothing while
    another run held the folder, which the run itself refused)."""
    if not keep and not os.path.isdir(out):
        return
    fd = os.open(out, os.O_RDONLY | os.O_DIRECTORY | getattr(os, "O_CLOEXEC", 0))
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise SpecError(f"{out}: another sweep, tuner or allocation is running in this folder; wait for it to end "
                        f"(then --resume), or use another --out") from None
    if not keep:
        os.close(fd)  # closing lets the lock go
        return
    _HELD.append(fd)
    _remove_dead_temporaries(out)


def _alive(pid):
    if pid <= 0:  # no process's (kill(0) would ask about our own group)
        return False
    try:
        os.kill(pid, 0)
    except (ProcessLookupError, OverflowError):
        return False
    except PermissionError:  # another user's process
        return True
    return True


def _remove_dead_temporaries(out):
    """A writer killed by SIGKILL (or a power cut) leaves its temporary (pass 72: .results.csv.<pid>.1.tmp
    stayed through every --resume). With the folder held, a temporary of a process no longer running is
    no one's: removed, and said. The folder and its subfolders one level down (a sweep's runs), no links."""
    def entries(folder):  # a folder we may not read holds nothing we could remove
        try:
            return list(os.scandir(folder))
        except OSError:
            return []
    folders = [out] + [e.path for e in entries(out) if e.is_dir(follow_symlinks=False)]
    removed = []
    for folder in folders:
        for e in entries(folder):
            m = TEMPORARY.fullmatch(e.name)  # io::OutputFile names its temporaries alike
            if m and e.is_file(follow_symlinks=False) and not _alive(int(m.group(2))):
                with contextlib.suppress(OSError):
                    os.unlink(e.path)
                    removed.append(os.path.relpath(e.path, out))
    if removed:
        shown = ", ".join(sorted(removed)[:5]) + (f" and {len(removed) - 5} more" if len(removed) > 5 else "")
        print(f"{out}: removed {len(removed)} temporary file(s) a killed writer left: {shown}", file=sys.stderr)


def refuse_if_running(out):
    """hold's refusal before a folder's files are judged: a study another tuner is creating looked empty, and
    the second tuner was told to remove it (pass 72). The lock is taken and let go at once (hold keeps it)."""
    if os.path.isdir(out) and not os.path.islink(out):
        hold(out)
        os.close(_HELD.pop())


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


def open_study(spec, out, resume):
    """The study stored in out/study.db (Optuna's RDB storage on SQLite), its
    folder checked (check_study_folder): created with the baseline as its
    first trial, or, with resume, loaded; then trials left RUNNING by a killed
    tuner are marked FAIL (`killed`) and queued again with the same gains.
    Its sampler is the caller's to set (seeded by what the study holds)."""
    import optuna

    db = out / STUDY_FILE
    if resume and not out.is_dir():  # (pass 48) refused all the same, after it had made the folder
        raise SpecError(f"{out}: no such folder: no study to resume; run without --resume")
    make_folder(out)
    import sqlalchemy.exc

    hold(out)
    existed = db.exists()
    if resume:
        check_resumable(db, out, STUDY_NAME)
    try:
        storage = optuna.storages.RDBStorage(f"sqlite:///{db.resolve()}")
        study = optuna.create_study(storage=storage, study_name=STUDY_NAME, direction="minimize",
                                    load_if_exists=True)
    # RuntimeError: a study file of another Optuna version ("no longer compatible with the table schema")
    except (sqlalchemy.exc.SQLAlchemyError, optuna.exceptions.StorageInternalError, RuntimeError) as e:
        if not existed:  # a new study not written (a full disk): exit 4 in main
            raise
        raise SpecError(f"{db}: cannot open it as a study ({str(e).splitlines()[0]}); use another --out") from None
    try:  # a damaged file (a table dropped) opens, then fails on its first read
        damaged = [t.number for t in study.get_trials(deepcopy=False)
                   if t.state == optuna.trial.TrialState.COMPLETE and t.value is None]
        fingerprint = study.user_attrs.get("fingerprint")
    except (sqlalchemy.exc.SQLAlchemyError, optuna.exceptions.StorageInternalError, RuntimeError, KeyError,
            TypeError, ValueError) as e:
        raise SpecError(f"{db}: cannot read it as a study ({str(e).splitlines()[0]}); use another --out") from None
    if damaged:
        raise SpecError(f"{db}: damaged: trial {damaged[0]} is complete without a value; use another --out")
    if fingerprint is None:  # new (or killed before its fingerprint, the last step of its making)
        if not study.trials:
            study.enqueue_trial(spec.baseline, user_attrs={"origin": "baseline"})
        study.set_user_attr("fingerprint", spec.fingerprint)
    elif fingerprint != spec.fingerprint:
        raise SpecError(f"{db} holds a study of another spec; --resume needs the same spec (the trial count "
                        f"may differ)")
    gain_names = [p.key for p in spec.gains]
    for t in study.get_trials(deepcopy=False, states=(optuna.trial.TrialState.RUNNING,)):
        # Its gains: those drawn, or those it was queued with (a baseline or a retry killed before it drew them).
        gains = {**t.system_attrs.get("fixed_params", {}), **t.params}
        storage.set_trial_user_attr(t._trial_id, "row", {"trial": t.number, "state": "FAIL", "reason": "killed",
                                                        "origin": t.user_attrs.get("origin", ""), **gains})
        storage.set_trial_state_values(t._trial_id, optuna.trial.TrialState.FAIL)
        # (pass 80) one killed before its gains were drawn has none to run again: a new proposal takes its place,
        # never one called its retry
        if all(k in gains for k in gain_names):
            study.enqueue_trial({k: gains[k] for k in gain_names}, user_attrs={"origin": f"retry of {t.number}"})
    return study


def check_trials_held(study, trials_csv):
    """On --resume, before trials.csv is written again from the study: every trial it records must be one
    the study holds. A study.db that lost them (damaged, or replaced by another) would rewrite trials.csv
    without them, the only record of the finished trials gone (pass 51: exit 4, "free the space");
    refused (SpecError, exit 2), nothing written. A trials.csv that does not read is the study's to rewrite."""
    import csv
    try:
        with open(trials_csv, newline="") as f:
            recorded = {int(r["trial"]) for r in csv.DictReader(f) if (r.get("trial") or "").isdigit()}
    except (OSError, UnicodeDecodeError, csv.Error, KeyError):
        return
    missing = sorted(recorded - {t.number for t in study.trials})
    if missing:
        shown = ", ".join(map(str, missing[:5])) + (" ..." if len(missing) > 5 else "")
        raise SpecError(f"{trials_csv} records {len(missing)} trial(s) the study in {trials_csv.parent / 'study.db'} "
                        f"does not hold ({shown}): the study file was damaged or replaced; trials.csv is kept (resume "
                        "from the study.db that holds them)")


def write_failure(out, e, then):
    """The OutputError (exit 4) of a write to out/study.db that failed with SQLite's error e, its advice
    before `then`. SQLite names no system cause for a file it cannot open ("unable to open database file":
    a read-only file system, a folder that refuses new files), so the system is asked, opening it as SQLite
    would; "free the space" only where it opens (the write itself failed) or SQLite says the disk is full."""
    path = out / STUDY_FILE
    said = str(e).splitlines()[0]
    cause = OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    if "database or disk is full" not in said:
        existed = os.path.lexists(path)
        try:
            os.close(os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC | os.O_NOFOLLOW, 0o666))
            if not existed:
                with contextlib.suppress(OSError):
                    os.unlink(path)
        except OSError as system:
            cause = system
            said += f" ({system.strerror})"
    return output_failed(f"cannot write the study {path}: {said}; {what_to_do(cause)}{then}", cause)


def trials_kept(out):
    """How many trials out/trials.csv holds (0 when there is none)."""
    try:
        return max(0, (out / TRIALS).read_bytes().count(b"\n") - 1)
    except OSError:
        return 0


def study_recorded(out):
    """Whether out/study.db holds this tool's study (what --resume takes)."""
    try:
        check_resumable(out / STUDY_FILE, out, STUDY_NAME)
    except SpecError:
        return False
    return True


def forget_unrecorded_study(out, folder_before=True):
    """Removes a new study's files when it was never recorded: the database, its journal, a trials.csv with
    no trial; and the folder, emptied, when this run made it (not folder_before)."""
    if trials_kept(out):
        return
    for name in (STUDY_FILE, STUDY_FILE + "-journal", TRIALS):
        if os.path.lexists(out / name):  # (pass 59) on a read-only file system even a missing one fails: EROFS
            with contextlib.suppress(FileNotFoundError):
                (out / name).unlink()
    if not folder_before:
        with contextlib.suppress(OSError):
            out.rmdir()


def study_write_errors():
    """The exceptions of a failed write to the study's storage."""
    import optuna
    import sqlalchemy.exc
    return optuna.exceptions.StorageInternalError, sqlalchemy.exc.SQLAlchemyError
