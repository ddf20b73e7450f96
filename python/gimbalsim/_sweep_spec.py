"""A sweep spec checked whole before anything runs: the base scene, the
design of dispersed keys, the closed loop's controller, phases and indices
(_closed_spec.py), and the fingerprint a resume must match."""
import json

import gimbalsim
from . import _provenance, _sampling
from ._closed_spec import CONTROLLER_PREFIX, ClosedLoopSpec, plant_overrides
from ._idle_keys import idle_reason, refuse_idle_set, takes_of
from ._idle_sensors import KNOWLEDGE, KNOWLEDGE_AT_THE_END, TRUTH_ONLY
from ._one_quantity import quantities_given_twice
from ._spec import Spec
from .indices import seconds
from .dispersion import Design, check_within, design_size, parse_parameter

METRICS = ["pointing_error_max", "pointing_error_final", "peak_contact_force", "peak_joint2_force", "impacts",
           "continuous_contact_from", "impacts_joint1", "impacts_joint2", "max_tilt1", "max_tilt2"]
# Per joint: impacts at its ends and the largest tilt of its journal (0 for a
# joint without clearance or a planar one: it cannot tilt).
JOINT_METRICS = ["max_tilt1", "max_tilt2"]  # a closed loop's, from the truth at its ticks
METRIC_UNITS = {"pointing_error_max": "rad", "pointing_error_final": "rad", "peak_contact_force": "N",
                "peak_joint2_force": "N", "impacts": "", "continuous_contact_from": "s", "wall_time": "s",
                "t_end": "s", "impacts_joint1": "", "impacts_joint2": "", "max_tilt1": "rad",
                "max_tilt2": "rad"}  # a closed loop's index_phase columns are in rad
MAX_SAMPLES = 10_000_000
NOT_READ = "not read by this sweep's runs"  # how a key no run reads is refused (gimbalsim.allocate tells it apart)


def _check_controller_key(spec, where, key, node, ctrl_types, closed):
    """A dispersed controller.<key>: refused unless the sweep is closed-loop and
    the key is the controller's, naming where controller keys go."""
    if not closed:
        spec.refuse(where, "a controller key, dispersed only by a closed-loop sweep: name its controller "
                    "(controller: default or a configuration file), then give it as controller.<key> under "
                    "parameters or grid (controller_set: for every sample alike)", node)
    if key not in ctrl_types:
        spec.refuse(where, f"not a key of the controller configuration (see gimbalsim.controller_keys() or "
                    f"docs/controller_keys.md): {key[len(CONTROLLER_PREFIX):]}", node)


def _within_note(p, trial, scene):
    """What a disk within a key reaches, for the refusal that names both keys ("" for any other trial)."""
    if p.kind != "disk" or "within" not in p.args:
        return ""
    within, fraction = p.args["within"], p.args["fraction"]
    value = trial[within] if within in trial else f"{scene.get(within)} (the scene's)"
    return f"disk: within {within}, fraction {fraction} of {within} {value} reaches {p.key} {trial[p.key]}: "


def _one_value(v):
    """A grid value as one point: a number whatever its spelling, a name as written."""
    return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v


class SweepSpec:
    """A checked sweep spec: the base scene (file + set), the design, and a
    fingerprint that a resume must match."""

    def __init__(self, path, folder=None, workdir=None, text=None):
        # where its paths are read from (a replay's copy: the original's); text: the spec's source, else the file's
        spec = Spec(path, folder, workdir, text)
        spec.check_keys({"scene", "set", "samples", "seed", "parameters", "grid", "controller", "controller_set",
                         "phases", "indices", "sampling"})
        root = spec.root.value
        for closed_only in ("controller_set", "phases", "indices"):
            if closed_only in root and "controller" not in root:
                spec.refuse(closed_only, "only for a closed-loop sweep: name its controller (controller: default "
                            "or a configuration file)", root[closed_only])
        for required in ("scene", "samples", "seed"):
            if required not in root:
                spec.refuse(required, "missing")
        self.scene_path = spec.path_of("scene", root["scene"])
        self.samples = spec.integer("samples", root["samples"], 1, MAX_SAMPLES)
        self.seed = spec.integer("seed", root["seed"], 0, 2**63 - 1)
        key_types = {k["key"]: k["type"] for k in gimbalsim.keys()}
        key_types.update({old: key_types[key] for old, key in gimbalsim.key_aliases().items()})
        sets = spec.known_mapping("set", key_types, "scene", gimbalsim.key_aliases())
        self.set = {k: spec.value(f"set.{k}", n) for k, n in sets.items()}
        self._set_nodes = sets
        params = spec.mapping("parameters", root["parameters"]) if "parameters" in root else {}
        # controller.<key> is dispersed in closed loop only, and is no scene key: said so, not "not a key of the scene"
        ctrl_types = {CONTROLLER_PREFIX + k["key"]: k["type"] for k in gimbalsim.controller_keys()}
        grid_node = root.get("grid")
        for section, body in (("parameters", params),
                              ("grid", spec.mapping("grid", grid_node) if grid_node is not None else {})):
            for key, node in body.items():
                if key.startswith(CONTROLLER_PREFIX):
                    _check_controller_key(spec, f"{section}.{key}", key, node, ctrl_types, "controller" in root)
        if "controller" in root:
            key_types.update(ctrl_types)
        grid = spec.known_mapping("grid", key_types, "scene")
        # One quantity in one place, whatever its spelling (_one_quantity.py)
        aliases = gimbalsim.key_aliases()
        twice, set_and_dispersed = quantities_given_twice((("set", sets), ("parameters", params), ("grid", grid)),
                                                          aliases)
        if twice:
            spec.refuse(*twice[0])
        self.grid = []
        for key, node in grid.items():
            if not isinstance(node.value, list) or not node.value:
                spec.refuse(f"grid.{key}", "expected a non-empty list of values", node)
            if key_types.get(key) in ("vec2", "vec3", "inertia"):  # its cell was one text, its applied_ cells numbers
                spec.refuse(f"grid.{key}", f"a {key_types[key]} key is dispersed under parameters: "
                            "({choice: [...]}); a grid point holds numbers and names", node)
            values = [spec.value(f"grid.{key}", v) for v in node.value]
            # (pass 114) a point given twice ran its units twice into one budget (0.0 and -0.0, 2000 and 2000.0 one)
            for j, v in enumerate(values):
                if (i := next(i for i, w in enumerate(values) if _one_value(w) == _one_value(v))) < j:
                    spec.refuse(f"grid.{key}", f"{v!r} given twice (items {i + 1} and {j + 1}): a grid point runs "
                                "once, and twice its units would count twice in its budget", node.value[j])
            self.grid.append((key, values))
        # counted before anything is built or tried: a grid can multiply to more than memory holds
        size = design_size(self.grid, self.samples)
        if size > MAX_SAMPLES:
            spec.refuse("grid" if self.grid else "samples",
                        f"{size} samples in all (samples x grid points), more than the limit {MAX_SAMPLES}",
                        root["grid"] if self.grid else root["samples"])
        try:
            # a closed loop's sim.step takes the output interval it never reads with it (plant_overrides)
            self.base = gimbalsim.load_scene(self.scene_path,
                                             plant_overrides(self.set) if "controller" in root else self.set,
                                             sources={k: (spec.path, n.line) for k, n in sets.items()})
        except gimbalsim.SceneError as e:
            node = sets.get(e.key) if e.set_index else None
            spec.refuse(f"set.{e.key}" if node else "scene", str(e), node or root["scene"])
        # the stepping every sample takes (_sampling.py), the base scene with its overrides
        self.base, self.sampling = _sampling.apply(spec, root, self.base, [*self.set, *params, *grid],
                                                   "controller" in root, varied=[*params, *grid])
        # closed loop: controller keys are dispersed as controller.<key>, never confused with the scene's
        self.closed = None
        if "controller" in root:
            self.closed = ClosedLoopSpec(spec, root, float(self.base.values()["sim.duration"]),
                                         [aliases.get(k, k) for k in [*params, *grid]])
        self.parameters = [parse_parameter(spec, "parameters", k, n, key_types) for k, n in params.items()]
        if not self.parameters and not self.grid:
            spec.refuse("parameters", "nothing is dispersed: give parameters or grid")
        check_within(spec, "parameters", self.parameters, [k for k, _ in self.grid], self.base.values(), self.grid)
        self._refuse_keys_that_do_not_act(spec, grid)
        for why in set_and_dispersed:
            spec.refuse(*why)
        # Values the scene would refuse are refused now, at the spec's line.
        # A disk within a key is tried at the rim that key's ends give, with that key's value (dispersion.trials).
        for p in self.parameters:
            drawn_profiles = []  # a dispersed profile key's controllers at its range's ends (check_draws)
            for trial in p.trials():
                ctrl = {k[len(CONTROLLER_PREFIX):]: v for k, v in trial.items() if k.startswith(CONTROLLER_PREFIX)}
                scene = {k: v for k, v in trial.items() if not k.startswith(CONTROLLER_PREFIX)}
                note = p.end_note(trial[p.key])  # a normal's tail: which one
                if ctrl:
                    c = self.closed.load(spec, f"parameters.{p.key}", ctrl, p.node, note=note)
                    if "control.period" in ctrl:
                        self._check_period(spec, p, c)
                    if any(k.startswith("profile.") for k in ctrl):
                        drawn_profiles.append(c)
                if scene and not self._refused_alone(scene, p):  # a within key's own value: refused at its line
                    self._try(spec, f"parameters.{p.key}", scene, p.node,
                              note + _within_note(p, trial, self.base.values()))
            if drawn_profiles:
                self.closed.check_draws(spec, f"parameters.{p.key}", drawn_profiles, p.node)
        # A grid point's controller reaches the phases as the spec's must (each value alone, as the scene's are
        # tried): every sample there would be NaN in a phase its runs end before.
        for (key, values), node in zip(self.grid, grid.values()):
            for v in values:
                if key.startswith(CONTROLLER_PREFIX):
                    c = self.closed.load(spec, f"grid.{key}", {key[len(CONTROLLER_PREFIX):]: v}, node)
                    drawn = any(p.key.startswith(CONTROLLER_PREFIX + "profile.") for p in self.parameters)
                    self.closed.check_point(spec, f"grid.{key}", c, node, f"{key} = {v}: ", self._steps(), drawn)
                else:
                    self._try(spec, f"grid.{key}", {key: v}, node)
        # A closed loop ticks whole control periods of whole steps: a step drawn from a range divides no period
        # (pass 56: every sample was refused at its run, the spec accepted)
        step = next((p for p in self.parameters if p.key == "sim.step"), None)
        if self.closed is not None and step is not None and step.kind != "choice":
            spec.refuse("parameters.sim.step", f"{step.kind}: a closed loop's sim.step is given as a choice of "
                        "steps that divide control.period (a grid, or {choice: [...]}): a draw from a range divides "
                        "none, and every sample would be refused", step.node)
        # The period every sample runs at, when none is dispersed: it must tick at one of the study's steps.
        period_key = CONTROLLER_PREFIX + "control.period"
        if self.closed is not None and period_key not in [p.key for p in self.parameters] + [k for k, _ in self.grid]:
            given = "control.period" in self.closed.set_nodes
            self.closed.check_period(spec, "controller_set.control.period" if given else "controller",
                                     self.closed.controller, self.closed.set_nodes["control.period"] if given
                                     else root["controller"], "", self._steps())
        self.design = Design(self.parameters, self.grid, self.samples, self.seed, self.base.values())
        # (pass 34) draws that cannot differ are one unit run n times: a budget over them counted it n times
        if self.samples > 1 and not any(p.spreads() for p in self.parameters):
            what = ("each parameter takes one value (a range of width 0 or narrower than 1e-12 of its ends, a "
                    "radius of 0, a choice of one)" if self.parameters else "no parameter is dispersed")
            spec.refuse("samples", f"{what}: the {self.samples} draws{' at each grid point' if self.grid else ''} "
                        f"are one unit, which a budget would count {self.samples} times; give samples: 1, or a "
                        "parameter that spreads", root["samples"])
        self.spec_path = spec.path
        self.spec_text, self.spec_folder = spec.source_text, spec.folder.absolute()  # for the replay's copy
        self.fingerprint = json.dumps({"scene": self.base.values(), "seed": self.seed, "samples": self.samples,
                                       "parameters": {p.key: [p.kind, p.args] for p in self.parameters},
                                       "grid": self.grid,
                                       **({"closed_loop": self.closed.plain()} if self.closed else {})},
                                      sort_keys=True)
        # open loop: the metrics against the ideal-joint twin; closed loop: an index per phase, and why one is NaN
        self.metrics = self.closed.metrics() + JOINT_METRICS + ["t_end"] if self.closed else METRICS
        self.text_columns = 1 if self.closed else 0

    def _steps(self):
        """The sim.step values [s] the study gives: the scene's, a grid's or a
        choice's; None when drawn from a range (a period is not judged against it)."""
        for key, values in self.grid:
            if key == "sim.step":
                return [float(v) for v in values]
        p = next((p for p in self.parameters if p.key == "sim.step"), None)
        if p is None:
            return [self.base.step]
        return [float(v) for v in p.args] if p.kind == "choice" else None

    def _check_period(self, spec, p, controller):
        """A dispersed control.period: a choice of periods the plant and the run
        tick at (a range draws periods that are no whole number of sim.step)."""
        where = f"parameters.{p.key}"
        if p.kind != "choice":
            spec.refuse(where, f"{p.kind}: a control period is given as a choice of whole multiples of sim.step "
                        f"({seconds(self.base.step)} s): a draw from a range is none", p.node)
        self.closed.check_period(spec, where, controller, p.node, "", self._steps())

    def _refuse_keys_that_do_not_act(self, spec, grid):
        """A key whose value this kind of run never reads would be recorded as
        applied while every run ignores it: refused at its line (_idle_keys.py)."""
        aliases = gimbalsim.key_aliases()
        dispersed = [(f"parameters.{p.key}", p.key, p.node) for p in self.parameters] + \
                    [(f"grid.{k}", k, n) for k, n in grid.items()]
        dispersed_keys = {aliases.get(k, k) for _, k, _ in dispersed}
        takes = takes_of(self.parameters, self.grid, aliases)
        values = {k: str(v) for k, v in self.base.values().items()}  # read once: each key judged alike
        if self.closed is not None:
            values.update({CONTROLLER_PREFIX + k: str(v) for k, v in self.closed.values.items()})
        # the last ticks' measurements: only the knowledge index reads an estimate (a tick's own); the last
        # tick's over a phase that holds it (at sim.duration): the track phase, which runs to the run's end, or
        # a window [t0, t1) with t1 past it (the spec accepts t1 up to 1e-9 s beyond); the truth shows a
        # measurement two ticks later (_idle_sensors.TRUTH_ONLY)
        knowledge = self.closed is not None and any(ix.name == "knowledge" for ix in self.closed.indices)
        unread = TRUTH_ONLY if not knowledge else KNOWLEDGE_AT_THE_END if any(
            w is None and name == "track" or w is not None and w[1] > self.closed.duration_s
            for name, w in self.closed.phases) else KNOWLEDGE
        for where, key, node in dispersed:
            why = idle_reason(aliases.get(key, key), values, dispersed_keys, takes, self.closed is not None,
                              unread)
            if why is not None:
                spec.refuse(where, f"{NOT_READ} ({why}): a dispersed value would be recorded "
                            "but never act", node)
        # set: and controller_set: alike, judged with the loaded values (sim.duration is the closed loop's length)
        fixed = [(f"set.{k}", aliases.get(k, k), n) for k, n in self._set_nodes.items()
                 if aliases.get(k, k) != "sim.duration"]
        if self.closed is not None:
            fixed += [(f"controller_set.{k}", CONTROLLER_PREFIX + k, n) for k, n in self.closed.set_nodes.items()]
        refuse_idle_set(spec, fixed, values, dispersed_keys, takes, self.closed is not None, "this sweep's runs",
                        unread, ("controller", spec.root.value["controller"]) if self.closed is not None else None)

    def _plant(self, overrides):
        """Scene overrides as a sample's scene is loaded with them (_closed_sample.load_sample)."""
        return overrides if self.closed is None else plant_overrides(overrides)

    def _refused_alone(self, overrides, p):
        """Whether the scene refuses the values of `overrides` other than p's own (a disk's within key)."""
        rest = {k: v for k, v in overrides.items() if k != p.key}
        try:
            if rest:
                self.base.replace(self._plant(rest))
        except gimbalsim.SceneError:
            return True
        return False

    def _try(self, spec, where, overrides, node, note=""):
        try:
            self.base.replace(self._plant(overrides), sources={k: (spec.path, node.line) for k in overrides})
        except gimbalsim.SceneError as e:
            spec.refuse(where, f"{note}the scene refuses {overrides}: {e.problems[0]['text'] if e.problems else e}",
                        node)

    def input_files(self):
        """The files the sweep reads (spec, scene, controller configuration):
        none of its outputs may be one of them (_output.check_outputs)."""
        return [self.spec_path, self.scene_path, self.closed.controller_path if self.closed else None]

    def header(self):
        """The columns by the names the code uses (scene keys, metric names)."""
        return ["sample"] + self.design.columns() + ["status"] + ["reason"] * self.text_columns + self.metrics + \
            ["wall_time"] + _provenance.columns(self)

    _csv_header = None  # made once: a resume checks every journal row against it

    def csv_header(self):
        """header() as the journal and results.csv name it: the project's CSV
        convention (docs/usage.md), e.g. contact.clearance -> contact_clearance_m."""
        if self._csv_header is None:
            self._csv_header = self._make_csv_header()
        return list(self._csv_header)

    def _make_csv_header(self):
        units = {k["key"]: k["unit"] for k in gimbalsim.keys()}
        units.update({old: units[key] for old, key in gimbalsim.key_aliases().items()})
        if self.closed:
            units.update({CONTROLLER_PREFIX + k["key"]: k["unit"] for k in gimbalsim.controller_keys()})
        csv_name = gimbalsim._gimbalsim.csv_name
        names = ["sample"]
        for c in self.design.columns():  # "initial.ecc[0]" -> initial_ecc_0_m
            plain = c.replace(".", "_").replace("[", "_").replace("]", "")
            names.append(csv_name(plain, units.get(c.split("[")[0], "")))
        return names + ["status"] + ["reason"] * self.text_columns + \
            [csv_name(m, METRIC_UNITS.get(m, "rad")) for m in self.metrics + ["wall_time"]] + \
            _provenance.csv_names(self, csv_name, units)
