"""A sweep spec checked whole before anything runs: the base scene, the
design of dispersed keys, the closed loop's controller, phases and indices
(_closed_spec.py), and the fingerprint a resume must match."""
import json
import re

import gimbalsim
from . import _provenance
from ._closed_spec import CONTROLLER_PREFIX, ClosedLoopSpec, idle_in_controller
from ._spec import Spec
from .dispersion import Design, check_within, design_size, parse_parameter

METRICS = ["pointing_error_max", "pointing_error_final", "peak_contact_force", "peak_joint2_force", "impacts",
           "continuous_contact_from", "impacts_joint1", "impacts_joint2", "max_tilt1", "max_tilt2"]
# Per joint: impacts at its ends and the largest tilt of its journal (0 for a
# joint without clearance or a planar one: it cannot tilt).
# The antenna's sensors (MODEL.md 11.6): recorded in a closed loop, but no figure a sweep reads depends on them.
ANTENNA_SENSOR_KEYS = ("sensors.antenna", "sensors.tracker_")
JOINT_METRICS = ["max_tilt1", "max_tilt2"]  # a closed loop's, from the truth at its ticks
METRIC_UNITS = {"pointing_error_max": "rad", "pointing_error_final": "rad", "peak_contact_force": "N",
                "peak_joint2_force": "N", "impacts": "", "continuous_contact_from": "s", "wall_time": "s",
                "t_end": "s", "impacts_joint1": "", "impacts_joint2": "", "max_tilt1": "rad",
                "max_tilt2": "rad"}  # a closed loop's index_phase columns are in rad
MAX_SAMPLES = 10_000_000


class SweepSpec:
    """A checked sweep spec: the base scene (file + set), the design, and a
    fingerprint that a resume must match."""

    def __init__(self, path, folder=None):
        spec = Spec(path, folder)  # folder: where its paths are read from (a replay's copy: the original's)
        spec.check_keys({"scene", "set", "samples", "seed", "parameters", "grid", "controller", "controller_set",
                         "phases", "indices"})
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
        params = spec.mapping("parameters", root["parameters"]) if "parameters" in root else {}
        grid = spec.known_mapping("grid", key_types, "scene")
        # One key in one place, whatever its spelling (friction1.mu is joint1.friction.mu): two
        # spellings would both be recorded while one value acts.
        aliases = gimbalsim.key_aliases()
        seen = {}
        for section, mapping in (("parameters", params), ("grid", grid)):
            for key, node in mapping.items():
                canonical = aliases.get(key, key)
                if canonical in seen:
                    spec.refuse(f"{section}.{key}", f"the same key as {seen[canonical]}: give it in one place", node)
                seen[canonical] = f"{section}.{key}"
        self.grid = []
        for key, node in grid.items():
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
        # closed loop: controller keys are dispersed as controller.<key>, never confused with the scene's
        self.closed = None
        if "controller" in root:
            self.closed = ClosedLoopSpec(spec, root, float(self.base.values()["sim.duration"]))
            key_types.update({CONTROLLER_PREFIX + k: t for k, t in self.closed.key_types.items()})
        self.parameters = [parse_parameter(spec, "parameters", k, n, key_types) for k, n in params.items()]
        if not self.parameters and not self.grid:
            spec.refuse("parameters", "nothing is dispersed: give parameters or grid")
        check_within(spec, "parameters", self.parameters, [k for k, _ in self.grid], self.base.values())
        self._refuse_keys_that_do_not_act(spec, grid)
        # Values the scene would refuse are refused now, at the spec's line.
        for p in self.parameters:
            for v in p.extremes():
                if p.key.startswith(CONTROLLER_PREFIX):
                    self.closed.load(spec, f"parameters.{p.key}", {p.key[len(CONTROLLER_PREFIX):]: v}, p.node)
                else:
                    self._try(spec, f"parameters.{p.key}", {p.key: v}, p.node)
        for (key, values), node in zip(self.grid, grid.values()):
            for v in values:
                if key.startswith(CONTROLLER_PREFIX):
                    self.closed.load(spec, f"grid.{key}", {key[len(CONTROLLER_PREFIX):]: v}, node)
                else:
                    self._try(spec, f"grid.{key}", {key: v}, node)
        self.design = Design(self.parameters, self.grid, self.samples, self.seed, self.base.values())
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

    def _refuse_keys_that_do_not_act(self, spec, grid):
        """A key whose value this kind of run never reads would be recorded as
        applied while every run ignores it: refused at its line."""
        aliases = gimbalsim.key_aliases()
        if self.closed is not None:
            idle = {"sim.duration": "the closed loop runs for the spec's sim.duration (set:), one length for all",
                    "sim.output_interval": "the closed loop records every control period",
                    "torque.tau1": "the controller commands the torque", "torque.tau2": "the controller commands "
                    "the torque"}
        else:
            idle = {"torque.limit": "the firmware's motor limit: an open-loop run applies the scene's torques as "
                    "they are"}
        dispersed = [(f"parameters.{p.key}", p.key, p.node) for p in self.parameters] + \
                    [(f"grid.{k}", k, n) for k, n in grid.items()]
        dispersed_keys = {aliases.get(k, k) for _, k, _ in dispersed}
        scene = self.base.values()  # read once: each key is judged against the same scene
        for where, key, node in dispersed:
            canonical = aliases.get(key, key)
            why = idle.get(canonical) or _idle_in_scene(canonical, scene, dispersed_keys)
            if why is None and self.closed is not None and canonical.startswith(CONTROLLER_PREFIX):
                why = idle_in_controller(canonical[len(CONTROLLER_PREFIX):], self.closed.values, dispersed_keys)
            if why is None and self.closed is not None:
                why = _idle_in_sensors(canonical, scene, dispersed_keys)
            if why is None and canonical.startswith(ANTENNA_SENSOR_KEYS):
                why = "the controller does not use the antenna sensors yet (docs/MODEL.md 11.6)"
            if why is None and self.closed is None and canonical.startswith("sensors."):
                why = "an open-loop run has no sensors (they act in a closed-loop sweep: name its controller)"
            if why is not None:
                spec.refuse(where, f"not read by this sweep's runs ({why}): a dispersed value would be recorded "
                            "but never act", node)

    def _try(self, spec, where, overrides, node):
        try:
            self.base.replace(overrides, sources={k: (spec.path, node.line) for k in overrides})
        except gimbalsim.SceneError as e:
            spec.refuse(where, f"the scene refuses {overrides}: {e.problems[0]['text'] if e.problems else e}", node)

    def input_files(self):
        """The files the sweep reads (spec, scene, controller configuration):
        none of its outputs may be one of them (_output.check_outputs)."""
        return [self.spec_path, self.scene_path, self.closed.controller_path if self.closed else None]

    def header(self):
        """The columns by the names the code uses (scene keys, metric names)."""
        return ["sample"] + self.design.columns() + ["status"] + ["reason"] * self.text_columns + self.metrics + \
            ["wall_time"] + _provenance.columns(self)

    def csv_header(self):
        """header() as the journal and results.csv name it: the project's CSV
        convention (docs/usage.md), e.g. contact.clearance -> contact_clearance_m."""
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


# Star tracker keys that act only through its samples: idle when its outage covers the whole run.
_STAR_SAMPLE_KEYS = ("sensors.star_tracker_noise", "sensors.star_tracker_rate", "sensors.star_tracker_latency")


def _idle_in_sensors(key, scene, dispersed):
    """Why a sensor key cannot act (None if it can): the star tracker's
    sampling keys under an outage over the whole run [0, sim.duration]."""
    if key not in _STAR_SAMPLE_KEYS or {"sensors.star_tracker_outage", "sim.duration"} & dispersed:
        return None
    start, end = (float(x) for x in str(scene["sensors.star_tracker_outage"]).strip("[]").split(","))
    if start <= 0.0 and end >= float(scene["sim.duration"]):
        return f"sensors.star_tracker_outage [{start:g}, {end:g}] s covers the whole run: no star tracker sample is taken"
    return None


def _idle_in_scene(key, scene, dispersed):
    """Why `key` cannot act in this scene (None if it can): a bearing key on
    an ideal joint, a tilt key on a planar bearing, an adaptive-step key under
    the fixed policy, a base key on a fixed base. Nothing is judged when the
    deciding key (structure.*, sim.substep_policy) is itself dispersed."""
    joints = {j: scene.get(f"structure.joint{j}") for j in (1, 2)}
    rules = []
    for j in (1, 2):  # a joint's own bearing keys
        rules.append(((f"joint{j}.contact.", f"joint{j}.friction.", f"initial.ecc{j}"), f"structure.joint{j}",
                      joints[j] != "ideal", f"joint {j} is ideal: it has no bearing"))
        rules.append(((f"joint{j}.contact.bearing_length",), f"structure.joint{j}", joints[j] == "spatial",
                      f"joint {j}'s bearing is planar: it cannot tilt"))
    any_clearance = any(k != "ideal" for k in joints.values())
    rules += [(("contact.bearing_length",), "structure.joint", any(k == "spatial" for k in joints.values()),
               "no joint's bearing is spatial: none can tilt"),
              (("contact.", "friction.", "initial.ecc"), "structure.joint", any_clearance,
               "both joints are ideal: no bearing"),
              (("sim.substep_tol", "sim.substep_min", "sim.substep_max"), "sim.substep_policy",
               scene.get("sim.substep_policy") == "adaptive", "sim.substep_policy is fixed: only the adaptive "
               "policy reads it"),
              (("base.",), "structure.base", scene.get("structure.base") != "fixed",
               "structure.base is fixed: the base never moves")]
    for prefixes, decider, acts, why in rules:
        if key.startswith(prefixes) and not acts and not any(d.startswith(decider) for d in dispersed):
            return why
    return _bearing_key_idle(key, joints, scene, dispersed)


# Bearing keys read only under some laws: the law's key and which of its values read the key.
_READ_UNDER = {"friction.mu": ("friction.law", lambda law: law != "none"),
               "friction.v_a": ("friction.law", lambda law: law == "ambrosio"),
               "friction.v_b": ("friction.law", lambda law: law == "ambrosio"),
               "contact.restitution": ("contact.damping", lambda law: law != "none"),
               "contact.v0_min": ("contact.damping", lambda law: law != "none")}


def _bearing_key_idle(key, joints, scene, dispersed):
    """Why a bearing key (contact.*, friction.*, or a joint's own jointJ.*)
    is read on no joint (None if it is read on one): on each joint with a
    bearing, a shared key is overridden by the joint's own value (in the
    scene or dispersed; a clearance is stored as the journal radius), or the
    joint's law does not read it (friction.mu under friction.law none)."""
    m = re.fullmatch(r"(?:joint([12])\.)?((?:contact|friction)\..+)", key)
    if m is None or any(d.startswith("structure.joint") for d in dispersed):
        return None
    own, shared = (int(m.group(1)) if m.group(1) else None), m.group(2)
    bearings = [j for j in ((own,) if own else (1, 2)) if joints[j] != "ideal"]
    if not bearings:
        return None  # the structure's rules say so
    names = {shared, "contact.journal_radius"} if shared in ("contact.clearance", "contact.journal_radius") else {shared}
    why = []
    for j in bearings:
        overriding = sorted(f"joint{j}.{n}" for n in names if f"joint{j}.{n}" in scene or f"joint{j}.{n}" in dispersed)
        if own is None and overriding:
            sets = f" (joint{j}.contact.clearance sets it)" if overriding[0].endswith("journal_radius") else ""
            why.append(f"overridden by {overriding[0]}{sets}")
            continue
        law_key, reads = _READ_UNDER.get(shared, (None, None))
        if law_key is None or any(d in (law_key, f"joint{j}.{law_key}") for d in dispersed):
            return None
        law = scene.get(f"joint{j}.{law_key}", scene.get(law_key))
        if reads(law):
            return None
        why.append(f"joint {j}'s {law_key} is {law}")
    return "on every joint with a bearing: " + "; ".join(why)
