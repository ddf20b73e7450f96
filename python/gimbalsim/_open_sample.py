"""One open-loop sample (runs on a worker): the scene's constant torques, and
the pointing error against the ideal-joint twin with the same parameters."""
import math

import numpy as np

import gimbalsim
from ._closed_sample import load_sample


def _bore_angles(a, b):
    """Angle [rad] between the boresight rows of two runs, row by row."""
    i = [gimbalsim.COLUMNS.index(c) for c in ("bore_x", "bore_y", "bore_z")]
    n = min(len(a), len(b))
    u, v = a[:n][:, i], b[:n][:, i]
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=1), np.einsum("ij,ij->i", u, v))


def _stop_name(summary):
    """A stopped run's status in a row: the limit key, or its step status;
    a run whose steps all succeeded stopped on a non-finite output row
    (simulate.cpp), never "ok"."""
    stop = summary["stop"]
    if stop["key"]:
        return stop["key"]
    return "non-finite_output" if stop["step_status"] == "ok" else stop["step_status"].replace(" ", "_")


def run_sample(base, overrides, ideal_cache, series=False):
    """Sample's metrics: status and METRICS (dict), and `applied`: the
    dispersed keys as the loaded scene holds them (_provenance.applied). The ideal-joint run with
    the same parameters is the pointing reference (cached: it does not depend
    on the joint's parameters). A twin that stopped before the run's last row
    gives no pointing error (NaN) and the status `ideal:<its limit key>`
    (`<the run's key>|ideal:<key>` when the run stopped too). With series, the
    run too, under "run"."""
    scene, _, loaded = load_sample(base, None, overrides)
    if scene is None:
        return {"status": loaded["status"]}  # an open loop's row has no reason column
    applied = loaded["applied"]  # as loaded, not as drawn
    run = gimbalsim.simulate(scene)
    ideal = scene.replace({"structure.joint1": "ideal", "structure.joint2": "ideal"})
    key = tuple(sorted(ideal.values().items()))
    if key not in ideal_cache:
        twin = gimbalsim.simulate(ideal)
        ideal_cache[key] = (twin.rows, None if twin.ok else _stop_name(twin.summary))
    twin_rows, twin_stop = ideal_cache[key]
    status = "ok" if run.ok else _stop_name(run.summary)
    err = _bore_angles(run.rows, twin_rows)
    if twin_stop is not None and len(twin_rows) < len(run.rows):
        # the reference stopped before the run's last row: no pointing error over
        # the run (not one over the rows the twin reached); the status says why
        err = np.array([])
        status = f"ideal:{twin_stop}" if run.ok else f"{status}|ideal:{twin_stop}"
    s = run.summary
    return {"status": status, "applied": applied, **({"run": run} if series else {}),
            "pointing_error_max": float(err.max()) if len(err) else math.nan,
            "pointing_error_final": float(err[-1]) if len(err) else math.nan,
            "peak_contact_force": s["peak_contact_force_N"],
            "peak_joint2_force": s["peak_joint2_force_N"],
            "impacts": s["impacts"],
            "continuous_contact_from": s["continuous_contact_from_s"],
            **joint_metrics(s)}


def joint_metrics(summary):
    """impacts_joint1/2 and max_tilt1/2 from a run summary's clearance_joints."""
    out = {}
    for j in (1, 2):
        o = summary.get("clearance_joints", {}).get(f"joint{j}", {})
        out[f"impacts_joint{j}"] = o.get("impacts", 0)
        out[f"max_tilt{j}"] = o.get("max_tilt_rad", 0.0)
    return out
