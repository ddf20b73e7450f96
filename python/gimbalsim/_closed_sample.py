"""One closed-loop sample (runs on a worker): the dispersed scene and
controller closed in the firmware model, and the pointing indices of each
phase computed from the run's own error vectors with indices.py."""
import math

import numpy as np

import gimbalsim
from . import _provenance, indices as ix
from ._closed_spec import CONTROLLER_PREFIX, plant_overrides, profile_phases

TRUE_ERROR = ("los_error_x", "los_error_y", "los_error_z")
ESTIMATED_ERROR = ("los_error_est_x", "los_error_est_y", "los_error_est_z")


def split_overrides(overrides):
    """A sample's values as (scene overrides, controller overrides)."""
    scene = {k: v for k, v in overrides.items() if not k.startswith(CONTROLLER_PREFIX)}
    ctrl = {k[len(CONTROLLER_PREFIX):]: v for k, v in overrides.items() if k.startswith(CONTROLLER_PREFIX)}
    return scene, ctrl


SEGMENT_CODES = {"slew": 1, "hold": 2, "track": 3}  # pointing::Segment, the ticks' segment column


def phase_windows(closed, controller, columns):
    """{phase: (t0, t1)} [s] for this sample. A profile phase runs from its
    first tick to the next phase's first tick as the firmware's own profile
    (TargetProfile::at, the ticks' segment column) placed them; a phase the
    run did not reach or finish ends where the profile's keys put it."""
    nominal = profile_phases(controller, closed.duration_s)
    t, seg = np.asarray(columns["t"]), np.asarray(columns["segment"])
    out = {}
    for name, window in closed.phases:
        if window is not None:
            out[name] = window
            continue
        code = SEGMENT_CODES[name]
        mine, later = np.flatnonzero(seg == code), np.flatnonzero(seg > code)
        if not len(mine):
            out[name] = nominal[name]
            continue
        t1 = float(t[later[0]]) if len(later) else nominal[name][1]
        out[name] = (float(t[mine[0]]), t1)
    return out


def sample_indices(closed, columns, windows):
    """{index_phase: IndexValue} over the run's ticks."""
    t = np.asarray(columns["t"])
    e_true = np.column_stack([columns[c] for c in TRUE_ERROR])
    e_est = np.column_stack([columns[c] for c in ESTIMATED_ERROR])
    out = {}
    for phase, (t0, t1) in windows.items():
        for spec in closed.indices:
            key = f"{spec.name}_{phase}"
            if len(t) < 2:
                out[key] = ix.IndexValue(math.nan, "the run stopped before its second tick")
            elif spec.name == "ape":
                out[key] = ix.ape(t, e_true, t0, t1)
            elif spec.name == "rpe":
                out[key] = ix.rpe(t, e_true, t0, t1, spec.window)
            elif spec.name == "pde":
                out[key] = ix.pde(t, e_true, t0, t1, spec.window, spec.separation)
            else:
                out[key] = ix.knowledge(t, e_est, e_true, t0, t1)
    return out


def load_sample(base, closed, overrides):
    """(scene, controller, {"applied": ...}) of a sample: the base scene with
    its values and, in closed loop (closed: the spec's ClosedLoopSpec; None in
    open loop), its controller, and what they applied (_provenance.applied, as
    loaded, not as drawn); or (None, None, {"status": "refused:<key>",
    "reason": why}). What a worker runs, and what a resume checks a journal
    row's applied_ columns against."""
    scene_ov, ctrl_ov = split_overrides(overrides)
    try:
        scene = base.replace(scene_ov if closed is None else plant_overrides(scene_ov))
    except gimbalsim.SceneError as e:
        return None, None, {"status": f"refused:{e.key or 'scene'}", "reason": str(e).replace(",", ";")}
    if closed is None:
        return scene, None, {"applied": _provenance.applied(scene.values(), overrides)}
    try:
        ctrl = gimbalsim.Controller(closed.controller_path, {**closed.set, **ctrl_ov})
    except gimbalsim.SceneError as e:
        return None, None, {"status": f"refused:controller.{e.key or ''}", "reason": str(e).replace(",", ";")}
    # A period the plant cannot tick (no whole number of sim.step) runs nothing: refused here, where a
    # resume checks a refused row, and not recorded as a run that stopped at its first tick.
    why = gimbalsim._gimbalsim._whole_multiple_problem(ctrl.period, scene.step, "the scene's step (sim.step)")
    if why:
        return None, None, {"status": "refused:controller.control.period",
                            "reason": f"control.period: {ctrl.period!r} s {why}".replace(",", ";")}
    loaded = {**scene.values(), **{CONTROLLER_PREFIX + k: t for k, t in ctrl._values_text().items()}}
    return scene, ctrl, {"applied": _provenance.applied(loaded, overrides)}


def run_closed_sample(base, closed, overrides, series=False):
    """A closed-loop sample's status, reason and indices (dict); with series,
    also the run itself under "run" (its ticks, for a replay)."""
    scene, ctrl, loaded = load_sample(base, closed, overrides)
    if scene is None:
        return loaded
    applied = loaded["applied"]
    run = gimbalsim.closed_loop(scene, ctrl, closed.duration_s, _study=True)  # its keys judged with the spec
    s = run.summary
    # a stop's key is never empty when the run is not ok (controller_bindings.cpp resultDict): a limit's or
    # non_finite, the statuses a resume accepts (_journal.CLOSED_STOPS)
    status = "ok" if s["ok"] else s["stop_key"]
    values = sample_indices(closed, run.columns, phase_windows(closed, ctrl, run.columns))
    reasons = [f"{k}: {v.reason}" for k, v in values.items() if not v.ok]
    if not s["ok"]:
        reasons.insert(0, s["error"])
    # no commas in the text: the CSV stays one the project's readers (numpy) split right
    result = {"status": status, "reason": " | ".join(reasons).replace(",", ";"), "t_end": float(s["t_end_s"]),
              "applied": applied, "max_tilt1": float(s["max_tilt_rad"][0]), "max_tilt2": float(s["max_tilt_rad"][1])}
    result.update({k: v.value for k, v in values.items()})
    if series:
        result["run"] = run
    return result
