"""Tolerance allocation, the inverse question of a pointing budget: the
largest (or smallest) value of one design key at which a requirement holds
at its level with its confidence, with the evidence at every value tried.

    python3 -m gimbalsim.allocate SPEC.yaml --out DIR [--workers N | --scheduler tcp://HOST:PORT] [--resume]
    python3 -m gimbalsim.allocate SPEC.yaml --out DIR --check    # every refusal of a run, nothing run or written

SPEC is a closed-loop sweep spec (scene, set, controller, samples, seed,
parameters, phases, indices) with an `allocate:` section (_allocate_spec.py;
docs/python.md "Tolerance allocation"). Each value tried is one sweep of the
spec with the key set to it, in DIR/values/<tried>/ (results.csv, report.md,
a --replay of any unit), over the same units: every other key has the same
draws at every value (common random numbers). The search scans the range,
then bisects the bracket (_allocate_search.py); each value's verdict is
indices.requirement_verdict over every unit drawn (one without a figure
counts as worst), its quantile and interval indices.quantile_bound.

Writes DIR/allocation.json (the bracket or why there is none, each value's
verdict and bound, where the index is not monotone, the runs used),
DIR/allocation.csv (the table), DIR/allocation.md and DIR/allocation.png.
--resume finishes an interrupted allocation: a finished value is read back,
not run, when every row passes the sweep's --resume checks and no sample is
missing; any other value resumes its sweep (sweep --resume: rows it could not
have written dropped, missing samples run). Either way the value's sweep
writes its report, summary, plots, spec copy and inputs.json again from its
rows (one damaged, or copied from another value, is never kept). A value
folder holding the sweep at another value than the search asks there (copied
from another value) is refused before any run (exit 2). Every name
written (values/<i>/ and all in it included) is checked before any run: a
link, anything but its kind, or a folder holding a sweep or a tuning study is
refused (exit 2); checked again before each value's sweep, one planted since
is exit 4 (the values before it kept: move it away, --resume).
Exit codes (docs/usage.md "Exit codes"): 0 a bracket, or every value
meets (the limit lies beyond the range: said so); 3 no bracket: no value of
the range meets the requirement, or the favourable end fails while a value
further on meets (outputs written, the best value tried); 2 spec refused; 4 an
output not written; 6 the --scheduler did not answer; 130 / 143 / 129 interrupted (SIGINT / SIGTERM / SIGHUP)
(finished values kept: --resume).
"""
import contextlib
import csv
import os
import pathlib
import sys

import gimbalsim
from . import _cluster, _scene_warnings, _study_file
from ._allocate_report import CSV, JSON, PAGE, PLOT, _text, record, write
from ._allocate_search import next_value, outcome, scan_values
from ._allocate_spec import AllocationSpec
from ._console import keep_console
from ._errors import EXIT_OK, EXIT_STOPPED, Interrupted, OutputError, SpecError, exit_program, guarded_main
from ._output import OutputRefused, make_folder, output_set, what_to_do, write_text
from ._output_names import check_output_names
from ._spec import check_out_dir, check_outputs_not_inputs
from .sweep import FINGERPRINT as SWEEP_FINGERPRINT, RESULTS, finished_rows, output_paths, sweep

FINGERPRINT, VALUES = "allocation_spec.json", "values"


def _held(path):
    try:
        return path.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise SpecError(f"{path}: cannot read it ({e}); --resume needs the spec it names")


def _rows(sub, folder):
    """A finished value's rows, as its sweep wrote results.csv."""
    path = folder / RESULTS
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise SpecError(f"{path}: cannot read it ({e}); move {folder} away and run again with --resume")
    if not rows or rows[0] != sub.csv_header():
        raise SpecError(f"{path}: not the results of this value's sweep (its header differs); move {folder} away "
                        "and run again with --resume")
    return rows[1:]


def _check_value_folder(spec, folder, was_there):
    """Just before a value's sweep writes: a folder that appeared since the
    start (a link, another run's) or a name in it that became a link or
    another kind is refused (exit 4: the values before it are kept)."""
    if not was_there and os.path.lexists(folder):
        raise OutputRefused(f"{folder}: appeared while the allocation ran (a link or another run's folder); "
                            "never written through or into")
    files, folders = output_paths(spec, folder)
    check_output_names(folder, "sweep", files, folders)


def _check_outputs(a, out, inputs):
    """Every name the allocation writes, its values' sweeps' too (the most the
    search may try), refused before any run (exit 2): a link, anything but
    its kind, an input under it, or out holding another tool's outputs."""
    files, folders = [out / n for n in (FINGERPRINT, CSV, JSON, PAGE, PLOT)], [out, out / VALUES]
    spec = a.sweep_at(a.lo)  # each value's sweep writes the same names
    for k in range(a.values):
        value_files, value_folders = output_paths(spec, out / VALUES / str(k))
        files, folders = files + value_files, folders + value_folders
    check_output_names(out, "allocation", files, folders, refuse=SpecError)
    check_outputs_not_inputs(files + folders[1:], inputs)


def _not_this_value(a, folder, value):
    return SpecError(f"{folder} holds a sweep at another value than {a.key} = {a.value_text(value)}, the one the "
                     "search asks there: not this allocation's value (copied from another, or another spec's); move "
                     "it away and run again with --resume")


def _check_held_values(a, out):
    """On --resume, before any run: each value folder holds the sweep at the
    value the search asks there (exit 2, nothing run). The scan's values are
    known up front; a bisection's follow from the verdicts read back before
    it, and past a value to run again are checked as the search gets there
    (the main loop)."""
    subs = {}  # each value's SweepSpec, made once (a scan value is also the bisection's first)

    def check(k, value):
        folder = out / VALUES / str(k)
        if value not in subs:
            subs[value] = a.sweep_at(value)
        if (folder / SWEEP_FINGERPRINT).exists() and _held(folder / SWEEP_FINGERPRINT) != subs[value].fingerprint:
            raise _not_this_value(a, folder, value)
        return folder, subs[value]
    for k, value in enumerate(scan_values(a)):
        check(k, value)
    tried = {}
    for k in range(a.values):
        value = next_value(a, tried)
        if value is None:
            return
        folder, sub = check(k, value)
        if not (folder / SWEEP_FINGERPRINT).exists() or finished_rows(sub, folder) is None:
            return
        tried[value] = record(a, sub, _rows(sub, folder), value, k)


def check_before_run(a, out, resume=False):
    """Every refusal allocate() makes before its first run (exit 2, nothing written): --check stops here."""
    inputs = a.input_files()
    fingerprint = out / FINGERPRINT
    _check_outputs(a, out, inputs)
    if resume and not out.is_dir():  # (pass 49) it started afresh, as tune's --resume did not
        raise SpecError(f"{out}: no such folder: no allocation to resume; run without --resume")
    if resume:
        if fingerprint.exists() and _held(fingerprint) != a.fingerprint:
            raise SpecError(f"{out} holds an allocation of another spec; --resume needs the same spec")
        _check_held_values(a, out)
    elif fingerprint.exists() or (out / VALUES).exists():
        raise SpecError(f"{out} already holds an allocation: give --resume to finish it, or another --out")


def allocate(a, out, workers=None, scheduler=None, resume=False, batch=None, progress=True):
    """Runs the search of a (an AllocationSpec) into out; (result, lines, runs, ran)."""
    check_before_run(a, out, resume)
    inputs = a.input_files()
    fingerprint = out / FINGERPRINT
    tried, runs, ran = {}, 0, 0
    were_there = {k for k in range(a.values) if os.path.lexists(out / VALUES / str(k))}
    with contextlib.ExitStack() as stack:
        # One cluster for every value's sweep (a local one starts for the first value to run).
        cluster = stack.enter_context(_cluster.dask_client(None, scheduler)) if scheduler else None
        _start(out, fingerprint, a.fingerprint, inputs)
        # one allocation per folder, and what a killed writer left in it removed (pass 76: only its value
        # sweeps' folders were held, so .allocation.csv.<pid>.1.tmp of a SIGKILLed allocation stayed)
        _study_file.hold(out)
        while (value := next_value(a, tried)) is not None:
            k = len(tried)
            folder, sub = out / VALUES / str(k), a.sweep_at(value)
            held = folder / SWEEP_FINGERPRINT
            _check_value_folder(sub, folder, k in were_there)
            if held.exists() and _held(held) != sub.fingerprint:  # past a value run again: checked here
                raise _not_this_value(a, folder, value)
            # Read back when whole, every row as the sweep's --resume checks it; else that resume runs the
            # missing samples (a row the sweep could not have written dropped), so n is the units drawn.
            finished = held.exists() and finished_rows(sub, folder) is not None
            if not finished:
                print(f"allocate: value {k + 1} of at most {a.values}: {a.key} = {a.value_text(value)}",
                      file=sys.stderr)
                if cluster is None:
                    cluster = stack.enter_context(_cluster.dask_client(workers, None))
            # A finished value's sweep is resumed too: it runs nothing, but writes its report, summary,
            # plots and what its replay reads again from its rows (any may be damaged, or another value's).
            s = sweep(sub, folder, resume=resume, batch=batch, progress=progress and not finished, cluster=cluster)
            ran += s["engine"].get("ran_this_invocation", 0)
            rows = _rows(sub, folder)
            runs += len(rows)
            tried[value] = r = record(a, sub, rows, value, k)
            print(f"allocate: {a.key} = {a.value_text(value)}{' (read back)' if finished else ''}: "
                  f"{'PASS' if r['passed'] else 'FAIL'}, {r['n_meeting']}/{r['n']} units meet "
                  f"{a.requirement:.4g} rad, quantile {_text(r['estimate'])}, upper bound {_text(r['upper'])}",
                  file=sys.stderr)
            _cluster.raise_if_interrupted()
    result = outcome(a, tried)
    with output_set():
        lines = write(a, tried, result, runs, ran, out, inputs, gimbalsim._gimbalsim.csv_name)
    return result, lines, runs, ran


def _start(out, fingerprint, text, inputs):
    """out/ and out/values/ made where missing, then the fingerprint written; a failure (exit 4) removes the
    empty folders it made, so "nothing kept" holds and a plain run again is not refused over them."""
    made = []
    try:
        for folder in (out, out / VALUES):
            if make_folder(folder):
                made.append(folder)
        write_text(fingerprint, text, inputs)
    except BaseException:
        for folder in reversed(made):
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise


def _kept_and_next(out, first):
    """What a stopped allocation kept and how to go on ("<first>" before running again): before its
    fingerprint was written nothing is kept, and a --resume would be refused (no allocation to resume)."""
    if not (out / FINGERPRINT).exists():
        return f"nothing kept ({out / FINGERPRINT} was not written); {first}run again"
    return f"finished values kept in {out / VALUES}; {first}run again with --resume"


def main(argv=None):
    ap = _cluster.program_parser("allocate", __doc__,
                                 "allocation spec (YAML): a closed-loop sweep spec with an allocate: section",
                                 "output directory")
    ap.add_argument("--resume", action="store_true", help="finish an interrupted allocation in --out")
    ap.add_argument("--check", action="store_true",
                    help="check the spec and --out as a run would, run and write nothing (exit 0 or 2)")
    ap.add_argument("--batch", type=_cluster.whole_number, default=None,
                    help="samples per task (default: about 8 tasks per worker, at most 10)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)
    if a.batch is not None and not 1 <= a.batch <= 10_000_000:
        ap.error("--batch must be in [1, 10000000]")
    _cluster.raise_on_signals()
    _scene_warnings.quiet()
    out = pathlib.Path(a.out)
    return guarded_main("allocate", lambda: _run(a, out), {
        OutputRefused: lambda e: f"; {_kept_and_next(out, 'move it out of --out and ')}",
        OutputError: lambda e: f"; {_kept_and_next(out, what_to_do(e))}",
        Interrupted: lambda e: f": {_kept_and_next(out, '')} to finish"})


def _run(a, out):
    check_out_dir(a.out, a.spec)
    spec = AllocationSpec(a.spec)
    if a.check:
        _study_file.hold(out, keep=False)  # another run's folder: refused, as the run refuses it
        check_before_run(spec, out, a.resume)
        print(f"allocate: {a.spec} and {out} checked; nothing run", file=sys.stderr)
        return EXIT_OK
    result, lines, runs, ran = allocate(spec, out, a.workers, a.scheduler, a.resume, a.batch, not a.no_progress)
    for line in lines:
        print(f"allocate: {line}", file=sys.stderr)
    print(f"allocate: table in {out / CSV}, plot in {out / PLOT}, answer in {out / JSON}", file=sys.stderr)
    return EXIT_OK if result["bracket"] or result["outcome"] == "every_value_meets" else EXIT_STOPPED


if __name__ == "__main__":
    keep_console()  # a console whose reader is gone stops nothing, --help included
    exit_program("allocate", main)
