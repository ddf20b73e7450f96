"""Monte Carlo sweep of a scene over dispersed parameters, on a Dask cluster.

    python3 -m gimbalsim.sweep SPEC.yaml --out DIR [--workers N | --scheduler tcp://HOST:PORT] [--resume]

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
journaled to DIR/results.partial.csv as they arrive; --resume runs only the
missing samples. Exit codes: 0 done, 2 spec refused, 130 interrupted.
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
from . import _cluster
from ._spec import Spec, SpecError, check_out_dir
from .dispersion import Design, parse_parameter

METRICS = ["pointing_error_max", "pointing_error_final", "peak_contact_force", "peak_joint2_force", "impacts",
           "continuous_contact_from"]
JOURNAL = "results.partial.csv"
MAX_SAMPLES = 10_000_000


# ---- the spec ----

class SweepSpec:
    """A checked sweep spec: the base scene (file + set), the design, and a
    fingerprint that a resume must match."""

    def __init__(self, path):
        spec = Spec(path)
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
        self.set = {k: n.plain() for k, n in sets.items()}
        try:
            self.base = gimbalsim.load_scene(self.scene_path, self.set,
                                             sources={k: (spec.path, n.line) for k, n in sets.items()})
        except gimbalsim.SceneError as e:
            node = sets.get(e.key) if e.set_index else None
            spec.refuse(f"set.{e.key}" if node else "scene", str(e), node or root["scene"])
        params = spec.mapping("parameters", root["parameters"]) if "parameters" in root else {}
        self.parameters = [parse_parameter(spec, "parameters", k, n, key_types) for k, n in params.items()]
        grid = spec.mapping("grid", root["grid"]) if "grid" in root else {}
        self.grid = []
        for key, node in grid.items():
            if key not in key_types:
                spec.refuse(f"grid.{key}", "not a key of the scene", node)
            if key in params:
                spec.refuse(f"grid.{key}", "also under parameters: give it in one place", node)
            if not isinstance(node.value, list) or not node.value:
                spec.refuse(f"grid.{key}", "expected a non-empty list of values", node)
            self.grid.append((key, node.plain()))
        if not self.parameters and not self.grid:
            spec.refuse("parameters", "nothing is dispersed: give parameters or grid")
        # Values the scene would refuse are refused now, at the spec's line.
        for p in self.parameters:
            for v in p.extremes():
                self._try(spec, f"parameters.{p.key}", {p.key: v}, p.node)
        for (key, values), node in zip(self.grid, grid.values()):
            for v in values:
                self._try(spec, f"grid.{key}", {key: v}, node)
        self.design = Design(self.parameters, self.grid, self.samples, self.seed, self.base.values())
        if len(self.design) > MAX_SAMPLES:
            spec.refuse("grid", f"{len(self.design)} samples in all, more than {MAX_SAMPLES}")
        self.spec_path = spec.path
        self.fingerprint = json.dumps({"scene": self.base.values(), "seed": self.seed, "samples": self.samples,
                                       "parameters": {p.key: [p.kind, p.args] for p in self.parameters},
                                       "grid": self.grid}, sort_keys=True)

    def _try(self, spec, where, overrides, node):
        try:
            self.base.replace(overrides, sources={k: (spec.path, node.line) for k in overrides})
        except gimbalsim.SceneError as e:
            spec.refuse(where, f"the scene refuses {overrides}: {e.problems[0]['text'] if e.problems else e}", node)

    def header(self):
        return ["sample"] + self.design.columns() + ["status"] + METRICS + ["wall_time"]


# ---- one sample (runs on a worker) ----

def _bore_angles(a, b):
    """Angle [rad] between the boresight rows of two runs, row by row."""
    i = [gimbalsim.COLUMNS.index(c) for c in ("bore_x", "bore_y", "bore_z")]
    n = min(len(a), len(b))
    u, v = a[:n][:, i], b[:n][:, i]
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))


def run_sample(base, overrides, ideal_cache):
    """Sample's metrics: status and METRICS (dict). The ideal-joint run with
    the same parameters is the pointing reference (cached: it does not depend
    on the joint's parameters)."""
    try:
        scene = base.replace(overrides)
    except gimbalsim.SceneError as e:
        return {"status": f"refused:{e.key or ''}"}
    run = gimbalsim.simulate(scene)
    ideal = scene.replace({"structure.joint2": "ideal"})
    key = tuple(sorted(ideal.values().items()))
    if key not in ideal_cache:
        ideal_cache[key] = gimbalsim.simulate(ideal).rows
    err = _bore_angles(run.rows, ideal_cache[key])
    s = run.summary
    status = "ok" if run.ok else (s["stop"]["key"] or s["stop"]["step_status"].replace(" ", "_"))
    return {"status": status,
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
        [result.get(m) for m in METRICS] + [result["wall_time"]]


def read_journal(path, header):
    """Rows already journaled, by sample (the last incomplete line, from an
    interrupted write, is dropped; a sample written twice counts once)."""
    done = {}
    if not path.exists():
        return done
    text = path.read_text()
    lines = text.split("\n")
    if lines and lines[-1] != "":
        lines = lines[:-1]  # no newline: cut off mid-write
    reader = csv.reader(lines)
    first = next(reader, None)
    if first != header:
        raise SpecError(f"{path} was written by another spec (its header differs); use another --out")
    for row in reader:
        if len(row) == len(header) and row[0].isdigit():
            done.setdefault(int(row[0]), row)
    return done


def write_atomic(path, text):
    tmp = path.with_name(path.name + ".tmp")
    with open(tmp, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


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
    out.mkdir(parents=True, exist_ok=True)
    header = spec.header()
    journal = out / JOURNAL
    results = out / "results.csv"
    fingerprint = out / "spec.json"
    if resume:
        if fingerprint.exists() and fingerprint.read_text() != spec.fingerprint:
            raise SpecError(f"{out} holds a sweep of another spec; --resume needs the same spec")
    elif journal.exists() or results.exists():
        raise SpecError(f"{out} already holds a sweep: give --resume to finish it, or another --out")
    write_atomic(fingerprint, spec.fingerprint)
    done = read_journal(journal, header)
    if results.exists() and resume and not done:
        done = read_journal(results, header)
    todo = [i for i in range(len(spec.design)) if i not in done]
    with open(journal, "w") as jf:  # the kept rows again: drops a line cut off by an interruption
        jf.write(csv_line(header))
        for i in sorted(done):
            jf.write(csv_line(done[i]))
        jf.flush()
        print(f"sweep: {len(spec.design)} samples, {len(done)} already done, {len(todo)} to run", file=sys.stderr)
        engine = {"ran_this_invocation": 0}
        if todo:
            engine = _run_on_cluster(spec, todo, jf, done, workers, scheduler, batch, progress)
    rows = [done[i] for i in sorted(done)]
    rows = [[str(v) for v in r] for r in rows]
    write_atomic(results, "".join(csv_line(r) for r in [header] + rows))
    summary = summarize(spec, rows, engine)
    summary["plots"] = [str(p) for p in plot(spec, rows, out / "plots")]
    write_atomic(out / "summary.json", json.dumps(summary, indent=2) + "\n")
    journal.unlink()
    return summary


def _run_on_cluster(spec, todo, jf, done, workers, scheduler, batch, progress):
    from distributed import as_completed
    from tqdm import tqdm

    with _cluster.dask_client(workers, scheduler) as (client, n_workers):
        # about 8 tasks per worker, at most 10 samples each: rows arrive often and a killed worker loses little
        size = batch or max(1, min(10, math.ceil(len(todo) / (n_workers * 8))))
        chunks = [todo[k:k + size] for k in range(0, len(todo), size)]
        base = client.scatter(spec.base, broadcast=True)
        t0 = time.perf_counter()
        futures = [client.submit(run_batch, base, [(i, spec.design.draw(i)) for i in c], pure=False)
                   for c in chunks]
        bar = tqdm(total=len(todo), unit="sample", disable=not progress, file=sys.stderr, smoothing=0.1)
        inside, ran = 0.0, 0
        try:
            for fut in as_completed(futures):
                results, t_task = fut.result()
                inside += t_task
                for r in results:
                    i = r["sample"]
                    if i in done:
                        continue
                    line = row_values(spec, spec.design.draw(i), r)
                    done[i] = [fmt(v) for v in line]
                    jf.write(csv_line(line))
                    ran += 1
                jf.flush()
                os.fsync(jf.fileno())
                bar.update(len(results))
                fut.release()
        except KeyboardInterrupt:
            bar.close()
            client.cancel(futures)
            print(f"\nsweep: interrupted with {len(done)} samples done; run again with --resume", file=sys.stderr)
            raise
        bar.close()
        elapsed = time.perf_counter() - t0
    run_time = sum(float(done[i][len(done[i]) - 1]) for i in todo)
    return {"workers": n_workers, "batch": size, "tasks": len(chunks), "ran_this_invocation": ran,
            "elapsed_s": elapsed, "samples_per_s": ran / elapsed if elapsed > 0 else None,
            "mean_run_s": run_time / ran if ran else None,
            # time the workers were busy with something other than our tasks, per sample
            "engine_overhead_per_sample_s": (elapsed * n_workers - inside) / ran if ran else None,
            "task_overhead_per_sample_s": (inside - run_time) / ran if ran else None}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m gimbalsim.sweep", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("spec", help="sweep spec (YAML)")
    ap.add_argument("--out", required=True, help="output directory")
    _cluster.add_cluster_arguments(ap)
    ap.add_argument("--resume", action="store_true", help="finish an interrupted sweep in --out")
    ap.add_argument("--batch", type=int, default=None, help="samples per task (default: about 8 tasks per worker, at most 10)")
    ap.add_argument("--no-progress", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)
    if a.workers is not None and a.workers < 1:
        ap.error("--workers must be >= 1")
    if a.batch is not None and a.batch < 1:
        ap.error("--batch must be >= 1")
    try:
        check_out_dir(a.out, a.spec)
        spec = SweepSpec(a.spec)
        s = sweep(spec, pathlib.Path(a.out), a.workers, a.scheduler, a.resume, a.batch, not a.no_progress)
    except SpecError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    e = s["engine"]
    pct = s["percentiles_of_ok_samples"]["pointing_error_max"]
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
