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

Writes DIR/results.csv (one row per sample, sorted by sample), DIR/summary.json
(counts per status, percentiles, the engine's figures) and DIR/plots/. Sample
i's parameters depend only on (seed, i): the results are the same whatever the
workers, machines, order or resumes (all columns but wall_time). Rows are
journaled to DIR/results.partial.csv as they arrive (appended and synced per
task; never cut in place); --resume runs only the missing samples, after
dropping, counting and rerunning any journal row the design did not draw.
A sample that kills its worker twice is recorded as `crashed` (its parameters,
no figures) and the sweep goes on (a batch is split to find it).
Exit codes: 0 done (crashed samples included), 2 spec refused, 4 an output not written (the journal
kept), 130 / 143 interrupted by SIGINT / SIGTERM (the journal kept).
"""
import argparse
import csv
import io
import json
import math
import os
import pathlib
import sys
import time

import numpy as np

import gimbalsim
from . import _cluster, _provenance
from ._spec import Spec, SpecError, check_out_dir
from .dispersion import Design, check_within, design_size, parse_parameter

METRICS = ["pointing_error_max", "pointing_error_final", "peak_contact_force", "peak_joint2_force", "impacts",
           "continuous_contact_from"]
METRIC_UNITS = {"pointing_error_max": "rad", "pointing_error_final": "rad", "peak_contact_force": "N",
                "peak_joint2_force": "N", "impacts": "", "continuous_contact_from": "s", "wall_time": "s"}
JOURNAL = "results.partial.csv"
MAX_SAMPLES = 10_000_000


# ---- the spec ----

class SweepSpec:
    """A checked sweep spec: the base scene (file + set), the design, and a
    fingerprint that a resume must match."""

    def __init__(self, path, folder=None):
        spec = Spec(path, folder)  # folder: where its paths are read from (a replay's copy: the original's)
        spec.check_keys({"scene", "set", "samples", "seed", "parameters", "grid"})
        root = spec.root.value
        for required in ("scene", "samples", "seed"):
            if required not in root:
                spec.refuse(required, "missing")
        self.scene_path = spec.path_of("scene", root["scene"])
        self.samples = spec.integer("samples", root["samples"], 1, MAX_SAMPLES)
        self.seed = spec.integer("seed", root["seed"], 0, 2**63 - 1)
        key_types = {k["key"]: k["type"] for k in gimbalsim.keys()}
        sets = spec.mapping("set", root["set"]) if "set" in root else {}
        for key, node in sets.items():
            if key not in key_types:
                spec.refuse(f"set.{key}", "not a key of the scene", node)
        self.set = {k: spec.value(f"set.{k}", n) for k, n in sets.items()}
        params = spec.mapping("parameters", root["parameters"]) if "parameters" in root else {}
        grid = spec.mapping("grid", root["grid"]) if "grid" in root else {}
        self.grid = []
        for key, node in grid.items():
            if key not in key_types:
                spec.refuse(f"grid.{key}", "not a key of the scene", node)
            if key in params:
                spec.refuse(f"grid.{key}", "also under parameters: give it in one place", node)
            if not isinstance(node.value, list) or not node.value:
                spec.refuse(f"grid.{key}", "expected a non-empty list of values", node)
            self.grid.append((key, [spec.value(f"grid.{key}", v) for v in node.value]))
        # counted before anything is built or tried: a grid can multiply to more than memory holds
        size = design_size(self.grid, self.samples)
        if size > MAX_SAMPLES:
            spec.refuse("grid" if self.grid else "samples",
                        f"{size} samples in all (samples x grid points), more than the limit {MAX_SAMPLES}",
                        root["grid"] if self.grid else root["samples"])
        try:
            self.base = gimbalsim.load_scene(self.scene_path, self.set,
                                             sources={k: (spec.path, n.line) for k, n in sets.items()})
        except gimbalsim.SceneError as e:
            node = sets.get(e.key) if e.set_index else None
            spec.refuse(f"set.{e.key}" if node else "scene", str(e), node or root["scene"])
        self.parameters = [parse_parameter(spec, "parameters", k, n, key_types) for k, n in params.items()]
        if not self.parameters and not self.grid:
            spec.refuse("parameters", "nothing is dispersed: give parameters or grid")
        check_within(spec, "parameters", self.parameters, [k for k, _ in self.grid], self.base.values())
        # Values the scene would refuse are refused now, at the spec's line.
        for p in self.parameters:
            for v in p.extremes():
                self._try(spec, f"parameters.{p.key}", {p.key: v}, p.node)
        for (key, values), node in zip(self.grid, grid.values()):
            for v in values:
                self._try(spec, f"grid.{key}", {key: v}, node)
        self.design = Design(self.parameters, self.grid, self.samples, self.seed, self.base.values())
        self.spec_path = spec.path
        self.spec_text, self.spec_folder = spec.source_text, spec.folder.absolute()  # for the replay's copy
        self.fingerprint = json.dumps({"scene": self.base.values(), "seed": self.seed, "samples": self.samples,
                                       "parameters": {p.key: [p.kind, p.args] for p in self.parameters},
                                       "grid": self.grid}, sort_keys=True)

    def _try(self, spec, where, overrides, node):
        try:
            self.base.replace(overrides, sources={k: (spec.path, node.line) for k in overrides})
        except gimbalsim.SceneError as e:
            spec.refuse(where, f"the scene refuses {overrides}: {e.problems[0]['text'] if e.problems else e}", node)

    def header(self):
        """The columns by the names the code uses (scene keys, metric names)."""
        return ["sample"] + self.design.columns() + ["status"] + METRICS + ["wall_time"] + _provenance.columns(self)

    def csv_header(self):
        """header() as the journal and results.csv name it: the project's CSV
        convention (docs/usage.md), e.g. contact.clearance -> contact_clearance_m."""
        units = {k["key"]: k["unit"] for k in gimbalsim.keys()}
        csv_name = gimbalsim._gimbalsim.csv_name
        names = ["sample"]
        for c in self.design.columns():  # "initial.ecc[0]" -> initial_ecc_0_m
            plain = c.replace(".", "_").replace("[", "_").replace("]", "")
            names.append(csv_name(plain, units.get(c.split("[")[0], "")))
        return (names + ["status"] + [csv_name(m, METRIC_UNITS[m]) for m in METRICS + ["wall_time"]]
                + _provenance.csv_names(self, csv_name, units))


# ---- one sample (runs on a worker) ----

def _bore_angles(a, b):
    """Angle [rad] between the boresight rows of two runs, row by row."""
    i = [gimbalsim.COLUMNS.index(c) for c in ("bore_x", "bore_y", "bore_z")]
    n = min(len(a), len(b))
    u, v = a[:n][:, i], b[:n][:, i]
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))


def run_sample(base, overrides, ideal_cache, keep=None):
    """Sample's metrics: status and METRICS (dict), and `applied`: the
    dispersed keys as the loaded scene holds them (_provenance.applied). The
    ideal-joint run with the same parameters is the pointing reference
    (cached: it does not depend on the joint's parameters). keep (a dict), if
    given, gets the run."""
    try:
        scene = base.replace(overrides)
    except gimbalsim.SceneError as e:
        return {"status": f"refused:{e.key or ''}"}
    applied = _provenance.applied(scene.values(), overrides)  # as loaded, not as drawn
    run = gimbalsim.simulate(scene)
    if keep is not None:
        keep["run"] = run
    ideal = scene.replace({"structure.joint2": "ideal"})
    key = tuple(sorted(ideal.values().items()))
    if key not in ideal_cache:
        ideal_cache[key] = gimbalsim.simulate(ideal).rows
    err = _bore_angles(run.rows, ideal_cache[key])
    s = run.summary
    status = "ok" if run.ok else (s["stop"]["key"] or s["stop"]["step_status"].replace(" ", "_"))
    return {"status": status, "applied": applied,
            "pointing_error_max": float(err.max()) if len(err) else math.nan,
            "pointing_error_final": float(err[-1]) if len(err) else math.nan,
            "peak_contact_force": s["peak_contact_force_N"],
            "peak_joint2_force": s["peak_joint2_force_N"],
            "impacts": s["impacts"],
            "continuous_contact_from": s["continuous_contact_from_s"]}


def run_batch(base, items):
    """A task: samples [(i, overrides)] in turn, the C++ runs with the GIL
    released. Returns ([row dict], seconds inside this task)."""
    t_task = time.perf_counter()
    cache, rows = {}, []
    for i, overrides in items:
        t0 = time.perf_counter()
        _cluster.crash_hook(i)
        r = run_sample(base, overrides, cache)
        r["sample"] = i
        r["wall_time"] = time.perf_counter() - t0
        rows.append(r)
    return rows, time.perf_counter() - t_task


# ---- results ----

def fmt(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "nan" if math.isnan(v) else repr(v)
    return str(v)


def csv_line(values):
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\n").writerow([fmt(v) for v in values])
    return buf.getvalue()


def row_values(spec, values, result):
    return [result["sample"]] + spec.design.row_values(values) + [result["status"]] + \
        [result.get(m) for m in METRICS] + [result["wall_time"]] + \
        _provenance.values(spec, result)


def sample_alone(spec, i):
    """Sample i of the spec run alone in this process, as a worker runs it:
    its row as results.csv holds it (text) and the run it made (None when the
    scene refused the sample). The seam of --replay (replay.py)."""
    values = spec.design.draw(i)
    keep = {}
    t0 = time.perf_counter()
    r = run_sample(spec.base, values, {}, keep)
    r["sample"], r["wall_time"] = i, time.perf_counter() - t0
    return [fmt(v) for v in row_values(spec, values, r)], keep.get("run")


class OutputError(Exception):
    """An output could not be written (exit 4); what was journaled is kept."""


def _is_float(text):
    try:
        float(text)
        return True
    except ValueError:
        return False


def check_row(spec, row, n_columns):
    """Why a journal row is not to be trusted, or None: the sample index in
    range, the parameters equal to the design's draw, the figures numbers."""
    if len(row) != n_columns:
        return "wrong number of columns"
    if not row[0].isdigit() or not int(row[0]) < len(spec.design):
        return "sample index outside the design"
    i = int(row[0])
    drawn = [fmt(v) for v in spec.design.row_values(spec.design.draw(i))]
    if row[1:1 + len(drawn)] != drawn:
        return "parameters differ from the design's draw"
    figures = row[2 + len(drawn):n_columns - len(_provenance.columns(spec))]
    if not row[1 + len(drawn)] or not all(v == "" or _is_float(v) for v in figures) or not _is_float(figures[-1]):
        return "status or figures unreadable"
    return None


def read_journal(spec, path, header):
    """The journal's trusted rows by sample, what was dropped ({reason:
    count}), and whether the file can be appended to as it is. A last line
    without its newline (cut by an interruption) is dropped; a sample written
    twice counts once."""
    done, dropped = {}, {}
    if not path.exists():
        return done, dropped, False
    try:
        data = path.read_bytes()
    except OSError as e:
        raise OutputError(f"cannot read the journal {path}: {e.strerror}")
    lines = data.decode("utf-8", errors="replace").split("\n")
    torn = lines.pop() != ""  # the text after the last newline: empty when the last write was whole
    if torn:
        dropped["last line cut by an interruption"] = 1
    if not lines:  # killed before the header was whole: nothing was journaled
        return done, dropped, False
    if next(csv.reader(lines[:1]), None) != header:
        raise SpecError(f"{path} was written by another spec (its header differs); use another --out")
    for row in csv.reader(lines[1:]):
        why = check_row(spec, row, len(header))
        if why is None and int(row[0]) in done:
            why = "sample already journaled" if row == done[int(row[0])] else "sample journaled twice, differently"
        if why is not None:
            dropped[why] = dropped.get(why, 0) + 1
            continue
        done[int(row[0])] = row
    return done, dropped, not dropped


def write_atomic(path, text):
    """Writes text to path whole or not at all: a temporary file beside it,
    synced, then renamed over it (the folder synced too, for a power cut)."""
    tmp = path.with_name(path.name + ".tmp")
    try:
        with open(tmp, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
        fd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
    except OSError as e:
        try:
            tmp.unlink()
        except OSError:
            pass
        raise OutputError(f"cannot write {path}: {e.strerror or e}") from None


def percentiles(x):
    x = np.asarray([v for v in x if v is not None and math.isfinite(v)], dtype=float)
    if not len(x):
        return None
    return {"p50": float(np.percentile(x, 50)), "p90": float(np.percentile(x, 90)),
            "p99": float(np.percentile(x, 99)), "max": float(x.max()), "n": int(len(x))}


def summarize(spec, rows, engine):
    header = spec.header()
    col = {c: header.index(c) for c in header}
    status = {}
    for r in rows:
        status[r[col["status"]]] = status.get(r[col["status"]], 0) + 1
    ok = [r for r in rows if r[col["status"]] == "ok"]
    num = lambda r, c: float(r[col[c]]) if r[col[c]] not in ("", "nan") else None
    return {"spec": str(spec.spec_path), "scene": str(spec.scene_path), "samples": len(rows), "status": status,
            "percentiles_of_ok_samples": {m: percentiles([num(r, m) for r in ok]) for m in METRICS + ["wall_time"]},
            "fingerprints": _provenance.fingerprints(spec),
            "applied_differs": sum(1 for r in rows if r[col[_provenance.DIFFERS]]),
            "engine": engine}


def plot(spec, rows, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    header = spec.header()
    col = {c: header.index(c) for c in header}
    ok = [r for r in rows if r[col["status"]] == "ok"]
    if not ok:
        return []
    out.mkdir(parents=True, exist_ok=True)
    written = []
    val = lambda c: np.array([float(r[col[c]]) for r in ok])
    for metric, unit, name in (("pointing_error_max", "rad", "pointing_error"),
                               ("peak_joint2_force", "N", "peak_force")):
        x = np.sort(val(metric))
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].hist(x, bins=min(50, max(5, len(x) // 10)))
        ax[0].set_xlabel(f"{metric} [{unit}]")
        ax[0].set_ylabel("samples")
        ax[1].step(x, np.arange(1, len(x) + 1) / len(x), where="post")
        ax[1].set_xlabel(f"{metric} [{unit}]")
        ax[1].set_ylabel("empirical CDF")
        ax[1].axhline(0.99, ls=":", c="gray")
        fig.suptitle(f"{len(x)} samples ({spec.scene_path.name})")
        fig.tight_layout()
        written.append(out / f"{name}_distribution.png")
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
    for c in spec.design.columns():
        try:
            x = val(c)
        except ValueError:  # names (a choice of strings): no axis
            continue
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(x, val("pointing_error_max"), ".", ms=3)
        ax.set_xlabel(c)
        ax.set_ylabel("pointing_error_max [rad]")
        fig.tight_layout()
        written.append(out / f"pointing_error_vs_{c.replace('[', '_').replace(']', '')}.png")
        fig.savefig(written[-1], dpi=110)
        plt.close(fig)
    return written


# ---- the sweep ----

def sweep(spec, out, workers=None, scheduler=None, resume=False, batch=None, progress=True):
    header = spec.csv_header()
    journal = out / JOURNAL
    results = out / "results.csv"
    fingerprint = out / "spec.json"
    if resume:
        try:
            same = not fingerprint.exists() or fingerprint.read_text() == spec.fingerprint
        except (OSError, UnicodeDecodeError) as e:
            raise SpecError(f"{fingerprint}: cannot read it ({e}); --resume needs the spec it names")
        if not same:
            raise SpecError(f"{out} holds a sweep of another spec; --resume needs the same spec")
    elif journal.exists() or results.exists():
        raise SpecError(f"{out} already holds a sweep: give --resume to finish it, or another --out")
    done, dropped, appendable = read_journal(spec, journal, header)
    if results.exists() and resume and not done and not dropped:
        done, dropped, _ = read_journal(spec, results, header)
        appendable = False
    try:
        out.mkdir(exist_ok=True)  # its own folder only: the one it goes in was checked
    except OSError as e:
        raise OutputError(f"cannot make the folder {out}: {e.strerror}") from None
    write_atomic(fingerprint, spec.fingerprint)
    _provenance.record_inputs(spec, out, write_atomic)
    if not appendable:
        # The journal is never cut in place: its trusted rows go to a new file that replaces it whole.
        write_atomic(journal, "".join(csv_line(r) for r in [header] + [done[i] for i in sorted(done)]))
    todo = [i for i in range(len(spec.design)) if i not in done]
    for why, n in dropped.items():
        print(f"sweep: dropped {n} journal row{'s' * (n != 1)} ({why}); their samples run again", file=sys.stderr)
    print(f"sweep: {len(spec.design)} samples, {len(done)} already done, {len(todo)} to run", file=sys.stderr)
    engine = {"ran_this_invocation": 0}
    if todo:
        try:  # unbuffered: a failed write leaves nothing behind to fail again at close
            fd = os.open(journal, os.O_WRONLY | os.O_APPEND)
        except OSError as e:
            raise OutputError(f"cannot open the journal {journal}: {e.strerror}") from None
        try:
            engine = _run_on_cluster(spec, todo, fd, journal, done, workers, scheduler, batch, progress)
        finally:
            os.close(fd)
    rows = [done[i] for i in sorted(done)]
    rows = [[str(v) for v in r] for r in rows]
    write_atomic(results, "".join(csv_line(r) for r in [header] + rows))
    summary = summarize(spec, rows, engine)
    summary["journal_rows_dropped"] = dropped
    try:
        summary["plots"] = [str(p) for p in plot(spec, rows, out / "plots")]
    except OSError as e:
        raise OutputError(f"cannot write the plots in {out / 'plots'}: {e.strerror}") from None
    write_atomic(out / "summary.json", json.dumps(summary, indent=2) + "\n")
    journal.unlink()
    return summary


def crashed(i):
    """The row of a sample whose task killed its worker process twice: its
    parameters, status `crashed`, no figures."""
    return {"sample": i, "status": "crashed", "wall_time": math.nan}


def _run_on_cluster(spec, todo, fd, journal, done, workers, scheduler, batch, progress):
    from distributed import as_completed
    from distributed.scheduler import KilledWorker
    from tqdm import tqdm

    with _cluster.dask_client(workers, scheduler) as (client, n_workers):
        # about 8 tasks per worker, at most 10 samples each: rows arrive often and a killed worker loses little
        size = batch or max(1, min(10, math.ceil(len(todo) / (n_workers * 8))))
        chunks = [todo[k:k + size] for k in range(0, len(todo), size)]
        # the base scene (2 kB) goes in each task, not scattered: scattered data dies with the workers
        # holding it, and the tasks needing it then fail; a task's own arguments are resent on a retry
        t0 = time.perf_counter()
        submit = lambda c: client.submit(run_batch, spec.base, [(i, spec.design.draw(i)) for i in c], pure=False)
        samples_of = {}  # future -> the samples it runs
        for c in chunks:
            samples_of[submit(c)] = c
        bar = tqdm(total=len(todo), unit="sample", disable=not progress, file=sys.stderr, smoothing=0.1)
        inside, ran = 0.0, 0
        try:
            tasks = as_completed(list(samples_of))
            for fut in tasks:
                samples = samples_of.pop(fut)
                try:
                    results, t_task = fut.result()
                except KilledWorker:
                    if len(samples) > 1:  # which sample killed it? each runs alone, so only that one is crashed
                        for i in samples:
                            f = submit([i])
                            samples_of[f] = [i]
                            tasks.add(f)
                        fut.release()
                        continue
                    results, t_task = [crashed(samples[0])], 0.0
                inside += t_task
                lines = {}
                for r in results:
                    if r["sample"] not in done:
                        lines[r["sample"]] = [fmt(v) for v in row_values(spec, spec.design.draw(r["sample"]), r)]
                try:  # a task's rows in one append, synced: a cut can only tear the last line
                    data = "".join(csv_line(line) for line in lines.values()).encode()
                    while data:
                        data = data[os.write(fd, data):]
                    os.fsync(fd)
                except OSError as e:
                    raise OutputError(f"cannot write the journal {journal}: {e.strerror}") from None
                done.update(lines)
                ran += len(lines)
                bar.update(len(results))
                fut.release()
        finally:
            bar.close()
        elapsed = time.perf_counter() - t0
    w = spec.header().index("wall_time")
    times = [t for t in (float(done[i][w]) for i in todo) if math.isfinite(t)]  # crashed: nan
    run_time = sum(times)
    return {"workers": n_workers, "batch": size, "tasks": len(chunks), "ran_this_invocation": ran,
            "elapsed_s": elapsed, "samples_per_s": ran / elapsed if elapsed > 0 else None,
            "mean_run_s": run_time / len(times) if times else None,
            # time the workers were busy with something other than our tasks, per sample
            "engine_overhead_per_sample_s": (elapsed * n_workers - inside) / ran if ran else None,
            "task_overhead_per_sample_s": (inside - run_time) / ran if ran else None}


def _kept(out):
    """Samples in the journal now (for the one line after an interruption)."""
    try:
        return max(0, (out / JOURNAL).read_bytes().count(b"\n") - 1)
    except OSError:
        return 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m gimbalsim.sweep", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--version", action="version", version="gimbalsim.sweep " + gimbalsim.__version__)
    ap.add_argument("spec", help="sweep spec (YAML); with --replay, the sweep's output directory")
    ap.add_argument("--out", required=True, help="output directory; with --replay, the time series CSV")
    ap.add_argument("--replay", type=int, default=None, metavar="I", help="run sample I of the sweep in SPEC alone")
    ap.add_argument("--plot", default=None, help="with --replay: the plot (default: --out with .png)")
    _cluster.add_cluster_arguments(ap)
    ap.add_argument("--resume", action="store_true", help="finish an interrupted sweep in --out")
    ap.add_argument("--batch", type=int, default=None, help="samples per task (default: about 8 tasks per worker, at most 10)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)
    if a.workers is not None and a.workers < 1:
        ap.error("--workers must be >= 1")
    if a.batch is not None and a.batch < 1:
        ap.error("--batch must be >= 1")
    _cluster.raise_on_signals()
    if a.replay is not None:
        from . import replay
        return replay.main(a.spec, a.replay, a.out, a.plot)
    out = pathlib.Path(a.out)
    try:
        check_out_dir(a.out, a.spec)
        spec = SweepSpec(a.spec)
        s = sweep(spec, out, a.workers, a.scheduler, a.resume, a.batch, not a.no_progress)
    except SpecError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except OutputError as e:
        print(f"error: {e}; {_kept(out)} samples kept in {out / JOURNAL}: free the space and run again with "
              f"--resume", file=sys.stderr)
        return 4
    except _cluster.Interrupted as e:
        print(f"sweep: interrupted ({e}): {_kept(out)} samples kept in {out / JOURNAL}; run again with "
              f"--resume to finish", file=sys.stderr)
        return 128 + e.signum
    e = s["engine"]
    pct = s["percentiles_of_ok_samples"]["pointing_error_max"]
    if s["status"].get("crashed"):
        n = s["status"]["crashed"]
        print(f"sweep: {n} crashed sample{'s' * (n != 1)} (each killed a worker process twice): status crashed "
              f"in results.csv, with the parameters; the other samples ran", file=sys.stderr)
    if s["applied_differs"]:
        print(f"sweep: {s['applied_differs']} sample(s) ran with a value the scene changed from the drawn one: "
              f"see column {_provenance.DIFFERS} in results.csv", file=sys.stderr)
    print(f"sweep: {s['samples']} samples, status {s['status']}; pointing_error_max p50 "
          f"{pct['p50'] if pct else float('nan'):.3e} p99 {pct['p99'] if pct else float('nan'):.3e} rad; "
          f"results in {a.out}/results.csv", file=sys.stderr)
    if e.get("ran_this_invocation"):
        print(f"sweep: {e['ran_this_invocation']} samples in {e['elapsed_s']:.1f} s on {e['workers']} workers "
              f"({e['samples_per_s']:.1f}/s); mean run {e['mean_run_s']*1e3:.1f} ms, engine overhead "
              f"{e['engine_overhead_per_sample_s']*1e3:.2f} ms per sample", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
