"""Controller tuning with Optuna on a Dask cluster: each trial proposes
controller gains, runs the closed loop (firmware model + the project's
pointing controller) on a batch of dispersed plants, and scores a percentile
of the closed-loop inertial pointing error; commands beyond the torque limit
are a constraint.

    python3 -m gimbalsim.tune TUNE.yaml --out DIR [--workers N | --scheduler tcp://HOST:PORT]

TUNE (YAML):
    scene: tools/scenes/paper_clearance.yaml     # the plant (against the spec's folder, then the current directory)
    set: {}                                       # scene overrides for every plant
    controller: controllers/config/default.yaml  # the configuration the gains are laid over
    duration: 5.0                                 # closed loop [s] (the profile tracks from 3.5 s)
    trials: 40
    parallel_trials: 2                            # trials in flight at once (default: the workers)
    seed: 1
    batch: 32                                     # dispersed plants per trial: the same plants for every trial
    objective: {metric: max_track, percentile: 99}  # max_track | rms_track of the truth pointing error [rad]
    max_saturation: 0.0                           # constraint: fraction of ticks with a limited command
    gains:                                        # controller keys: uniform, loguniform or choice
      azimuth.kp: {loguniform: [5000, 50000]}
    plants:                                       # scene keys, the sweep's syntax (sensors included)
      contact.clearance: {uniform: [1.0e-4, 8.0e-4]}

Writes DIR/trials.csv (one row per trial), DIR/best.yaml (the whole controller
configuration with the best feasible trial's gains: `pointing_controller
DIR/best.yaml` loads it as it is) and DIR/progress.png. Exit codes: 0, 2 spec
refused, 3 no trial completed.
"""
import argparse
import csv
import io
import json
import math
import pathlib
import sys
import time
import warnings

import numpy as np

import gimbalsim
from . import _cluster
from ._spec import Spec, SpecError, check_out_dir
from .dispersion import Design, parse_parameter
from .sweep import write_atomic

METRICS = {"max_track": "max_truth_error_track_rad", "rms_track": "rms_truth_error_track_rad"}
GAIN_DISTRIBUTIONS = ("uniform", "loguniform", "choice")


class TuneSpec:
    def __init__(self, path):
        spec = Spec(path)
        spec.check_keys({"scene", "set", "controller", "controller_set", "duration", "trials", "parallel_trials",
                         "seed", "batch", "objective", "max_saturation", "gains", "plants"})
        root = spec.root.value
        for required in ("scene", "controller", "duration", "trials", "seed", "batch", "gains"):
            if required not in root:
                spec.refuse(required, "missing")
        self.spec_path = spec.path
        self.scene_path = spec.path_of("scene", root["scene"])
        self.controller_path = spec.path_of("controller", root["controller"])
        self.duration = spec.number("duration", root["duration"], 1e-3, 1e5)
        self.trials = spec.integer("trials", root["trials"], 1, 100_000)
        self.parallel = spec.integer("parallel_trials", root["parallel_trials"], 1, 1000) \
            if "parallel_trials" in root else None
        self.seed = spec.integer("seed", root["seed"], 0, 2**32 - 1)
        self.batch = spec.integer("batch", root["batch"], 1, 100_000)
        self.max_saturation = spec.number("max_saturation", root["max_saturation"], 0.0, 1.0) \
            if "max_saturation" in root else 0.0
        obj = spec.mapping("objective", root["objective"]) if "objective" in root else {}
        for k, n in obj.items():
            if k not in ("metric", "percentile"):
                spec.refuse(f"objective.{k}", "unknown key (expected metric, percentile)", n)
        self.metric = obj["metric"].value if "metric" in obj else "max_track"
        if self.metric not in METRICS:
            spec.refuse("objective.metric", f"expected one of {', '.join(METRICS)}, got {self.metric!r}", obj["metric"])
        self.percentile = spec.number("objective.percentile", obj["percentile"], 0.0, 100.0) \
            if "percentile" in obj else 99.0

        scene_types = {k["key"]: k["type"] for k in gimbalsim.keys()}
        sets = spec.mapping("set", root["set"]) if "set" in root else {}
        for k, n in sets.items():
            if k not in scene_types:
                spec.refuse(f"set.{k}", "not a key of the scene", n)
        try:
            self.base = gimbalsim.load_scene(self.scene_path, {k: n.plain() for k, n in sets.items()},
                                             sources={k: (spec.path, n.line) for k, n in sets.items()})
        except gimbalsim.SceneError as e:
            spec.refuse(f"set.{e.key}" if e.key in sets else "scene", str(e), sets.get(e.key, root["scene"]))
        ctrl_types = {k["key"]: k["type"] for k in gimbalsim.controller_keys()}
        csets = spec.mapping("controller_set", root["controller_set"]) if "controller_set" in root else {}
        for k, n in csets.items():
            if k not in ctrl_types:
                spec.refuse(f"controller_set.{k}", "not a controller key (see pointing_controller --keys)", n)
        self.controller_set = {k: n.plain() for k, n in csets.items()}
        try:
            self.controller = gimbalsim.Controller(self.controller_path, self.controller_set,
                                                   sources={k: (spec.path, n.line) for k, n in csets.items()})
        except gimbalsim.SceneError as e:
            spec.refuse(f"controller_set.{e.key}" if e.key in csets else "controller", str(e),
                        csets.get(e.key, root["controller"]))
        period = self.controller.period
        if abs(round(self.duration / period) * period - self.duration) > 1e-9 * max(1.0, self.duration):
            spec.refuse("duration", f"must be a whole number of control periods ({period} s)", root["duration"])

        self.gains = []
        for key, node in spec.mapping("gains", root["gains"]).items():
            p = parse_parameter(spec, "gains", key, node, ctrl_types)
            if p.kind not in GAIN_DISTRIBUTIONS:
                spec.refuse(f"gains.{key}", f"{p.kind}: gains take {', '.join(GAIN_DISTRIBUTIONS)}", node)
            for v in p.extremes():
                try:
                    gimbalsim.Controller(self.controller_path, {**self.controller_set, key: v},
                                         sources={**{k: (spec.path, n.line) for k, n in csets.items()},
                                                  key: (spec.path, node.line)})
                except gimbalsim.SceneError as e:
                    spec.refuse(f"gains.{key}", f"the controller refuses {key}={v!r}: {e.problems[0]['text']}", node)
            self.gains.append(p)
        if not self.gains:
            spec.refuse("gains", "no gain to tune", root["gains"])
        plants = spec.mapping("plants", root["plants"]) if "plants" in root else {}
        params = [parse_parameter(spec, "plants", k, n, scene_types) for k, n in plants.items()]
        for p in params:
            for v in p.extremes():
                try:
                    self.base.replace({p.key: v}, sources={p.key: (spec.path, p.node.line)})
                except gimbalsim.SceneError as e:
                    spec.refuse(f"plants.{p.key}", f"the scene refuses {p.key}={v!r}: {e.problems[0]['text']}",
                                p.node)
        self.plants = Design(params, [], self.batch, self.seed, self.base.values())


def run_plants(base, controller, duration, items):
    """A task: closed loops of one controller on plants [(j, overrides)]."""
    out = []
    for j, overrides in items:
        t0 = time.perf_counter()
        try:
            scene = base.replace(overrides)
        except gimbalsim.SceneError as e:
            out.append({"plant": j, "ok": False, "stop_key": f"refused:{e.key}", "wall_time": 0.0})
            continue
        s = gimbalsim.closed_loop(scene, controller, duration).summary
        s["plant"] = j
        s["wall_time"] = time.perf_counter() - t0
        out.append(s)
    return out


def nested_yaml(values):
    """`key.sub=value` texts as a nested YAML document (values are --set text, valid YAML)."""
    tree = {}
    for key, value in values.items():
        node = tree
        *parents, leaf = key.split(".")
        for p in parents:
            node = node.setdefault(p, {})
        node[leaf] = value
    lines = []

    def emit(node, depth):
        for k, v in node.items():
            if isinstance(v, dict):
                lines.append("  " * depth + f"{k}:")
                emit(v, depth + 1)
            else:
                lines.append("  " * depth + f"{k}: {v}")
    emit(tree, 0)
    return "\n".join(lines) + "\n"


def suggest(trial, p):
    if p.kind == "choice":
        return trial.suggest_categorical(p.key, p.args)
    if p.type == "int":
        return trial.suggest_int(p.key, int(p.args[0]), int(p.args[1]), log=p.kind == "loguniform")
    return trial.suggest_float(p.key, p.args[0], p.args[1], log=p.kind == "loguniform")


def tune(spec, out, workers=None, scheduler=None, progress=True):
    import optuna
    from distributed import wait
    from tqdm import tqdm

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    # constant_liar and constraints_func are marked experimental in Optuna 3.1: used knowingly.
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    out.mkdir(parents=True, exist_ok=True)
    sampler = optuna.samplers.TPESampler(
        seed=spec.seed, constant_liar=True, n_startup_trials=max(1, min(10, spec.trials // 3)),
        constraints_func=lambda t: (t.user_attrs.get("constraint", 1.0),))
    study = optuna.create_study(direction="minimize", sampler=sampler)
    gain_names = [p.key for p in spec.gains]
    header = ["trial", "state", "score", "constraint", *gain_names, "plants_ok", "reason", "wall_time"]
    rows = []
    plants = [(j, spec.plants.draw(j)) for j in range(spec.batch)]
    with _cluster.dask_client(workers, scheduler) as (client, n_workers):
        parallel = spec.parallel or n_workers
        chunk = max(1, math.ceil(spec.batch / max(1, n_workers)))
        base = client.scatter(spec.base, broadcast=True)
        in_flight = {}  # trial number -> (trial, futures, gains, t0)
        asked = 0
        bar = tqdm(total=spec.trials, unit="trial", disable=not progress, file=sys.stderr)
        while asked < spec.trials or in_flight:
            while asked < spec.trials and len(in_flight) < parallel:
                trial = study.ask()
                gains = {p.key: suggest(trial, p) for p in spec.gains}
                ctrl = gimbalsim.Controller(spec.controller_path, {**spec.controller_set, **gains})
                futs = [client.submit(run_plants, base, ctrl, spec.duration, plants[k:k + chunk], pure=False)
                        for k in range(0, len(plants), chunk)]
                in_flight[trial.number] = (trial, futs, gains, time.perf_counter())
                asked += 1
            wait([f for _, fs, _, _ in in_flight.values() for f in fs], return_when="FIRST_COMPLETED")
            for number in [n for n, (_, fs, _, _) in in_flight.items() if all(f.done() for f in fs)]:
                trial, futs, gains, t0 = in_flight.pop(number)
                results = [r for f in futs for r in f.result()]
                rows.append(_finish(study, trial, gains, results, spec, time.perf_counter() - t0))
                bar.update(1)
                _write_trials(out, header, rows)
        bar.close()
    done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    if not done:
        return None, rows
    feasible = [t for t in done if t.user_attrs["constraint"] <= 0.0]
    best = min(feasible or done, key=lambda t: t.value)
    best_ctrl = gimbalsim.Controller(spec.controller_path, {**spec.controller_set,
                                                             **{k: best.params[k] for k in gain_names}})
    text = (f"# gimbalsim.tune: trial {best.number} of {spec.spec_path.name}, score {best.value!r} rad "
            f"(p{spec.percentile:g} of {spec.metric} over {spec.batch} plants), "
            f"{'feasible' if feasible else 'NO FEASIBLE TRIAL: the least bad'}\n") + nested_yaml(best_ctrl._values_text())
    write_atomic(out / "best.yaml", text)
    _plot(out, rows, spec)
    summary = {"best_trial": best.number, "best_score": best.value, "feasible": bool(feasible),
               "best_gains": {k: best.params[k] for k in gain_names}, "trials": len(rows),
               "complete": len(done), "feasible_trials": len(feasible)}
    write_atomic(out / "summary.json", json.dumps(summary, indent=2) + "\n")
    return summary, rows


def _finish(study, trial, gains, results, spec, wall):
    import optuna

    ok = [r for r in results if r["ok"]]
    worst_sat = max((r["saturated_ticks"] / max(1, r["ticks"]) for r in ok), default=1.0)
    constraint = worst_sat - spec.max_saturation
    trial.set_user_attr("constraint", constraint)
    row = {"trial": trial.number, "constraint": constraint, **gains, "plants_ok": len(ok), "wall_time": wall}
    if len(ok) < len(results):
        why = sorted({r["stop_key"] for r in results if not r["ok"]})
        study.tell(trial, state=optuna.trial.TrialState.FAIL)
        return {**row, "state": "FAIL", "score": "", "reason": "plant stopped: " + " ".join(why)}
    score = float(np.percentile([r[METRICS[spec.metric]] for r in ok], spec.percentile))
    study.tell(trial, score)
    return {**row, "state": "COMPLETE", "score": score, "reason": ""}


def _fmt(v):
    return repr(v) if isinstance(v, float) else str(v)


def _write_trials(out, header, rows):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in sorted(rows, key=lambda r: r["trial"]):
        w.writerow([_fmt(r.get(h, "")) for h in header])
    write_atomic(out / "trials.csv", buf.getvalue())


def _plot(out, rows, spec):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = sorted(rows, key=lambda r: r["trial"])
    fig, ax = plt.subplots(figsize=(7, 4))
    best, xs, ys = math.inf, [], []
    for r in rows:
        if r["state"] != "COMPLETE":
            continue
        feasible = r["constraint"] <= 0
        ax.plot(r["trial"], r["score"], "o" if feasible else "x", c="C0" if feasible else "C3", ms=4)
        if feasible:
            best = min(best, r["score"])
            xs.append(r["trial"])
            ys.append(best)
    ax.step(xs, ys, where="post", c="k", label="best feasible so far")
    ax.set_yscale("log")
    ax.set_xlabel("trial")
    ax.set_ylabel(f"p{spec.percentile:g} {spec.metric} [rad]")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "progress.png", dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m gimbalsim.tune", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("spec", help="tuning spec (YAML)")
    ap.add_argument("--out", required=True, help="output directory")
    _cluster.add_cluster_arguments(ap)
    ap.add_argument("--no-progress", action="store_true")
    a = ap.parse_args(argv)
    try:
        check_out_dir(a.out, a.spec)
        spec = TuneSpec(a.spec)
        summary, rows = tune(spec, pathlib.Path(a.out), a.workers, a.scheduler, not a.no_progress)
    except SpecError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    if summary is None:
        print(f"tune: no trial completed ({len(rows)} failed); see {a.out}/trials.csv", file=sys.stderr)
        return 3
    print(f"tune: best trial {summary['best_trial']}: score {summary['best_score']:.3e} rad "
          f"({'feasible' if summary['feasible'] else 'no trial was feasible'}), gains {summary['best_gains']}; "
          f"{a.out}/best.yaml", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
