"""The tuning spec (TUNE.yaml of gimbalsim.tune): the plant and its
dispersed batch, the controller and the gains to tune, the objective and
its constraint, every value checked at the spec's line before anything runs."""
import json
import math

import gimbalsim
from . import _gimbalsim, _sampling
from ._closed_spec import CONTROLLER_PREFIX, controller_path_of, plant_overrides, ticks_too_many
from ._idle_keys import idle_reason, refuse_idle_set, takes_of
from ._one_quantity import quantities_given_twice
from ._spec import Spec
from .dispersion import CONTROLLER_KEYS, Design, check_within, parse_parameter
from .indices import seconds

METRICS = {"max_track": "max_truth_error_track_rad", "rms_track": "rms_truth_error_track_rad"}
METRIC_WINDOWS = {"max_track": "track", "rms_track": "track"}  # the profile window each metric is over
GAIN_DISTRIBUTIONS = ("uniform", "loguniform", "choice")


PERCENTILE_RANGE = (50.0, 100.0)  # the objective bounds the plants from above: the median at the least


def _percentile(spec, node):
    """objective.percentile in [50, 100]: below the median the gains are tuned
    for the lucky plants (at 1e-300, the best one's figure alone)."""
    lo, hi = PERCENTILE_RANGE
    v = node.value
    if isinstance(v, (int, float)) and not isinstance(v, bool) and v < lo:
        spec.refuse("objective.percentile", f"expected a number in [{lo}, {hi}], got {v!r}: a percentile below the "
                    "median tunes for the lucky plants, not a bound on the others", node)
    return spec.number("objective.percentile", node, lo, hi)  # above 100, not finite, not a number


def fail_reason(results):
    """Why a trial with a plant not ok failed: `plant stopped: <keys>` for
    plants that ran and stopped, `not run: refused:<key> (<why>)` when no
    plant could start, and `N of M plants refused: refused:<key> (<why>)`
    when some did (a refused plant never started; the others ran)."""
    parts = []
    for refused in (False, True):
        failed = [r for r in results if not r["ok"] and r["stop_key"].startswith("refused:") == refused]
        if not failed:
            continue
        keys = " ".join(sorted({r["stop_key"] for r in failed}))
        errors = sorted({r["error"] for r in failed if r.get("error")})
        head = "plant stopped" if not refused else "not run" if len(failed) == len(results) else \
            f"{len(failed)} of {len(results)} plants refused"
        parts.append(f"{head}: {keys}" + (f" ({errors[0]})" if errors else ""))
    return "; ".join(parts)


def suggest(trial, p):
    """The Optuna trial's value of gain parameter p, drawn from its distribution."""
    if p.kind == "choice":
        return trial.suggest_categorical(p.key, p.args)
    if p.type == "int":
        return trial.suggest_int(p.key, math.ceil(p.args[0]), math.floor(p.args[1]), log=p.kind == "loguniform")
    return trial.suggest_float(p.key, p.args[0], p.args[1], log=p.kind == "loguniform")


class TuneSpec:
    def __init__(self, path):
        spec = Spec(path)
        spec.check_keys({"scene", "set", "controller", "controller_set", "duration", "trials", "parallel_trials",
                         "seed", "batch", "objective", "max_saturation", "gains", "plants", "sampling"})
        root = spec.root.value
        for required in ("scene", "controller", "duration", "trials", "seed", "batch", "gains"):
            if required not in root:
                spec.refuse(required, "missing")
        self.spec_path = spec.path
        self.scene_path = spec.path_of("scene", root["scene"])
        self.controller_path = controller_path_of(spec, root["controller"])  # `default`: the built-in one
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
        self.metric = spec.text("objective.metric", obj["metric"]) if "metric" in obj else "max_track"
        if self.metric not in METRICS:
            spec.refuse("objective.metric", f"expected one of {', '.join(METRICS)}, got {self.metric!r}", obj["metric"])
        self.percentile = _percentile(spec, obj["percentile"]) if "percentile" in obj else 99.0

        scene_types = {k["key"]: k["type"] for k in gimbalsim.keys()}
        # the old spellings too (friction1.mu is joint1.friction.mu), as the sweep's spec reads them
        scene_types.update({old: scene_types[key] for old, key in gimbalsim.key_aliases().items()})
        sets = spec.known_mapping("set", scene_types, "scene", gimbalsim.key_aliases())
        set_values = {k: spec.value(f"set.{k}", n) for k, n in sets.items()}
        try:
            self.base = gimbalsim.load_scene(self.scene_path, plant_overrides(set_values),  # a closed loop's step
                                             sources={k: (spec.path, n.line) for k, n in sets.items()})
        except gimbalsim.SceneError as e:
            spec.refuse(f"set.{e.key}" if e.key in sets else "scene", str(e), sets.get(e.key, root["scene"]))
        plant_keys = spec.mapping("plants", root["plants"]) if "plants" in root else {}
        self.base, self.sampling = _sampling.apply(spec, root, self.base, [*sets, *plant_keys], closed=True,
                                                   varied=plant_keys)
        ctrl_types = {k["key"]: k["type"] for k in gimbalsim.controller_keys()}
        csets = spec.known_mapping("controller_set", ctrl_types, "controller (see `pointing_controller --keys`)")
        self.controller_set = {k: spec.value(f"controller_set.{k}", n) for k, n in csets.items()}
        try:
            self.controller = gimbalsim.Controller(self.controller_path, self.controller_set,
                                                   sources={k: (spec.path, n.line) for k, n in csets.items()})
        except gimbalsim.SceneError as e:
            spec.refuse(f"controller_set.{e.key}" if e.key in csets else "controller", str(e),
                        csets.get(e.key, root["controller"]))
        period = self.controller.period
        why = _gimbalsim._whole_multiple_problem(self.duration, period, "control.period")
        if why:  # the C++ keys' own rule (isWholeMultiple)
            spec.refuse("duration", f"must be a whole number of control periods: {why}", root["duration"])
        if why := ticks_too_many(self.duration, period):  # (pass 104) each trial's closed loops in memory
            spec.refuse("duration", why, root["duration"])
        # The score is over the profile's track (Controller.windows, the closed loop's own boundaries):
        # a run that ends before it would score NaN for every trial.
        track_start, track_end = self.controller.windows[METRIC_WINDOWS[self.metric]]
        if not self.duration > track_start:
            spec.refuse("duration", f"the run ends at {seconds(self.duration)} s, before the "
                        f"{METRIC_WINDOWS[self.metric]} window [{seconds(track_start)}, {seconds(track_end)}) s of "
                        f"objective.metric {self.metric}", root["duration"])

        self.gains = []
        gain_nodes = spec.mapping("gains", root["gains"])
        for key, node in gain_nodes.items():
            p = parse_parameter(spec, "gains", key, node, ctrl_types, CONTROLLER_KEYS)
            if p.kind not in GAIN_DISTRIBUTIONS:
                spec.refuse(f"gains.{key}", f"{p.kind}: gains take {', '.join(GAIN_DISTRIBUTIONS)}", node)
            if p.kind == "choice" and not all(isinstance(v, (int, float, str)) for v in p.args):
                spec.refuse(f"gains.{key}", "choice: a gain's choices are numbers or names", node)
            if len(set(map(str, p.args))) < 2:  # every trial would run this gain at one value
                spec.refuse(f"gains.{key}", f"{p.kind} over one value {p.args[0]!r}: nothing to search; give it "
                            "under controller_set", node)
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
        # one quantity in one place, whatever its spelling, as a sweep's spec (pass 102: set: beside plants: in
        # another spelling was taken, the set value recorded and never acting)
        twice, set_and_dispersed = quantities_given_twice((("set", sets), ("plants", plants)), gimbalsim.key_aliases())
        if twice:
            spec.refuse(*twice[0])
        params = [parse_parameter(spec, "plants", k, n, scene_types) for k, n in plants.items()]
        check_within(spec, "plants", params, [], self.base.values())
        self._refuse_keys_that_do_not_act(spec, params, sets, csets)
        for why in set_and_dispersed:
            spec.refuse(*why)
        for p in params:  # each end alone; a disk within a dispersed key at the rim each of its ends gives
            for trial in p.trials():
                try:
                    self.base.replace(plant_overrides(trial), sources={k: (spec.path, p.node.line) for k in trial})
                except gimbalsim.SceneError as e:
                    what = ", ".join(f"{k}={v!r}" for k, v in trial.items())
                    spec.refuse(f"plants.{p.key}", f"{p.end_note(trial[p.key])}the scene refuses {what}: "
                                f"{e.problems[0]['text']}", p.node)
        self.plants = Design(params, [], self.batch, self.seed, self.base.values())
        # (pass 78) plants that cannot differ are one plant scored batch times, as a sweep refuses its samples
        if self.batch > 1 and not any(p.spreads() for p in params):
            what = ("each plant key takes one value (a range of width 0 or narrower than 1e-12 of its ends, a "
                    "radius of 0, a choice of one)" if params else "no plant key is dispersed")
            spec.refuse("batch", f"{what}: the {self.batch} plants are one plant, which each trial's percentile "
                        f"would count {self.batch} times; give batch: 1, or a plant key that spreads", root["batch"])
        # Trial 0 is the baseline: the configuration's own gains, which the ranges must hold.
        own = self.controller.values()
        self.baseline = {}
        for p in self.gains:
            v = float(own[p.key]) if p.type == "number" else int(own[p.key]) if p.type == "int" else own[p.key]
            if not (v in p.args if p.kind == "choice" else p.args[0] <= v <= p.args[1]):
                spec.refuse(f"gains.{p.key}", f"the range leaves out the configuration's own value {v!r}: trial 0 "
                            "runs the configuration's gains (the baseline)", p.node)
            self.baseline[p.key] = v
        # what a resumed study must share (the trial count may grow)
        self.fingerprint = json.dumps({"scene": self.base.values(), "controller": own, "duration": self.duration,
                                       "seed": self.seed, "batch": self.batch, "metric": self.metric,
                                       "percentile": self.percentile, "max_saturation": self.max_saturation,
                                       "gains": {p.key: [p.kind, p.args] for p in self.gains},
                                       "plants": [[p.key, p.kind, p.args] for p in params]}, sort_keys=True)

    def _refuse_keys_that_do_not_act(self, spec, plants, sets, csets):
        """A gain or plant key the tuned loop never reads: every trial would
        run the same loop, recorded as if it differed (as a sweep refuses it)."""
        aliases = gimbalsim.key_aliases()
        entries = [(f"gains.{p.key}", CONTROLLER_PREFIX + p.key, p.node) for p in self.gains] + \
                  [(f"plants.{p.key}", aliases.get(p.key, p.key), p.node) for p in plants]
        takes = {**takes_of(self.gains, [], {}, CONTROLLER_PREFIX), **takes_of(plants, [], aliases)}
        values = {k: str(v) for k, v in self.base.values().items()}
        values["sim.duration"] = repr(self.duration)  # the study's run length, not the scene's
        values.update({CONTROLLER_PREFIX + k: str(v) for k, v in self.controller.values().items()})
        dispersed = {k for _, k, _ in entries}
        for where, key, node in entries:
            # the objective reads the truth error alone (the default unread_ticks: TRUTH_ONLY)
            why = idle_reason(key, values, dispersed, takes, closed=True)
            if why is not None:
                spec.refuse(where, f"not read by the tuned loop ({why}): every trial would run the same loop", node)
        # set: and controller_set: alike (set: sim.duration too: the tuner's duration: is every run's length)
        refuse_idle_set(spec, [(f"set.{k}", aliases.get(k, k), n) for k, n in sets.items()] +
                        [(f"controller_set.{k}", CONTROLLER_PREFIX + k, n) for k, n in csets.items()],
                        values, dispersed, takes, True, "the tuned loop",
                        controller=("controller", spec.root.value["controller"]))

    def input_files(self):
        """The files the study reads (spec, scene, controller configuration):
        none of its outputs may be one of them (_output.check_outputs)."""
        return [self.spec_path, self.scene_path, self.controller_path]
