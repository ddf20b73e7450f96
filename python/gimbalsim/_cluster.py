"""The Dask cluster the sweep and the tuner run on: a local cluster of one
worker process per core (the default), or an existing scheduler that
dask-worker processes on any number of machines have joined. Every worker
needs this package on its PYTHONPATH."""
import argparse
import asyncio
import contextlib
import ctypes
import functools
import logging
import os
import signal
import sys
import time
import threading
import warnings

from . import _flags, _number
from ._early_signals import STOP_SIGNALS
from ._errors import Interrupted, NoCluster

LOOPBACK = "127.0.0.1"
ALLOWED_FAILURES = 1
NEVER_S = 10 ** 9  # [s] a timeout that never ends a run (32 years)
WORKERS_TIMEOUT_S = 60  # how long a scheduler named by --scheduler may go without a worker
# Test hook, read in the worker: the sample (sweep) or plant (tune) whose
# index it names kills its worker process, as a crash in the C++ core would.
CRASH_HOOK = "GIMBALSIM_TEST_KILL_WORKER_AT"


def task_chunks(todo, size, n_workers, guided):
    """The tasks' samples: `size` each, or (guided) shrinking towards 1 as the samples left run out, so that
    at the end no worker waits long on another's whole task (60 closed-loop units in tasks of 4 left one of
    two workers idle for about 2 s: 32 ms per sample of "engine overhead" that no engine spent)."""
    chunks, k = [], 0
    while k < len(todo):
        n = size if not guided else max(1, min(size, (len(todo) - k) // (2 * n_workers)))
        chunks.append(todo[k:k + n])
        k += n
    return chunks


def warm_up(client, task, *args):
    """Seconds for every worker present to run task(*args) once: an empty task, unpickled by name, imports
    the module that runs the samples (0.7 s each here) before the first one, so that no sample's figures
    carry it (a dask-worker that never ran the sweep's module read it as 20 ms of engine overhead per sample
    over 60 units). A worker that cannot answer warms on its first task instead."""
    import time
    t = time.perf_counter()
    try:
        client.run(task, *args)
    except Exception:  # noqa: BLE001 (the tasks meet whatever this met, and report it as theirs)
        return 0.0
    return time.perf_counter() - t


def rerun_alone(items, submit):
    """After a task of several items killed its worker (KilledWorker): each item in a task of its own,
    [(future, [item])], so only the one that kills its worker again is crashed (pass 43: its task's others were,
    and the result changed with the worker count). [] for a task of one item: that item is the crash."""
    return [(submit([it]), [it]) for it in items] if len(items) > 1 else []


_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3  # glibc's mallopt parameters (malloc.h)


@functools.cache
def keep_freed_memory():
    """Called at each task's start on a worker (once a process): glibc keeps what a sample frees for the next.
    A Dask nanny starts its worker with MALLOC_TRIM_THRESHOLD_=65536, and any threshold set freezes glibc's
    mmap threshold at 128 KiB: every column and array above it was mapped afresh and page-faulted in, each
    sample (7200 faults, 2.5 times a closed-loop sample's CPU on an AMD EPYC VM). Here, not in the cluster's
    configuration, so that dask-worker processes the user starts are mended too; a worker keeps up to 64 MiB."""
    try:
        libc = ctypes.CDLL(None)
        libc.mallopt(_M_MMAP_THRESHOLD, 32 << 20)
        libc.mallopt(_M_TRIM_THRESHOLD, 64 << 20)
    except (OSError, AttributeError):
        pass  # no glibc: its thresholds are not ours to mend


def crash_hook(index):
    """Kills this worker process when the test hook names index."""
    if os.environ.get(CRASH_HOOK) == str(index):
        os.kill(os.getpid(), signal.SIGKILL)


@contextlib.contextmanager
def dask_client(workers=None, scheduler=None):
    """Yields (client, number of workers)."""
    import dask
    # distributed's defaults in dask.config before the set below: set over a config without them, its exit
    # removed the whole "distributed" tree, and the next cluster of the process failed (KeyError 'comm')
    import distributed  # noqa: F401

    if scheduler:
        with _scheduler_client(scheduler) as client:
            yield client, len(client.scheduler_info()["workers"])
        return
    n = workers or os.cpu_count() or 1
    # A worker absent from the scheduler lost-worker-timeout (15 s) after a death had its nanny closed for good
    # by the cluster (SpecCluster, read at each death), never replaced: a sample killing each restarted worker
    # of a loaded machine left none, and the study waited forever (pass 58). Each nanny restarts its own worker.
    with dask.config.set({"distributed.deploy.lost-worker-timeout": NEVER_S}):
        yield from _local_client(n)


def _local_client(n):
    """dask_client's local cluster of n worker processes (a generator dask_client yields from)."""
    import dask
    from distributed import Client, LocalCluster

    # Ctrl-C (and a terminal's hangup) reaches the whole process group: worker processes started while
    # SIGINT and SIGHUP are ignored keep ignoring them (no worker tracebacks, no worker killed under the
    # shutdown); this process takes them and shuts the workers down.
    # the worker processes' own logging (set up at their start, from the environment): errors only,
    # not the INFO lines of a start after a killed cluster (stale lock files purged)
    os.environ.setdefault("DASK_LOGGING__DISTRIBUTED", "error")
    main = threading.current_thread() is threading.main_thread()
    handlers = {s: signal.signal(s, signal.SIG_IGN) for s in (signal.SIGINT, signal.SIGHUP)} if main else {}
    try:
        # A task on a worker that dies twice raises KilledWorker (Dask's default:
        # four deaths), so a sample that kills its worker is retried once, then
        # reported. One task at a time per worker (saturation 1): a death
        # accuses only the task that was running, not one queued behind it.
        with warnings.catch_warnings(), dask.config.set({"distributed.scheduler.allowed-failures": ALLOWED_FAILURES,
                                                         "distributed.scheduler.worker-saturation": 1.0}):
            warnings.filterwarnings("ignore", message="Port .* is already in use")
            # Loopback only: scheduler, nannies, workers and their HTTP servers
            # (which otherwise listen on every interface, the scheduler's on
            # 8787 even with no dashboard asked for). Other machines join a
            # scheduler the user starts and names with --scheduler.
            # Worker logs off: a task's failure reaches us as its exception.
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host=LOOPBACK,
                                   dashboard_address=f"{LOOPBACK}:0", worker_dashboard_address=f"{LOOPBACK}:0",
                                   silence_logs=logging.CRITICAL)
        client = Client(cluster)
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)
    try:
        yield client, n
    except BaseException:
        # interrupted or failed: shut down without the cluster's own complaints
        logging.getLogger("distributed").setLevel(logging.CRITICAL)
        with contextlib.suppress(Exception, Interrupted):  # a second signal ends the wait, not the shutdown
            _let_starting_workers_start(cluster)
        with contextlib.suppress(Exception):
            client.close()
        with contextlib.suppress(Exception):
            cluster.close()
        raise
    client.close()
    cluster.close()


STARTING_WAIT_S = 10.0  # at most, for a worker replacing a dead one to finish its start before the cluster closes


def _let_starting_workers_start(cluster):
    """Waits (STARTING_WAIT_S at most) until no worker process is starting
    and none has been for 0.3 s: Dask 2022.12 closing a worker inside its
    start (a nanny replacing a worker a sample killed) closes it twice, and
    the worker process prints Dask's AssertionError traceback on the way out."""
    from distributed.core import Status
    deadline, quiet_since = time.monotonic() + STARTING_WAIT_S, None
    while time.monotonic() < deadline:
        nannies = list(cluster.workers.values())
        busy = any(getattr(n, "process", None) is None or n.process.status != Status.running for n in nannies
                   if getattr(n, "status", None) == Status.running)
        now = time.monotonic()
        quiet_since = None if busy else quiet_since or now
        if quiet_since is not None and now - quiet_since >= 0.3:
            return
        time.sleep(0.05)


@contextlib.contextmanager
def _scheduler_client(address):
    """A client of the scheduler at address (--scheduler) with a worker
    joined. One that does not answer within Dask's connect timeout
    (distributed.comm.timeouts.connect, 30 s unless the environment's
    DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT says), or has no worker within
    WORKERS_TIMEOUT_S, is NoCluster (exit 6): one line, not Dask's traceback."""
    import dask
    from dask.utils import parse_timedelta
    from distributed import Client

    wait = dask.config.get("distributed.comm.timeouts.connect")
    try:
        client = Client(address, timeout=wait)
    except (OSError, asyncio.TimeoutError) as e:
        why = str(e).splitlines()[0] if str(e) else type(e).__name__
        why = "" if why.startswith("Timed out") else f": {why}"  # Dask's own words only when they add a cause
        raise NoCluster(f"--scheduler {address}: no Dask scheduler answered within {parse_timedelta(wait):g} s "
                        f"(Dask's distributed.comm.timeouts.connect){why}; start it, or check the address") from None
    try:
        try:
            client.wait_for_workers(1, timeout=WORKERS_TIMEOUT_S)
        except (OSError, asyncio.TimeoutError):
            raise NoCluster(f"--scheduler {address}: no worker joined the scheduler within {WORKERS_TIMEOUT_S} s; "
                            "start dask-worker processes pointed at it") from None
        yield client
    finally:
        client.close()


class _DropInterrupted(logging.Filter):
    """A signal that lands inside a library's cleanup (SQLAlchemy resetting
    the study's connection from a finalizer) is logged there with its
    traceback on its way out; the program reports it itself, in one line."""

    def filter(self, record):
        return not (record.exc_info and isinstance(record.exc_info[1], Interrupted))


_DROP_INTERRUPTED = _DropInterrupted()


_received = []  # every stop signal (STOP_SIGNALS) seen, in order


def _quiet_unraisable(u):
    """Python prints and drops an exception raised inside a finalizer; an
    Interrupted there is kept in _received and raised again by the loops
    (raise_if_interrupted), so it is not printed. Anything else is."""
    if not isinstance(u.exc_value, Interrupted):
        _quiet_unraisable.default(u)


_quiet_unraisable.default = sys.unraisablehook


def raise_on_signals():
    """SIGINT, SIGTERM and SIGHUP raise Interrupted in the main thread (and no
    library's log repeats it on the console)."""
    def handler(signum, frame):
        _received.append(signum)
        raise Interrupted(signum)
    for signum in STOP_SIGNALS:
        signal.signal(signum, handler)
    if sys.unraisablehook is not _quiet_unraisable:
        _quiet_unraisable.default = sys.unraisablehook
        sys.unraisablehook = _quiet_unraisable
    if logging.lastResort is not None and _DROP_INTERRUPTED not in logging.lastResort.filters:
        logging.lastResort.addFilter(_DROP_INTERRUPTED)


def raise_if_interrupted():
    """Raises Interrupted for a signal already received. A signal that lands
    inside a finalizer (SQLAlchemy's cleanup of the study's session) has its
    exception printed and dropped by Python; the loops call this at each
    step so the run still stops for it."""
    if _received:
        raise Interrupted(_received[0])


def whole_number(text):
    """An argparse type: a plain whole number as written (' 1', '+1', '1_0' and '0x1' are not)."""
    n = _number.plain_whole(text)
    if n is None:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number")
    return n


def path_text(text):
    """An argparse type: a path, never empty or blank ('' wrote the whole study into the current folder)."""
    if not text:
        raise argparse.ArgumentTypeError("an empty path: name a folder or a file")
    if not text.strip():  # a file named '  ' is a slip of the shell, never a name anyone means
        raise argparse.ArgumentTypeError(f"a blank path {text!r}: name a folder or a file")
    return text


def local_workers(text):
    """--workers N: a whole number from 1 to 4 per core of this machine. More
    local processes only share the cores (and each holds its own memory);
    more machines join through --scheduler."""
    most = 4 * (os.cpu_count() or 1)
    n = whole_number(text)
    if not 1 <= n <= most:
        raise argparse.ArgumentTypeError(f"{n}: must be from 1 to {most} (4 per core of this machine; "
                                         "more machines: --scheduler)")
    return n


def scheduler_address(text):
    """--scheduler: a Dask scheduler's address, [SCHEME://]HOST:PORT, checked
    as Dask reads it before anything runs: a malformed one (no port, an
    unknown scheme) failed only at the connection, after --out was written."""
    from distributed.comm.addressing import get_address_host_port

    form = "give tcp://HOST:PORT, the address dask-scheduler prints (PORT from 1 to 65535)"
    try:
        host, port = get_address_host_port(text)
    except ValueError:
        scheme = text.split("://")[0] if "://" in text else "tcp"
        why = (f"unknown scheme {scheme!r}" if scheme not in ("tcp", "tls", "ucx", "ws", "wss") else
               "no PORT" if ":" not in text.split("://")[-1] else "a bad PORT")
        raise argparse.ArgumentTypeError(f"{text!r} is not a scheduler address ({why}): {form}") from None
    digits = text.rsplit(":", 1)[-1]
    if not host.strip() or not (digits.isascii() and digits.isdigit()) or not 1 <= port <= 65535:
        why = "no HOST" if not host.strip() else f"PORT {digits!r}"
        raise argparse.ArgumentTypeError(f"{text!r} is not a scheduler address ({why}): {form}")
    return text


def program_parser(module, doc, spec_help, out_help):
    """The argument parser of the package's programs (sweep, tune, allocate):
    no abbreviations, the module's doc as its description, --version, the
    spec, --out and the cluster's flags; every flag that takes one value is
    refused when given twice."""
    from . import __version__
    ap = argparse.ArgumentParser(allow_abbrev=False, prog=f"python3 -m gimbalsim.{module}", description=doc,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    _flags.one_value_each(ap)
    ap.add_argument("--version", action="version", version=f"gimbalsim.{module} {__version__}")
    ap.add_argument("spec", type=path_text, help=spec_help)  # '' read the folder one stands in (pass 87)
    ap.add_argument("--out", type=path_text, required=True, help=out_help)
    add_cluster_arguments(ap)
    return ap


def add_cluster_arguments(parser):
    g = parser.add_mutually_exclusive_group()
    g.add_argument("--workers", type=local_workers, default=None,
                   help="local cluster of N worker processes (default: one per core; at most 4 per core)")
    g.add_argument("--scheduler", type=scheduler_address, default=None,
                   help="an existing Dask scheduler, tcp://HOST:PORT (dask-scheduler + dask-worker processes)")
