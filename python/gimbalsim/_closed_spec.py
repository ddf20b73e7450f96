"""The closed-loop part of a sweep spec: the controller (a configuration file
or the built-in default, its overrides), the phases and the pointing indices
(ECSS-E-ST-60-10C) each sample reports, all checked at the spec's lines.

    controller: default                 # or a configuration file, against the spec's folder
    controller_set: {azimuth.kp: 900}   # controller overrides for every sample
    phases: [slew, hold, track, {settled: [4.0, 5.0]}]   # the profile's segments or [t0, t1) in s
    indices:
      ape: {level: 0.9973, confidence: 0.95, requirement: 1.0e-4}
      rpe: {window: 0.1}
      pde: {window: 0.1, separation: 0.5}
      knowledge: {}

A dispersed controller key is named `controller.<key>` (e.g.
controller.azimuth.kp): scene and controller keys cannot be confused.
"""
import math

import gimbalsim
from . import _gimbalsim
from .indices import LEVEL_3SIGMA, MAX_REQUIREMENT_RAD, seconds

PROFILE_PHASES = ("slew", "hold", "track")
INDICES = ("ape", "rpe", "pde", "knowledge")
INDEX_KEYS = {"ape": set(), "knowledge": set(), "rpe": {"window"}, "pde": {"window", "separation"}}
CONTROLLER_PREFIX = "controller."


def plant_overrides(overrides):
    """A closed loop's scene overrides as the scene is loaded with them: one
    that changes sim.step takes sim.output_interval = that step. The closed
    loop records every control period and never reads output_interval (a
    key it refuses under set and parameters, _idle_keys), but the scene holds
    it to whole steps, an open-loop rule: a step the controller's period
    allows was refused for the scene file's interval (0.001 s no multiple of
    3e-4 s). Not written in the spec, nor in a row's applied_ columns: the
    run does not read it. Given this way, not as a rule the closed loop
    drops: the scene's own check stays whole for every other key."""
    if "sim.step" not in overrides or "sim.output_interval" in overrides:
        return overrides
    return {**overrides, "sim.output_interval": overrides["sim.step"]}


def controller_path_of(spec, node):
    """The spec's `controller:` as a path against its folder, or None for
    `default` (the built-in configuration): the same word in a sweep and a
    tuning spec."""
    return None if node.value == "default" else spec.path_of("controller", node)


def ticks_too_many(duration_s, period_s):
    """Why a closed loop of duration_s at period_s would not fit in this machine's free memory (closed_loop's own
    MemoryError, asked before any sample: pass 104, 1e5 s passed --check and every sample ended in a traceback),
    or None."""
    try:
        _gimbalsim._closed_loop_fits_in_memory(duration_s, period_s)
    except MemoryError as e:
        return f"{e}: every sample would be refused"
    return None


def profile_phases(controller, duration_s):
    """The profile's phases {name: (t0, t1)} [s] for a run of duration_s:
    the controller's own windows (Controller.windows, the closed loop's own
    definition, pointing/profile_windows.hpp), the track ending with the run's last tick."""
    windows = controller.windows
    track0 = windows["track"][0]
    end = duration_s + controller.period
    return {"slew": tuple(windows["slew"]), "hold": tuple(windows["hold"]),
            "track": (track0, max(end, track0 + 1e-9))}


class IndexSpec:
    """One index: its window [s], separation [s] (PDE), level, confidence and
    optional requirement [rad]."""

    def __init__(self, name, window=None, separation=None, level=LEVEL_3SIGMA, confidence=0.95, requirement=None):
        self.name, self.window, self.separation = name, window, separation
        self.level, self.confidence, self.requirement = level, confidence, requirement

    def plain(self):
        return {"window_s": self.window, "separation_s": self.separation, "level": self.level,
                "confidence": self.confidence, "requirement_rad": self.requirement}


class ClosedLoopSpec:
    """The controller, its overrides, the phases and the indices of a closed-loop sweep."""

    def __init__(self, spec, root, duration_s, varied=()):
        """varied: the keys the study disperses or grids (a profile key among them moves the profile's phases,
        so those are judged at each of its values, not at the base controller's: pass 55)."""
        node = root["controller"]
        self.profile_varied = any(k.startswith("controller.profile.") for k in varied)
        self.controller_path = controller_path_of(spec, node)
        self.key_types = {k["key"]: k["type"] for k in gimbalsim.controller_keys()}
        sets = spec.known_mapping("controller_set", self.key_types, "controller (see `pointing_controller --keys`)")
        self.set = {k: spec.value(f"controller_set.{k}", n) for k, n in sets.items()}
        self.set_nodes = sets  # each controller_set key's line: one another setting switches off is refused there
        self.controller = self.load(spec, "controller", {}, node, sets)
        self.values = self.controller.values()
        self.period_s = float(self.values["control.period"])
        self.duration_s = duration_s
        why = _gimbalsim._whole_multiple_problem(duration_s, self.period_s, "control.period")
        if why:  # the C++ keys' own rule (isWholeMultiple)
            spec.refuse("set.sim.duration" if "set" in root else "scene",
                        f"the closed loop runs whole control periods: sim.duration {seconds(duration_s)} s {why}",
                        root.get("set") or root["scene"])
        if why := ticks_too_many(duration_s, self.period_s):  # (pass 104) each sample's closed loop in memory
            given = root["set"].value.get("sim.duration") if "set" in root and isinstance(root["set"].value, dict) \
                else None
            spec.refuse("set.sim.duration" if given else "scene", why, given or root["scene"])
        self.phases = self._phases(spec, root)
        self.indices = self._indices(spec, root)
        self._check_reached(spec, root)

    def load(self, spec, where, extra, node, sets=None, note=""):
        """The controller with the spec's overrides and `extra`; refused at
        node, or at the controller_set key the controller names (note: what
        the tried value is, ahead of the refusal)."""
        overrides = dict(self.set)
        overrides.update(extra)
        try:
            return gimbalsim.Controller(self.controller_path, overrides)
        except gimbalsim.SceneError as e:
            if sets and e.key in sets:
                where, node = f"controller_set.{e.key}", sets[e.key]
            # what was tried: the value at hand, else the file and the spec's controller_set (pass 40 printed "{}")
            tried = extra if extra else "its file and controller_set" if self.set else "its file"
            spec.refuse(where, f"{note}the controller refuses {tried}: "
                        f"{e.problems[0]['text'] if e.problems else e}", node)

    def _phases(self, spec, root):
        """[(name, (t0, t1) or None for the profile's own)]."""
        if "phases" not in root:
            return [(p, None) for p in PROFILE_PHASES]
        node = root["phases"]
        if not isinstance(node.value, list) or not node.value:
            spec.refuse("phases", f"expected a list of {', '.join(PROFILE_PHASES)} or {{name: [t0, t1]}}", node)
        phases = []
        for item in node.value:
            if isinstance(item.value, str):
                if item.value not in PROFILE_PHASES:
                    spec.refuse("phases", f"unknown phase '{item.value}' (the profile's are "
                                f"{', '.join(PROFILE_PHASES)}; give others as {{name: [t0, t1]}})", item)
                phases.append((item.value, None))
                continue
            body = spec.mapping("phases", item)
            if len(body) != 1:
                spec.refuse("phases", "give one phase per item: {name: [t0, t1]}", item)
            name, window = next(iter(body.items()))
            if not name.isidentifier() or not name.islower():
                spec.refuse(f"phases.{name}", "a phase's name is a lower-case identifier (it names columns)", item)
            if name in PROFILE_PHASES:  # (pass 78) {track: [3.6, 3.9]} read as the profile's track in every report
                spec.refuse(f"phases.{name}", f"'{name}' is the profile's own phase (give it bare, as {name}); name "
                            "a window of your own otherwise", item)
            t = window.plain()
            if not (isinstance(t, list) and len(t) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                                for v in t)):
                spec.refuse(f"phases.{name}", f"expected [t0, t1], two times in s, got {t!r}", window)
            if not all(math.isfinite(v) for v in t):  # (pass 60) [0.1, inf] was told "0 <= t0 < t1", which it meets
                spec.refuse(f"phases.{name}", f"expected [t0, t1], two finite times in s, got {t!r} (a phase to the "
                            "run's end ends at sim.duration)", window)
            if not 0 <= t[0] < t[1]:
                spec.refuse(f"phases.{name}", f"expected [t0, t1] in s with 0 <= t0 < t1, got {t!r}", window)
            phases.append((name, (float(t[0]), float(t[1]))))
        names = [p for p, _ in phases]
        for name in names:
            if names.count(name) > 1:
                spec.refuse("phases", f"phase '{name}' given twice", node)
        return phases

    def _check_reached(self, spec, root):
        """Every phase, and every index's window inside it, lies within the
        run: a run that ends before (or inside) a phase would give every
        sample NaN there, so the spec is refused at its line instead."""
        nominal = profile_phases(self.controller, self.duration_s)
        if "phases" not in root:  # the profile's phases that have time (profile.hold_time 0: no hold)
            self.phases = [(p, w) for p, w in self.phases if p == "track" or nominal[p][1] > nominal[p][0]]
        sets = root["set"].value if "set" in root and isinstance(root["set"].value, dict) else {}
        duration_node = sets.get("sim.duration", root["scene"])
        items = {}
        if "phases" in root:
            for item in root["phases"].value:
                items[item.value if isinstance(item.value, str) else next(iter(item.value))] = item
        for kind, name, message in self._unreached(self.controller, self.period_s):
            if self.profile_varied and self.moves(name):
                continue  # judged at each value (check_point, check_draws), not at a profile no sample runs
            if kind == "index":
                spec.refuse(f"indices.{name}", message, root["indices"].value[name])
            where = items.get(name, duration_node)
            if kind == "run":
                spec.refuse(f"phases.{name}" if items else "sim.duration", message, where)
            spec.refuse(f"phases.{name}", message, items[name] if kind == "empty" else where)

    def check_point(self, spec, where, controller, node, note, steps, profile_drawn=False):
        """A grid point's controller (loaded with its values): check_period,
        and its runs reach every phase and index window as the spec's own
        must (_check_reached), else refused at node (where), note naming the point. With a profile key
        dispersed (profile_drawn), the phases that move with it are judged at its draws (check_draws), not at a
        profile no sample runs (pass 110: a gain on the grid was refused for the default hold_time)."""
        period = self.check_period(spec, where, controller, node, note, steps)
        for _, name, message in self._unreached(controller, period):
            if not (profile_drawn and self.moves(name)):
                spec.refuse(where, note + message, node)

    def moves(self, name):
        """Whether phase or index `name` moves with the profile: a profile phase, or an index judged in one."""
        profile_phases_named = {p for p, w in self.phases if w is None}
        return name in profile_phases_named or (name in {ix.name for ix in self.indices} and bool(profile_phases_named))

    def check_draws(self, spec, where, controllers, node):
        """A dispersed profile key: refused at node (where) only for a phase or index that the runs miss at
        every value tried (the key's range ends), since only then would every sample be NaN there."""
        missed = [{(kind, name): message for kind, name, message in self._unreached(c, self.period_s)
                   if self.moves(name)} for c in controllers]
        for key in missed[0] if missed else ():
            if all(key in m for m in missed[1:]):
                spec.refuse(where, f"at every value tried (its range's ends): {missed[0][key]}", node)

    def check_period(self, spec, where, controller, node, note, steps):
        """The controller's period [s], refused at node (where) unless it ticks
        the run (whole periods in sim.duration) and the plant at one of the
        study's steps (a whole number of sim.step; steps [s]: the values it
        gives, None when drawn from a range: not judged): else every sample
        would be refused at its run (load_sample)."""
        period = float(controller.values()["control.period"])
        problems = [] if steps is None else \
            [_gimbalsim._whole_multiple_problem(period, s, "the scene's step (sim.step)") for s in steps]
        if problems and all(problems):  # refused here, at its line
            why = problems[0] if len(steps) == 1 else \
                f"is a whole multiple of none of the steps the study gives ({', '.join(map(seconds, steps))} s)"
            spec.refuse(where, f"{note}control.period {seconds(period)} s {why}: every sample would be refused", node)
        why = _gimbalsim._whole_multiple_problem(self.duration_s, period, "control.period")
        if why:
            spec.refuse(where, f"{note}sim.duration {seconds(self.duration_s)} s with control.period "
                        f"{seconds(period)} s {why}: every sample would be refused", node)
        if why := ticks_too_many(self.duration_s, period):  # (pass 104) each sample's closed loop in memory
            spec.refuse(where, f"{note}{why}", node)
        return period

    def _unreached(self, controller, period_s):
        """(kind, name, why) of each phase ("empty", "tick", "run") or index
        ("index") the runs with this controller do not reach, in the spec's order."""
        nominal = profile_phases(controller, self.duration_s)
        tol = 1e-9 * max(1.0, self.duration_s)
        for ix in self.indices:  # a grid's control.period: an RPE window of one tick is 0 by construction
            if ix.name == "rpe" and ix.window < 2 * period_s - tol:
                yield "index", ix.name, (f"the window {seconds(ix.window)} s holds one control tick "
                                         f"({seconds(period_s)} s): its deviation from its own mean is 0 by "
                                         "construction")
        for name, window in self.phases:
            t0, t1 = window if window is not None else nominal[name]
            ends_with_run = window is None and name == "track"
            if not ends_with_run and not t1 > t0 + tol:  # e.g. profile.hold_time 0: no sample has a figure there
                yield "empty", name, (f"phase '{name}' [{seconds(t0)}, {seconds(t1)}) s is empty (the controller's "
                                      "profile gives it no time): leave it out of phases")
            first_tick = math.ceil((t0 - tol) / period_s) * period_s  # the loop records every period
            if not ends_with_run and not first_tick < t1 - tol:
                yield "tick", name, (f"phase '{name}' [{seconds(t0)}, {seconds(t1)}) s holds no control tick (one "
                                     f"every {seconds(period_s)} s): its indices would be NaN for every sample")
            # the last tick's sample holds for its period, as gimbalsim.indices reads it (a phase ending 1e-7 s
            # past the run was refused here while the indices gave it a value, pass 55)
            # A run whose last tick is the phase's first has not passed its start either (pass 87: a track from
            # 0.2999 s of a 0.3 s run gave every sample NaN)
            if self.duration_s <= first_tick + tol or (not ends_with_run and self.duration_s + period_s < t1 - tol):
                # the track as the profile has it, [t0, inf): its end here is only the run's own (pass 61)
                shown = "inf" if ends_with_run else seconds(t1)
                where = "before" if self.duration_s <= t0 + tol else \
                    "at the first control tick of" if self.duration_s <= first_tick + tol else "inside"
                yield "run", name, (f"the run ends at sim.duration {seconds(self.duration_s)} s, {where} phase "
                                    f"'{name}' [{seconds(t0)}, {shown}) s: its indices would be NaN for every sample")
            end = self.duration_s if ends_with_run else t1
            for ix in self.indices if end > t0 + tol else ():  # a phase the run misses is said above
                need = (ix.window or 0.0) + (ix.separation or 0.0)
                if need > end - t0 + tol:  # each term printed as given: their sum rounds (0.1 + 0.01)
                    given = f"the window {seconds(ix.window)} s" + \
                        (f" plus separation {seconds(ix.separation)} s" if ix.separation else "")
                    yield "index", ix.name, (f"{given} is longer than phase '{name}' [{seconds(t0)}, "
                                             f"{seconds(end)}) s of this run")

    def _whole_periods(self, spec, where, value, node):
        if not value > 0 or _gimbalsim._whole_multiple_problem(value, self.period_s, "control.period"):
            spec.refuse(where, f"{value!r} s is not a positive whole number of control periods "
                        f"({seconds(self.period_s)} s)", node)
        return value

    def _within_run(self, spec, where, node):
        """A window or separation no longer than the run: 1e300 s read as "not
        whole control periods" (the ratio overflows), .inf as "not finite"."""
        v = node.value
        if isinstance(v, (int, float)) and not isinstance(v, bool) and v > self.duration_s:
            spec.refuse(where, f"{v!r} s is longer than the run (sim.duration {seconds(self.duration_s)} s): "
                        "no phase can hold it", node)
        return spec.number(where, node)

    def _indices(self, spec, root):
        if "indices" not in root:
            return [IndexSpec("ape"), IndexSpec("knowledge")]
        body = spec.mapping("indices", root["indices"])
        out = []
        for name, node in body.items():
            where = f"indices.{name}"
            if name not in INDICES:
                spec.refuse(where, f"unknown index (expected one of {', '.join(INDICES)})", node)
            opts = spec.mapping(where, node) if node.value is not None else {}
            allowed = INDEX_KEYS[name] | {"level", "confidence", "requirement"}
            for k, n in opts.items():
                if k not in allowed:
                    spec.refuse(f"{where}.{k}", f"unknown key (expected one of {', '.join(sorted(allowed))})", n)
            for k in sorted(INDEX_KEYS[name]):
                if k not in opts:
                    spec.refuse(f"{where}.{k}", "missing (in s)", node)
            kw = {k: self._whole_periods(spec, f"{where}.{k}", self._within_run(spec, f"{where}.{k}", opts[k]),
                                         opts[k]) for k in INDEX_KEYS[name]}
            # One tick's deviation from its own mean is 0 by construction: a figure (and a PASS) from no question.
            # PDE's one-tick windows are kept: two samples a separation apart differ by the drift asked about.
            if name == "rpe" and round(kw["window"] / self.period_s) < 2:
                spec.refuse(f"{where}.window", f"{kw['window']!r} s holds one control tick ({seconds(self.period_s)} "
                            "s): its deviation from its own mean is 0 by construction; give at least two control "
                            "periods", opts["window"])
            for k in ("level", "confidence"):
                if k in opts:
                    kw[k] = spec.number(f"{where}.{k}", opts[k], 0.5, 1 - 1e-9)  # indices._check_question
            if "requirement" in opts:
                # 0 (or -0) rad: every unit fails; above pi every unit meets it: a verdict from no question
                kw["requirement"] = spec.number(f"{where}.requirement", opts["requirement"], 0.0, MAX_REQUIREMENT_RAD,
                                                above=True)
            out.append(IndexSpec(name, **kw))
        if not out:
            spec.refuse("indices", "no index named: give one or more of " + ", ".join(INDICES), root["indices"])
        return out

    def metrics(self):
        """Per-sample columns: index_phase [rad], in phase order."""
        return [f"{ix.name}_{p}" for p, _ in self.phases for ix in self.indices]

    def plain(self):
        return {"controller": str(self.controller_path or "default"), "values": self.values,
                "phases": [[p, w] for p, w in self.phases], "indices": {ix.name: ix.plain() for ix in self.indices}}
