"""Controller tuning with Optuna on a Dask cluster: each trial proposes
controller gains, runs the closed loop (firmware model + the project's
pointing controller) on a batch of dispersed plants, and scores a percentile
of the closed-loop inertial pointing error; commands beyond the torque limit
are a constraint.

    python3 -m gimbalsim.tune TUNE.yaml --out DIR [--workers N | --scheduler tcp://HOST:PORT] [--resume]

TUNE (YAML):
    scene: tools/scenes/paper_clearance.yaml     # the plant (against the spec's folder, then the current directory)
    set: {}                                       # scene overrides for every plant
    controller: controllers/config/default.yaml  # the configuration the gains are laid over (default: the built-in one)
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

Writes DIR/study.db (the Optuna study, SQLite), DIR/trials.csv (one row per
trial with every plant's figures; trial 0 is the configuration's own gains),
DIR/best.yaml (the whole controller configuration with the best feasible
trial's gains: `pointing_controller DIR/best.yaml` loads it as it is) and
DIR/progress.png. --resume continues the study in DIR: trials a killed tuner
left running are marked FAIL and run again; without it a DIR holding a study
is refused. Exit codes (the project's table, docs/usage.md "Exit codes",
mirrored in _errors.py): 0, 2 spec refused, 3 no trial completed, 4 an output not written,
6 the --scheduler did not answer or had no worker (nothing written), 130 / 143 / 129 interrupted by
SIGINT / SIGTERM / SIGHUP (the study kept).
"""
import contextlib
import math
import os
import pathlib
import sys
import time
import warnings

import numpy as np

import gimbalsim
from . import _cluster, _scene_warnings, _study_file
from ._console import keep_console
from ._errors import EXIT_OK, EXIT_STOPPED, Interrupted, SpecError, exit_program, guarded_main
from ._closed_spec import plant_overrides
from ._journal import fmt
from ._output import json_text, output_set, savefig, write_csv, write_text
from ._output_names import check_output_names
from ._spec import check_out_dir, check_outputs_not_inputs
from ._study_file import (STUDY_FILE, TRIALS, check_trials_held, forget_unrecorded_study, open_study, study_recorded,
                          study_write_errors, trials_kept)
from ._tune_spec import METRICS, TuneSpec, fail_reason, suggest  # noqa: F401 (TuneSpec: the module's API)

def run_plants(base, controller, duration, items):
    """A task: closed loops of one controller on plants [(j, overrides)]."""
    _cluster.keep_freed_memory()
    _scene_warnings.quiet()
    out = []
    for j, overrides in items:
        t0 = time.perf_counter()
        _cluster.crash_hook(j)
        try:
            scene = base.replace(plant_overrides(overrides))  # sim.step with the interval it never reads
        except gimbalsim.SceneError as e:
            out.append({"plant": j, "ok": False, "stop_key": f"refused:{e.key or 'scene'}", "error": str(e),
                        "wall_time": 0.0})  # (pass 40) a keyless refusal was "refused:None"
            continue
        try:
            s = gimbalsim.closed_loop(scene, controller, duration, _study=True).summary  # judged with the spec
        except (gimbalsim.SceneError, ValueError) as e:  # the run's arguments refused: FAIL, not a crash
            out.append({"plant": j, "ok": False, "stop_key": f"refused:{getattr(e, 'key', None) or 'duration'}",
                        "error": str(e), "wall_time": 0.0})
            continue
        if s["stop_key"].startswith("refused:controller."):  # nothing ran; a tuner names gains without the prefix
            s["stop_key"] = "refused:" + s["stop_key"][len("refused:controller."):]
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
            lines.append("  " * depth + (f"{k}:" if isinstance(v, dict) else f"{k}: {v}"))
            if isinstance(v, dict):
                emit(v, depth + 1)
    emit(tree, 0)
    return "\n".join(lines) + "\n"


PLANT_FIGURES = ("max_truth_error_track_rad", "rms_truth_error_track_rad", "controller_limited_ticks", "ticks")
# The study's files in --out, by the names its writers take; SQLite writes its journal beside the study.
BEST, SUMMARY, PROGRESS = "best.yaml", "summary.json", "progress.png"
OUTPUTS = (STUDY_FILE, STUDY_FILE + "-journal", TRIALS, BEST, SUMMARY, PROGRESS)


def check_study_folder(spec, out, resume):
    """Refuses (exit 2), before the cluster or anything written: a folder of
    another tool's outputs, a study without --resume, and a link, anything
    but a file or an input under any output's name (found at the end, every
    trial was lost)."""
    check_output_names(out, "study", [out / n for n in OUTPUTS], [out], refuse=SpecError)  # a sweep's, an allocation's
    _study_file.refuse_if_running(out)
    if not resume and ((out / STUDY_FILE).exists() or (out / TRIALS).exists()):
        if (out / STUDY_FILE).exists() and not study_recorded(out) and not trials_kept(out):
            # --resume would be refused too (pass 56): say what the file is, not a resume that cannot be
            raise SpecError(f"{out / STUDY_FILE} holds no study of {_study_file.STUDY_NAME} (empty, or a tuner "
                            f"stopped before it recorded one): nothing to resume; remove it, or use another --out")
        raise SpecError(f"{out} already holds a study ({STUDY_FILE}, {TRIALS}): give --resume to continue it, "
                        f"or another --out")
    check_outputs_not_inputs([out / n for n in OUTPUTS], spec.input_files())


def tune(spec, out, workers=None, scheduler=None, progress=True, resume=False):
    import optuna
    from distributed import wait
    from distributed.scheduler import KilledWorker
    from tqdm import tqdm

    optuna.logging.set_verbosity(optuna.logging.WARNING)
    # constant_liar and constraints_func are marked experimental in Optuna 3.1: used knowingly.
    warnings.filterwarnings("ignore", category=optuna.exceptions.ExperimentalWarning)
    def sampler(seed):
        return optuna.samplers.TPESampler(
            seed=seed, constant_liar=True, n_startup_trials=max(1, min(10, spec.trials // 3)),
            constraints_func=lambda t: (t.user_attrs.get("constraint", 1.0),))
    check_study_folder(spec, out, resume)
    with contextlib.ExitStack() as stack:
        # A named scheduler is reached before the study is made: one that does not answer (exit 6) leaves
        # --out as it was, not a study the next run would want resumed.
        named = stack.enter_context(_cluster.dask_client(None, scheduler)) if scheduler else None
        study = open_study(spec, out, resume)
        # A resumed study's sampler is seeded by the spec's seed and the trials held (pass 80: the spec's seed
        # again replayed the first run's draws, finished gains proposed anew).
        seed = int(np.random.SeedSequence([spec.seed, len(study.trials)]).generate_state(1)[0]) if resume else spec.seed
        study.sampler = sampler(seed)
        gain_names = [p.key for p in spec.gains]
        header = ["trial", "state", "origin", "score", "constraint", *gain_names, "plants_ok", "reason",
                  "wall_time"] + [f"plant{j}.{c}" for j in range(spec.batch) for c in ("status",) + PLANT_FIGURES]
        if resume:  # the kills marked, the rows of trials told before a kill but not yet written
            check_trials_held(study, out / TRIALS)
            _write_trials(out, header, study, spec.input_files())
        # the requested count is of finished trials; a trial killed with the tuner is not one (its retry is)
        finished = sum(1 for t in study.trials if t.state.is_finished() and t.user_attrs.get("row", {}).get("reason")
                       != "killed")
        plants = [(j, spec.plants.draw(j)) for j in range(spec.batch)]
        client, n_workers = named or stack.enter_context(_cluster.dask_client(workers))
        parallel = spec.parallel or n_workers
        chunk = max(1, math.ceil(spec.batch / max(1, n_workers)))
        in_flight = {}  # trial number -> (trial, futures, gains, t0)
        # the scene goes in each task: scattered data would die with its workers
        submit = lambda ctrl, items: (  # noqa: E731
            client.submit(run_plants, spec.base, ctrl, spec.duration, items, pure=False), items)
        bar = tqdm(total=spec.trials, initial=min(finished, spec.trials), unit="trial", disable=not progress,
                   file=sys.stderr)
        while finished + len(in_flight) < spec.trials or in_flight:
            _cluster.raise_if_interrupted()
            while finished + len(in_flight) < spec.trials and len(in_flight) < parallel:
                trial = study.ask()
                gains = {p.key: suggest(trial, p) for p in spec.gains}
                try:  # gains the controller refuses, or a period that does not divide the run: FAIL, the study goes on
                    ctrl = gimbalsim.Controller(spec.controller_path, {**spec.controller_set, **gains})
                    why = gimbalsim._gimbalsim._whole_multiple_problem(spec.duration, ctrl.period, "control.period")
                    refused = ("control.period", f"duration {spec.duration:g} s {why}") if why else None
                except (gimbalsim.SceneError, ValueError) as e:
                    refused = (getattr(e, "key", None) or "", str(e))
                if refused:  # no plant run: each is refused:<key>
                    _finish(study, trial, gains, [{"plant": j, "ok": False, "stop_key": f"refused:{refused[0]}",
                                                   "error": refused[1]} for j, _ in plants], spec, 0.0)
                    finished += 1
                    bar.update(1)
                    _write_trials(out, header, study, spec.input_files())
                    continue
                in_flight[trial.number] = (trial, [submit(ctrl, plants[k:k + chunk]) for k in
                                                   range(0, len(plants), chunk)], gains, time.perf_counter(), ctrl, [])
            wait([f for _, fs, *_ in in_flight.values() for f, _ in fs], return_when="FIRST_COMPLETED")
            for number in [n for n, (_, fs, *_) in in_flight.items() if all(f.done() for f, _ in fs)]:
                trial, futs, gains, t0, ctrl, results = in_flight.pop(number)
                again = []
                for f, items in futs:
                    try:
                        results += f.result()
                    except KilledWorker:  # a plant that kills its worker twice fails the trial, not the study
                        alone = _cluster.rerun_alone(items, lambda c: submit(ctrl, c)[0])
                        again += alone
                        if not alone:
                            results.append({"plant": items[0][0], "ok": False, "stop_key": "crashed"})
                if again:
                    in_flight[number] = (trial, again, gains, t0, ctrl, results)
                    continue
                _finish(study, trial, gains, sorted(results, key=lambda r: r["plant"]), spec,
                        time.perf_counter() - t0)
                finished += 1
                bar.update(1)
                _write_trials(out, header, study, spec.input_files())
        bar.close()
        _cluster.raise_if_interrupted()
    done = [t for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE]
    rows = [t.user_attrs["row"] for t in study.trials if "row" in t.user_attrs]
    if not done:  # (pass 44) nothing was written: summary.json says so, with why (no best.yaml, no best)
        reasons = sorted({r.get("reason") or "" for r in rows} - {""})
        summary = {"best_trial": None, "best_score": None, "feasible": False, "best_gains": None,
                   "trials": len(rows), "complete": 0, "feasible_trials": 0, "sampling": spec.sampling,
                   "note": f"no trial completed ({len(rows)} failed): " + "; ".join(reasons[:5])}
        write_text(out / SUMMARY, json_text(summary), spec.input_files())
        return None, rows
    feasible = [t for t in done if t.user_attrs["constraint"] <= 0.0]
    best = min(feasible or done, key=lambda t: t.value)
    best_ctrl = gimbalsim.Controller(spec.controller_path, {**spec.controller_set,
                                                             **{k: best.params[k] for k in gain_names}})
    text = (f"# gimbalsim.tune: trial {best.number} of {spec.spec_path.name}, score {best.value!r} rad "
            f"(p{spec.percentile:g} of {spec.metric} over {spec.batch} plants), "
            f"{'feasible' if feasible else 'NO FEASIBLE TRIAL: the least bad'}\n") + \
        nested_yaml(best_ctrl._values_text())
    summary = {"best_trial": best.number, "best_score": best.value, "feasible": bool(feasible),
               "best_gains": {k: best.params[k] for k in gain_names}, "trials": len(rows),
               "complete": len(done), "feasible_trials": len(feasible), "sampling": spec.sampling}
    with output_set():  # the study's verdict is one set: stopped part-way, none of it is left
        write_text(out / BEST, text, spec.input_files())
        _plot(out, rows, spec)
        write_text(out / SUMMARY, json_text(summary), spec.input_files())
    return summary, rows


def _finish(study, trial, gains, results, spec, wall):
    """Scores a trial, keeps its row (every plant's figures) in the study, and tells the study."""
    import optuna

    ok = [r for r in results if r["ok"]]
    sat = [r["controller_limited_ticks"] / max(1, r["ticks"]) for r in ok]  # no plant ok: none measured, no value
    constraint = max(sat) - spec.max_saturation if sat else None
    row = {"trial": trial.number, "origin": trial.user_attrs.get("origin", ""), "constraint": constraint, **gains,
           "plants_ok": len(ok), "wall_time": wall}
    for r in results:
        row[f"plant{r['plant']}.status"] = "ok" if r["ok"] else r["stop_key"]
        row.update({f"plant{r['plant']}.{c}": r[c] for c in PLANT_FIGURES if c in r})
    metric = METRICS[spec.metric]
    unscored = sorted({r.get("reasons", {}).get(metric, "not finite") for r in ok if not math.isfinite(r[metric])})
    if len(ok) < len(results):
        row.update(state="FAIL", score="", reason=fail_reason(results))
    elif unscored:  # a figure with no value is no score, never 0 (the spec check makes it rare)
        row.update(state="FAIL", score="", reason=f"no {metric}: " + "; ".join(unscored))
    else:
        row.update(state="COMPLETE", score=float(np.percentile([r[METRICS[spec.metric]] for r in ok],
                                                               spec.percentile)), reason="")
    if constraint is not None:
        trial.set_user_attr("constraint", constraint)
    trial.set_user_attr("row", row)
    if row["state"] == "FAIL":
        study.tell(trial, state=optuna.trial.TrialState.FAIL)
    else:
        study.tell(trial, row["score"])


def _csv_names(header):
    """trials.csv's header in the project's CSV convention (docs/usage.md):
    azimuth.kp -> azimuth_kp_Nm_per_rad, plant0.status -> plant0_status."""
    units = {k["key"]: k["unit"] for k in gimbalsim.controller_keys()}
    units["wall_time"] = "s"
    return [gimbalsim._gimbalsim.csv_name(h.replace(".", "_"), units.get(h, "")) for h in header]


def _write_trials(out, header, study, inputs=()):
    """trials.csv from the study: every finished trial, in trial order."""
    rows = [t.user_attrs["row"] for t in study.get_trials(deepcopy=False) if "row" in t.user_attrs]
    write_csv(out / TRIALS, [_csv_names(header)] + [[fmt(r.get(h, "")) for h in header] for r in rows],
              inputs)


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
    savefig(fig, out / PROGRESS, spec.input_files(), dpi=110, close=True)


def main(argv=None):
    ap = _cluster.program_parser("tune", __doc__, "tuning spec (YAML)", "output directory")
    ap.add_argument("--resume", action="store_true", help="continue the study stored in --out")
    ap.add_argument("--no-progress", action="store_true")
    a = ap.parse_args(argv)
    _cluster.raise_on_signals()
    _scene_warnings.quiet()
    out = pathlib.Path(a.out)
    return guarded_main("tune", lambda: _run(a, out), {Interrupted: lambda e: _interrupted_note(out)})


def _interrupted_note(out):
    """How to go on after a signal: --resume where the study was recorded, else a plain run again."""
    if study_recorded(out):
        kept = trials_kept(out)  # none yet: no trials.csv to name
        return (f": {f'{kept} finished trials kept in ' + str(out / TRIALS) if kept else 'no trial finished yet'}; "
                f"the study is in {out / STUDY_FILE}: run again with --resume to continue it")
    return f": before the study was recorded, nothing kept in {out}: run again (without --resume)"


def _run(a, out):
    """The study of the command line a, its line on the console; its exit
    code (what goes wrong is raised, for guarded_main's exit code)."""
    check_out_dir(a.out, a.spec)
    made_before = (out / STUDY_FILE).exists()  # a study file this run did not make is never removed
    folder_before = os.path.lexists(out)  # a folder this run made goes with its files (pass 66: left empty)
    spec = TuneSpec(a.spec)
    if spec.sampling["overrides"]:  # said when the runs step otherwise than the scene is written
        print(f"tune: stepping (sampling: {spec.sampling['mode']}): {spec.sampling['why']}", file=sys.stderr)
    write_errors = study_write_errors()
    try:
        summary, rows = tune(spec, out, a.workers, a.scheduler, not a.no_progress, a.resume)
    except Interrupted:
        # a signal before the new study was recorded leaves files no run takes (a --resume and a plain run were
        # both refused over them, pass 56): they go, as after a failed write
        if not a.resume and not made_before and not study_recorded(out):
            forget_unrecorded_study(out, folder_before)
        raise
    except write_errors as e:  # the study's file refused a write (a full disk): what was told is kept
        if a.resume or study_recorded(out):
            raise _study_file.write_failure(out, e, "run again with --resume") from None
        # A new study that failed before it was recorded: its files are this run's and hold nothing a resume
        # could take (a --resume and a plain run were both refused over them, pass 55); they go.
        failure = _study_file.write_failure(out, e, "run again (nothing was kept)")  # asks in the folder: first
        forget_unrecorded_study(out, folder_before)
        raise failure from None
    if summary is None:
        print(f"tune: no trial completed ({len(rows)} failed); see {a.out}/trials.csv and summary.json",
              file=sys.stderr)
        return EXIT_STOPPED
    print(f"tune: best trial {summary['best_trial']}: score {summary['best_score']:.3e} rad "
          f"({'feasible' if summary['feasible'] else 'no trial was feasible'}), gains {summary['best_gains']}; "
          f"{a.out}/best.yaml", file=sys.stderr)
    return EXIT_OK


if __name__ == "__main__":
    keep_console()  # a console whose reader is gone stops nothing, --help included
    exit_program("tune", main)
