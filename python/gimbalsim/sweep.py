"""Monte Carlo sweep of a scene over dispersed parameters, on a Dask cluster.

    python3 -m gimbalsim.sweep SPEC.yaml --out DIR [--workers N | --scheduler tcp://HOST:PORT] [--resume]
    python3 -m gimbalsim.sweep DIR --replay I --out run.csv [--plot run.png]   # sample I alone (replay.py)

SPEC (YAML):
    scene: tools/scenes/paper_clearance.yaml   # against the spec's folder, then the current directory
    set: {sim.duration: 2.0}                   # overrides for every sample
    samples: 1000
    seed: 7
    parameters:                                # any scene key (dispersion.py lists the distributions)
      contact.clearance: {uniform: [1.0e-4, 8.0e-4]}
      initial.ecc: {disk: {within: contact.clearance, fraction: 0.95}}
    grid:                                      # optional: every grid point gets `samples` draws
      torque.tau2: [5.0, 10.0, 20.0]

A spec naming a controller runs each sample in closed loop and reports the
pointing indices per phase (docs/python.md, "Closed-loop sweeps"; --until
INDEX:PHASE:RELWIDTH [--max-samples N] grows it until an interval is narrow).

Writes DIR/results.csv (one row per sample, sorted by sample), DIR/summary.json
(counts per status, percentiles, the engine's figures; a closed loop's budget),
DIR/plots/ and, in closed loop, DIR/report.md. Sample
i's parameters depend only on (seed, i): the results are the same whatever the
workers, machines, order or resumes (all columns but wall_time). Rows are
journaled to DIR/results.partial.csv as they arrive (appended and synced per
task; never cut in place); --resume runs only the missing samples, after
dropping, counting and rerunning any journal row the sweep could not have
written (not drawn by the design, another fingerprint or applied value, a
figure that is not the writer's finite number).
A sample that kills its worker twice is recorded as `crashed` (its parameters,
no figures) and the sweep goes on (a batch is split to find it).
Exit codes (the project's table, docs/usage.md "Exit codes", mirrored in _errors.py): 0 done (crashed samples included),
2 spec refused, 4 an output not written (the journal kept), 6 the --scheduler did not answer or had no worker
(nothing written), 130 / 143 / 129 interrupted by SIGINT / SIGTERM / SIGHUP (the journal kept).
"""
import contextlib
import math
import os
import pathlib
import socket
import sys
import time

from . import _budget, _budget_report, _cluster, _provenance, _scene_warnings, _study_file, replay
from ._console import keep_console
from ._errors import (EXIT_OK, Interrupted, OutputError, SpecError, exit_program,  # noqa: F401 (SpecError: API)
                      guarded_main)
from ._journal import JOURNAL, csv_line, fmt, read_for_resume, read_journal, record_design  # noqa: F401 (API)
from ._output import (OutputRefused, append_synced, json_text, make_folder, open_append, output_failed, output_set,
                      what_to_do, write_text)
from ._sample import row_values, run_one, sample_alone  # noqa: F401 (sample_alone: API)
from ._spec import check_out_dir
from ._summary import plot, summarize
from ._until import Until
from ._sweep_spec import MAX_SAMPLES, SweepSpec
# FINGERPRINT, check_output_folder, output_paths: the API allocate.py reads the sweep's folder by
from ._sweep_start import (FINGERPRINT, PLOTS, REPORT, RESULTS, SUMMARY, check_output_folder,  # noqa: F401
                           check_start, output_paths, remove_empty_folder, take_design, until_of, write_start)


# ---- one task (runs on a worker) ----

def run_batch(base, closed, items):
    """A task: samples [(i, overrides)] in turn, the C++ runs with the GIL
    released. Returns ([row dict], seconds inside this task, which worker process ran it)."""
    t_task = time.perf_counter()
    _cluster.keep_freed_memory()
    _scene_warnings.quiet()
    cache, rows = {}, []
    for i, overrides in items:
        t0 = time.perf_counter()
        _cluster.crash_hook(i)
        r = run_one(base, closed, overrides, cache)
        r["sample"] = i
        r["wall_time"] = time.perf_counter() - t0
        rows.append(r)
    return rows, time.perf_counter() - t_task, f"{socket.gethostname()}:{os.getpid()}"


# ---- the sweep ----

def finished_rows(spec, out):
    """The rows of the finished sweep in out, each checked as --resume checks
    a row (_journal.read_journal), or None when it is not whole: a journal
    left, a sample missing, or a row the sweep could not have written."""
    if (out / JOURNAL).exists() or not (out / RESULTS).is_file():
        return None
    done, dropped, _ = read_journal(spec, out / RESULTS, spec.csv_header())
    return None if dropped or len(done) != len(spec.design) else [done[i] for i in sorted(done)]


def sweep(spec, out, workers=None, scheduler=None, resume=False, batch=None, progress=True, until=None,
          cluster=None):
    """Runs spec into out; cluster: a (client, workers) already open (gimbalsim.allocate keeps one for
    all its sweeps), else one is started (--workers) or reached (--scheduler) here."""
    header = spec.csv_header()
    inputs = spec.input_files()
    write = lambda path, text: write_text(path, text, inputs)  # noqa: E731
    journal = out / JOURNAL
    results = out / RESULTS
    check_start(spec, out, resume, inputs)  # --check's own refusals
    engine, grown = {"ran_this_invocation": 0}, None
    if spec.sampling["overrides"]:  # said when the runs step otherwise than the scene is written
        print(f"sweep: stepping (sampling: {spec.sampling['mode']}): {spec.sampling['why']}", file=sys.stderr)
    with contextlib.ExitStack() as stack:
        # A named scheduler is reached before anything is written: one that does not answer (exit 6) leaves
        # --out as it was, not a journal the next run would want resumed. The local cluster starts for the
        # first sample to run; either is kept for every round of --until.
        if cluster is None and scheduler:
            cluster = stack.enter_context(_cluster.dask_client(None, scheduler))
        made = make_folder(out)
        _study_file.hold(out)  # before the journal is read: another sweep may be writing it
        take_design(spec, out, until)  # the samples --until added before (a resume holds them, no more)
        # the journal's rows, and results.csv's too when a resume finds one (a finished sweep resumed)
        done, dropped_in, appendable = read_for_resume(spec, journal, results, header)
        dropped = {}
        write_start(spec, out, write, [done[i] for i in sorted(done)], appendable, made)
        for read_from, reasons in dropped_in:
            for why, numbers in reasons.items():
                dropped[why] = dropped.get(why, []) + numbers
                n, shown = len(numbers), ", ".join(map(str, numbers[:10])) + (" ..." if len(numbers) > 10 else "")
                kind = "journal row" if read_from == journal else "row"
                # a sample outside the design is no sample of this sweep: nothing runs for it (pass 42)
                again = ("the same row kept once" if why.startswith("sample already") else
                         "not samples of this design: nothing runs for them" if why.endswith("outside the design")
                         else "their samples run again")
                print(f"sweep: dropped {n} {kind}{'s' * (n != 1)} ({why}) at {read_from} line{'s' * (n != 1)} "
                      f"{shown}; {again}", file=sys.stderr)
        while True:
            todo = [i for i in range(len(spec.design)) if i not in done]
            print(f"sweep: {len(spec.design)} samples, {len(done)} already done, {len(todo)} to run",
                  file=sys.stderr)
            if todo:
                if cluster is None:
                    cluster = stack.enter_context(_cluster.dask_client(workers, scheduler))
                fd = open_append(journal)  # unbuffered: a failed write leaves nothing behind to fail again at close
                try:
                    engine = _merge(engine, _run_on_cluster(spec, todo, fd, journal, done, cluster, batch, progress))
                finally:
                    os.close(fd)
                _cluster.raise_if_interrupted()
            rows = [[str(v) for v in done[i]] for i in sorted(done) if i < len(spec.design)]
            if until is None:
                break
            stop, grown = until.check(spec, rows)
            if stop:
                break
            until.grow(spec)
            record_design(out, spec, write)
    # The report is one set: stopped or failed part-way, none of it is left (the journal holds
    # every row, and --resume writes the whole set), nor the plots folder it made.
    plots_was_there = (out / PLOTS).exists()
    with contextlib.ExitStack() as report:
        report.callback(lambda: plots_was_there or remove_empty_folder(out / PLOTS))
        report.enter_context(output_set())
        write(results, "".join(csv_line(r) for r in [header] + rows))
        summary = summarize(spec, rows, engine)
        summary["journal_rows_dropped"] = {why: len(numbers) for why, numbers in dropped.items()}
        if grown is not None:
            summary["until"] = grown
        if spec.closed:
            summary["report"] = str(write_report(spec, rows, summary, out, inputs))
        summary["plots"] = [str(p) for p in _plots(lambda: plot(spec, rows, out / PLOTS, inputs), out)]
        write(out / SUMMARY, json_text(summary))
    journal.unlink()
    return summary


def _merge(a, b):
    """The engine figures of two rounds of --until as one."""
    if not a.get("ran_this_invocation"):
        return b
    ran = a["ran_this_invocation"] + b["ran_this_invocation"]
    elapsed = a["elapsed_s"] + b["elapsed_s"]
    return {**b, "tasks": a["tasks"] + b["tasks"], "ran_this_invocation": ran, "elapsed_s": elapsed,
            "samples_per_s": ran / elapsed if elapsed > 0 else None}


def _plots(draw, out):
    """draw(): the plots written into OUT/plots (made there if missing); a
    folder that cannot be made is an OutputError as a plot not written is."""
    try:
        return draw()
    except OutputError:
        raise
    except OSError as e:
        raise output_failed(f"cannot write the plots in {out / PLOTS}: {e.strerror or e}", e) from None


def write_report(spec, rows, summary, out, inputs=()):
    """OUT/report.md and its CDF plots (closed loop)."""
    plots = _plots(lambda: _budget_report.cdf_plots(spec, rows, summary["budget"], out / PLOTS,
                                                    inputs=inputs), out)
    text = _budget_report.body(spec, rows, summary["budget"], plots, summary["engine"])
    write_text(out / REPORT, text, inputs)
    return out / REPORT


def crashed(i):
    """The row of a sample whose task killed its worker process twice: its
    parameters, status `crashed`, no figures."""
    return {"sample": i, "status": "crashed", "wall_time": math.nan}


def _run_on_cluster(spec, todo, fd, journal, done, cluster, batch, progress):
    """Runs the samples todo on cluster = (client, n_workers), appending each
    task's rows to the journal as they arrive; the engine's figures."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker
    from tqdm import tqdm

    client, n_workers = cluster
    # about 8 tasks per worker, at most 10 samples each: rows arrive often and a killed worker loses little
    size = batch or max(1, min(10, math.ceil(len(todo) / (n_workers * 8))))
    chunks = _cluster.task_chunks(todo, size, n_workers, guided=batch is None)
    # the base scene (2 kB) goes in each task, not scattered: scattered data dies with the workers
    # holding it, and the tasks needing it then fail; a task's own arguments are resent on a retry
    t0 = time.perf_counter()
    warm = _cluster.warm_up(client, run_batch, spec.base, spec.closed, [])  # [s] each worker's import, once
    submit = lambda c: client.submit(run_batch, spec.base, spec.closed, [(i, spec.design.draw(i)) for i in c],
                                     pure=False)
    samples_of = {}  # future -> the samples it runs
    for c in chunks:
        samples_of[submit(c)] = c
    bar = tqdm(total=len(todo), unit="sample", disable=not progress, file=sys.stderr, smoothing=0.1)
    inside, ran, last_done = 0.0, 0, {}  # last_done: worker -> when its last task's rows arrived
    try:
        tasks = as_completed(list(samples_of))
        for fut in tasks:
            samples = samples_of.pop(fut)
            try:
                results, t_task, worker = fut.result()
                last_done[worker] = time.perf_counter()
            except KilledWorker:
                if alone := _cluster.rerun_alone(samples, submit):
                    for f, c in alone:
                        samples_of[f] = c
                        tasks.add(f)
                    fut.release()
                    continue
                results, t_task = [crashed(samples[0])], 0.0
            inside += t_task
            lines = {}
            for r in results:
                if r["sample"] not in done:
                    lines[r["sample"]] = [fmt(v) for v in row_values(spec, spec.design.draw(r["sample"]), r)]
            # a task's rows in one append, synced: a cut can only tear the last line
            append_synced(fd, "".join(csv_line(line) for line in lines.values()).encode(), journal)
            done.update(lines)
            ran += len(lines)
            bar.update(len(results))
            fut.release()
    finally:
        bar.close()
    t_end = time.perf_counter()
    elapsed = t_end - t0
    # a worker idle after its last task had nothing left to run: no engine spent that time (tasks of 5 units
    # of 0.5 s left one of two workers up to 2.5 s idle at the end, read as 40 ms of overhead per sample)
    # of n_workers at most (a worker a crash replaced has an older last task and a new name)
    drain = sum(t_end - t for t in sorted(last_done.values())[-n_workers:])
    w = spec.header().index("wall_time")
    times = [t for t in (float(done[i][w]) for i in todo) if math.isfinite(t)]  # crashed: nan
    run_time = sum(times)
    return {"workers": n_workers, "batch": size, "tasks": len(chunks), "ran_this_invocation": ran,
            "elapsed_s": elapsed, "samples_per_s": ran / elapsed if elapsed > 0 else None,
            "mean_run_s": run_time / len(times) if times else None,
            # time the workers were busy with something other than our tasks while tasks were left, per sample
            "engine_overhead_per_sample_s": (elapsed * n_workers - inside - drain - warm * n_workers) / ran
            if ran else None,
            "drain_idle_per_sample_s": drain / ran if ran else None, "warm_up_s": warm,
            "task_overhead_per_sample_s": (inside - run_time) / ran if ran else None}


def _kept(out):
    """Samples in the journal now (for the one line after an interruption); None when there is no journal."""
    try:
        return max(0, (out / JOURNAL).read_bytes().count(b"\n") - 1)
    except OSError:
        return None


def _kept_and_next(out, first):
    """What a stopped sweep kept and how to go on: "<first>" is what to do before running again. Without a
    journal nothing is kept and a resume has nothing to resume (it said "0 samples kept in" a missing file)."""
    n = _kept(out)
    if n is None:
        return f"nothing kept ({out / JOURNAL} was not written); {first}run again"
    return f"{n} samples kept in {out / JOURNAL}; {first}run again with --resume"


def main(argv=None):
    ap = _cluster.program_parser("sweep", __doc__, "sweep spec (YAML); with --replay, the sweep's output directory",
                                 "output directory; with --replay, the time series CSV")
    ap.add_argument("--replay", type=_cluster.whole_number, default=None, metavar="I",
                    help="run sample I of the sweep in SPEC alone")
    ap.add_argument("--plot", type=_cluster.path_text, default=None,
                    help="with --replay: the plot (default: --out with .png)")
    ap.add_argument("--resume", action="store_true", help="finish an interrupted sweep in --out")
    ap.add_argument("--batch", type=_cluster.whole_number, default=None,
                    help=f"samples per task, in [1, {MAX_SAMPLES}] (default: about 8 tasks per worker, at most 10)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    ap.add_argument("--check", action="store_true",
                    help="check the spec and --out, run and write nothing (exit 0 or 2)")
    ap.add_argument("--until", metavar="INDEX:PHASE:RELWIDTH",
                    help="closed loop: add batches of the spec's samples until the index's confidence interval in "
                         "the phase is at most RELWIDTH of its value (e.g. ape:track:0.2), or --max-samples")
    ap.add_argument("--max-samples", type=_cluster.whole_number, default=None,
                    help="with --until: the cap (default: 20 times the spec's samples)")
    a = ap.parse_args(argv)
    if a.max_samples is not None and (a.until is None or not 1 <= a.max_samples <= MAX_SAMPLES):
        ap.error(f"--max-samples goes with --until, and must be in [1, {MAX_SAMPLES}]")
    if a.batch is not None and not 1 <= a.batch <= MAX_SAMPLES:  # no sweep has more samples to put in a task
        ap.error(f"--batch must be in [1, {MAX_SAMPLES}]")
    # --replay runs one sample here and now: a flag of the sweep would be silently ignored.
    sweep_only = [f for f, v in (("--resume", a.resume), ("--until", a.until), ("--max-samples", a.max_samples),
                                 ("--batch", a.batch), ("--workers", a.workers), ("--scheduler", a.scheduler),
                                 ("--check", a.check))
                  if v not in (None, False)]
    if a.replay is not None and sweep_only:
        ap.error(f"--replay runs one sample in this process: not with {', '.join(sweep_only)} (flags of a sweep)")
    if a.replay is None and a.plot is not None:
        ap.error("--plot goes with --replay (a sweep's plots are in --out/plots)")
    _cluster.raise_on_signals()
    _scene_warnings.quiet()
    if a.replay is not None:
        return replay.main(a.spec, a.replay, a.out, a.plot)
    out = pathlib.Path(a.out)
    return guarded_main("sweep", lambda: _run(a, out), {
        # a name refused at the end (a link made while the sweep ran): more space would not help
        OutputRefused: lambda e: f"; {_kept_and_next(out, 'move it out of --out and ')}",
        OutputError: lambda e: f"; {_kept_and_next(out, what_to_do(e))}",
        Interrupted: lambda e: f": {_kept_and_next(out, '')} to finish"})


def _run(a, out):
    """The sweep of the command line a, its lines on the console; EXIT_OK
    (what goes wrong is raised, for guarded_main's exit code)."""
    check_out_dir(a.out, a.spec)
    spec = SweepSpec(a.spec)
    until = until_of(a.until, a.max_samples, spec)
    if a.resume and not out.is_dir():  # (pass 49) it started afresh, as tune's --resume did not
        raise SpecError(f"{out}: no such folder: no sweep to resume; run without --resume")
    if a.check:  # every refusal of the run, in its order (sweep() calls check_start first), nothing written
        _study_file.hold(out, keep=False)
        check_start(spec, out, a.resume, spec.input_files())
        take_design(spec, out, until)
        return EXIT_OK
    s = sweep(spec, out, a.workers, a.scheduler, a.resume, a.batch, not a.no_progress, until)
    e = s["engine"]
    if s["status"].get("crashed"):
        n = s["status"]["crashed"]
        print(f"sweep: {n} crashed sample{'s' * (n != 1)} (each killed a worker process twice): status crashed "
              f"in results.csv, with the parameters; the other samples ran", file=sys.stderr)
    if s["applied_differs"]:
        print(f"sweep: {s['applied_differs']} sample(s) ran with a value the scene changed from the drawn one: "
              f"see column {_provenance.DIFFERS} in results.csv", file=sys.stderr)
    if spec.closed:
        print(f"sweep: {s['samples']} samples, status {s['status']}; results in {a.out}/results.csv, report in "
              f"{s['report']}", file=sys.stderr)
        print("\n".join("sweep: " + line for line in _budget.console_lines(s["budget"])), file=sys.stderr)
        if "until" in s:
            u = s["until"]
            print(f"sweep: --until {u['until']}: stopped by the {u['stopped_by']} at {u['samples']} samples "
                  f"(relative width {Until.width_text(u)}, target {u['relative_width_target']:.3g})",
                  file=sys.stderr)
    else:
        pct = s["percentiles_of_ok_samples"]["pointing_error_max"]
        figure = (f"p50 {pct['p50']:.3e} p99 {pct['p99']:.3e} rad" if pct else
                  f"n/a ({s['percentiles_of_ok_samples_note']['pointing_error_max']})")
        print(f"sweep: {s['samples']} samples, status {s['status']}; pointing_error_max {figure}; "
              f"results in {a.out}/results.csv", file=sys.stderr)
    if e.get("ran_this_invocation"):
        rate = "n/a" if e["samples_per_s"] is None else f"{e['samples_per_s']:.1f}/s"
        # a crashed sample has no run time: none of the invocation's samples may have one
        mean = "n/a (every sample it ran crashed)" if e["mean_run_s"] is None else f"{e['mean_run_s'] * 1e3:.1f} ms"
        print(f"sweep: {e['ran_this_invocation']} samples in {e['elapsed_s']:.1f} s on {e['workers']} "
              f"worker{'s' * (e['workers'] != 1)} ({rate}); mean run {mean}, engine overhead "
              f"{e['engine_overhead_per_sample_s'] * 1e3:.2f} ms per sample", file=sys.stderr)
    return EXIT_OK


if __name__ == "__main__":
    keep_console()  # a console whose reader is gone stops nothing, --help included
    exit_program("sweep", main)
